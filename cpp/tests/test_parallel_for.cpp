// parallel_for (parallel_for.hpp): every item runs once, on a thread index below the count, the
// errors stay with their items, and thread_count reads HOVI_NUM_THREADS.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <stdexcept>

#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"

using namespace hovi;

TEST(ParallelFor, RunsEveryItemOnceAndKeepsErrorsPerItem) {
  for (int threads : {1, 2, 7}) {
    std::vector<std::atomic<int>> runs(100);
    std::vector<int> thread_of(100, -1);
    const auto errors = parallel_for(100, threads, [&](int item, int thread) {
      ++runs[item];
      thread_of[item] = thread;
      if (item % 10 == 3) throw std::runtime_error("item " + std::to_string(item));
    });
    ASSERT_EQ(errors.size(), 100u);
    for (int i = 0; i < 100; ++i) {
      EXPECT_EQ(runs[i], 1);
      EXPECT_GE(thread_of[i], 0);
      EXPECT_LT(thread_of[i], threads);
      EXPECT_EQ(errors[i], i % 10 == 3 ? "item " + std::to_string(i) : "");
    }
  }
}

TEST(ParallelFor, OneThreadRunsInOrderOnTheCaller) {
  std::vector<int> order;
  parallel_for(5, 1, [&](int item, int thread) {
    EXPECT_EQ(thread, 0);
    order.push_back(item);
  });
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_TRUE(parallel_for(0, 4, [](int, int) { FAIL(); }).empty());
  EXPECT_THROW(parallel_for(3, 0, [](int, int) {}), InputError);
}

TEST(ParallelFor, ThreadCountFromTheArgumentOrTheEnvironment) {
  EXPECT_EQ(thread_count(3), 3);
  EXPECT_THROW(thread_count(-1), InputError);
  setenv("HOVI_NUM_THREADS", "5", 1);
  EXPECT_EQ(thread_count(0), 5);
  EXPECT_EQ(thread_count(2), 2);
  for (const char* bad : {"0", "-2", "two", "3x"}) {
    setenv("HOVI_NUM_THREADS", bad, 1);
    EXPECT_THROW(thread_count(0), InputError) << bad;
  }
  unsetenv("HOVI_NUM_THREADS");
  EXPECT_GE(thread_count(0), 1);
}
