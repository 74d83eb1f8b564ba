#include "hovi/parallel/parallel_for.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <system_error>
#include <thread>

#include "hovi/errors.hpp"

namespace hovi {

int thread_count(int requested) {
  if (requested > 0) return requested;
  if (requested < 0) throw InputError("threads must be at least 1 (or 0/None: all cores), got " + std::to_string(requested));
  if (const char* env = std::getenv("HOVI_NUM_THREADS"); env && *env) {
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (*end != '\0' || n < 1 || n > 1 << 16)
      throw InputError(std::string("HOVI_NUM_THREADS must be a positive integer, got '") + env + "'");
    return static_cast<int>(n);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

std::vector<std::string> parallel_for(int count, int threads, const std::function<void(int, int)>& body) {
  if (threads < 1) throw InputError("threads must be at least 1, got " + std::to_string(threads));
  std::vector<std::string> errors(std::max(count, 0));
  std::atomic<int> next{0};
  auto work = [&](int thread) {
    for (int item = next++; item < count; item = next++) {
      try {
        body(item, thread);
      } catch (const std::exception& e) {
        errors[item] = e.what();
        if (errors[item].empty()) errors[item] = "unknown error";
      } catch (...) {
        errors[item] = "unknown error";
      }
    }
  };
  const int used = std::min(threads, std::max(count, 1));
  std::vector<std::thread> pool;
  pool.reserve(used - 1);
  for (int t = 1; t < used; ++t) {
    try {
      pool.emplace_back(work, t);
    } catch (const std::system_error&) {  // no more threads to be had: those running take every item
      break;
    }
  }
  work(0);
  for (auto& t : pool) t.join();
  return errors;
}

}  // namespace hovi
