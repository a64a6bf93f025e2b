#include <gtest/gtest.h>

#include <sched.h>
#include <stdlib.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

#include "vocal/core/worker_pool.h"

namespace {

// Every block once, with the range forBlocks promises, for pools of each size and loops of each shape.
TEST(WorkerPool, EachBlockRunsOnceWithItsRange) {
  for (int threads : {1, 2, 4, 7}) {
    vocal::WorkerPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    EXPECT_EQ(pool.threadSource(), "set");
    for (int count : {0, 1, 5, 64, 1001}) {
      for (int block_size : {1, 3, 64}) {
        const int blocks = vocal::WorkerPool::blockCount(count, block_size);
        std::vector<std::atomic<int>> runs(blocks);
        std::vector<std::atomic<int>> items(count);
        pool.forBlocks(count, block_size, [&](int block, int begin, int end) {
          ++runs[block];
          EXPECT_EQ(begin, block * block_size);
          EXPECT_EQ(end, std::min(count, begin + block_size));
          for (int i = begin; i < end; ++i) ++items[i];
        });
        for (int b = 0; b < blocks; ++b) ASSERT_EQ(runs[b].load(), 1) << threads << " threads, block " << b;
        for (int i = 0; i < count; ++i) ASSERT_EQ(items[i].load(), 1) << threads << " threads, item " << i;
      }
    }
  }
}

// A pool of more than one thread does share the work (each loop waits until every thread has taken a
// block, which fails if any thread never runs one), also after its workers have gone to sleep.
TEST(WorkerPool, EveryThreadTakesBlocksAwakeAndAfterSleeping) {
  vocal::WorkerPool pool(3);
  for (int round = 0; round < 2; ++round) {
    std::atomic<int> arrived{0};
    std::mutex mutex;
    std::set<std::thread::id> seen;
    pool.forBlocks(3, 1, [&](int, int, int) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        seen.insert(std::this_thread::get_id());
      }
      ++arrived;
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (arrived.load() < 3 && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    });
    EXPECT_EQ(arrived.load(), 3);
    EXPECT_EQ(seen.size(), 3u) << "round " << round;
    // Long past the workers' spin: they sleep now, and must be woken by the next loop.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// A loop called from a body, or from a second thread while one runs, runs on its own caller: each
// block still once, nothing deadlocks.
TEST(WorkerPool, CallsWhileALoopRunsRunOnTheirCaller) {
  vocal::WorkerPool pool(2);
  std::atomic<int> inner_items{0};
  pool.forBlocks(4, 1, [&](int, int, int) {
    pool.forBlocks(10, 3, [&](int, int begin, int end) { inner_items += end - begin; });
  });
  EXPECT_EQ(inner_items.load(), 40);

  std::atomic<long> total{0};
  auto loops = [&] {
    for (int k = 0; k < 200; ++k) pool.forBlocks(100, 7, [&](int, int begin, int end) { total += end - begin; });
  };
  std::thread other(loops);
  loops();
  other.join();
  EXPECT_EQ(total.load(), 2 * 200 * 100);
}

// A worker held up mid-block (as one the OS takes off its core for a slice) makes the caller run the
// next loops alone, each block still once; and it tries the others again after a while.
TEST(WorkerPool, AWorkerHeldUpMidBlockMakesTheCallerGoOnAlone) {
  vocal::WorkerPool pool(2);
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool> other_started{false};
  pool.forBlocks(2, 1, [&](int, int, int) {
    if (std::this_thread::get_id() == caller) {
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (!other_started.load() && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    } else {
      other_started = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  ASSERT_TRUE(other_started.load());
  EXPECT_EQ(pool.loops(), 1);
  EXPECT_EQ(pool.loopsAlone(), 0);
  std::atomic<int> items{0};
  for (int k = 0; k < 300; ++k) pool.forBlocks(50, 5, [&](int, int begin, int end) { items += end - begin; });
  EXPECT_EQ(items.load(), 300 * 50);
  EXPECT_GE(pool.loopsAlone(), 64);  // at least the first stretch alone
  // and the others tried again after it (even were every try to stall: after 64, then 128 alone)
  EXPECT_GE(pool.loops() - pool.loopsAlone(), 3);
}

// Blocks are fixed by the loop: per-block sums added in block order are the same bits for any pool.
TEST(WorkerPool, PerBlockReductionIsTheSameForEveryThreadCount) {
  std::vector<double> values(10007);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 1.0 / (1.0 + i * 0.37) * ((i % 3) ? 1.0 : -1e3);
  auto sum = [&](int threads) {
    vocal::WorkerPool pool(threads);
    std::vector<double> partial(vocal::WorkerPool::blockCount(static_cast<int>(values.size()), 64));
    pool.forBlocks(static_cast<int>(values.size()), 64, [&](int block, int begin, int end) {
      double s = 0.0;
      for (int i = begin; i < end; ++i) s += values[i];
      partial[block] = s;
    });
    double total = 0.0;
    for (double p : partial) total += p;
    return total;
  };
  const double one = sum(1);
  EXPECT_EQ(sum(2), one);
  EXPECT_EQ(sum(4), one);
}

// threads 0: OMP_NUM_THREADS where set to a positive number, else the CPUs this process may run on.
TEST(WorkerPool, ZeroThreadsMeansOmpNumThreadsElseTheAllowedCores) {
  const char* saved = std::getenv("OMP_NUM_THREADS");
  const std::string restore = saved ? saved : "";
  setenv("OMP_NUM_THREADS", "3", 1);
  {
    vocal::WorkerPool pool(0);
    EXPECT_EQ(pool.threads(), 3);
    EXPECT_EQ(pool.threadSource(), "OMP_NUM_THREADS");
  }
  setenv("OMP_NUM_THREADS", "not a number", 1);
  cpu_set_t set;
  CPU_ZERO(&set);
  ASSERT_EQ(sched_getaffinity(0, sizeof(set), &set), 0);
  {
    vocal::WorkerPool pool(0);
    EXPECT_EQ(pool.threads(), CPU_COUNT(&set));
    EXPECT_EQ(pool.threadSource(), "the cores");
  }
  unsetenv("OMP_NUM_THREADS");
  std::string source;
  EXPECT_EQ(vocal::defaultThreadCount(&source), CPU_COUNT(&set));
  EXPECT_EQ(source, "the cores");
  if (saved) setenv("OMP_NUM_THREADS", restore.c_str(), 1);
}

}  // namespace
