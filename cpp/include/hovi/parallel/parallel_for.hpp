// Independent items spread over a few C++ threads: the batched calls (batch.hpp) run B rollouts,
// steps or linearisations with one call. Items are handed out one at a time from an atomic
// counter (a long item does not hold up the others) and each writes only its own slot, so the
// results do not depend on the number of threads or on scheduling.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace hovi {

// The number of threads to use: `requested` if positive; 0 means the environment variable
// HOVI_NUM_THREADS if set, else every core (std::thread::hardware_concurrency). Throws
// InputError for a negative request or a HOVI_NUM_THREADS that is not a positive integer.
int thread_count(int requested = 0);

// Calls body(item, thread) for item = 0..count-1 on min(threads, count) threads (the calling
// thread is thread 0; threads = 1 runs everything on it, in order), `thread` in [0, threads) being
// the index of the thread that runs the item, for per-thread workspaces. An exception thrown by
// an item is caught and its message returned in that item's slot (empty: the item finished), so
// one failed item does not stop the others. Throws InputError if threads < 1.
std::vector<std::string> parallel_for(int count, int threads, const std::function<void(int item, int thread)>& body);

}  // namespace hovi
