#include "vocal/core/worker_pool.h"

#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace vocal {

namespace {
// How long an idle thread polls before it sleeps: about the gap between two loops of one frame (a 6x6
// solve, a few microseconds), far shorter than the gap between frames, so that a shared core loses at
// most this much to the wait. 0, 5, 20 and 50 us gave the same idle rate within run-to-run noise
// (26-28 fps on freiburg1_desk, 2-vCPU Xeon VM): waking a sleeping thread costs little here.
constexpr auto kSpinTime = std::chrono::microseconds(20);
constexpr std::uint64_t kBlockMask = 0xffffffffu;
// A wait for the others this much past twice the caller's own share is a stall (noteStragglers).
constexpr auto kStallSlack = std::chrono::microseconds(200);

void pause() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

// Polls `ready` for up to kSpinTime; true as soon as it holds.
template <class Ready>
bool spinUntil(Ready ready) {
  const auto until = std::chrono::steady_clock::now() + kSpinTime;
  for (;;) {
    for (int i = 0; i < 64; ++i) {
      if (ready()) return true;
      pause();
    }
    if (std::chrono::steady_clock::now() >= until) return ready();
  }
}
}  // namespace

int defaultThreadCount(std::string* source) {
  if (const char* omp = std::getenv("OMP_NUM_THREADS")) {
    // "4" or a nesting list "4,2": the outermost level's.
    const int n = std::atoi(omp);
    if (n > 0) {
      if (source) *source = "OMP_NUM_THREADS";
      return n;
    }
  }
  if (source) *source = "the cores";
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  const unsigned cores = std::thread::hardware_concurrency();
  return cores > 0 ? static_cast<int>(cores) : 1;
}

WorkerPool::WorkerPool(int threads) : thread_source_("set") {
  if (threads <= 0) threads = defaultThreadCount(&thread_source_);
  workers_.reserve(threads - 1);
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { workerLoop(); });
}

WorkerPool& WorkerPool::callerOnly() {
  // No worker: run() never touches the pool's state, so any number of threads may share it.
  static WorkerPool pool(1);
  return pool;
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    generation_.fetch_add(1);
  }
  work_ready_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void WorkerPool::run(int blocks, BlockFunction call, void* context) {
  const auto alone = [&] {
    for (int block = 0; block < blocks; ++block) call(context, block);
  };
  if (blocks <= 0) return;
  if (workers_.empty() || blocks == 1 || busy_.exchange(true)) return alone();
  struct Idle {
    std::atomic<bool>* busy;
    ~Idle() { busy->store(false); }
  } idle{&busy_};
  ++loops_;
  if (alone_left_ > 0) {
    --alone_left_;
    ++loops_alone_;
    return alone();
  }
  std::uint32_t generation;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation = generation_.load() + 1;
    call_ = call;
    context_ = context;
    blocks_ = blocks;
    done_.store(0);
    next_.store(static_cast<std::uint64_t>(generation) << 32);
    generation_.store(generation);
  }
  if (sleeping_workers_.load() > 0) work_ready_.notify_all();
  const auto started = std::chrono::steady_clock::now();
  runBlocks(generation, blocks, call, context);
  const auto own_done = std::chrono::steady_clock::now();
  if (!spinUntil([&] { return done_.load() == blocks; })) {
    // A block is still running on a thread the OS has not scheduled: sleep, so that this core can take it.
    std::unique_lock<std::mutex> lock(mutex_);
    caller_sleeping_.store(true);
    work_done_.wait(lock, [&] { return done_.load() == blocks; });
    caller_sleeping_.store(false);
  }
  noteStragglers(own_done - started, std::chrono::steady_clock::now() - own_done);
}

void WorkerPool::noteStragglers(std::chrono::steady_clock::duration own, std::chrono::steady_clock::duration waited) {
  // Waiting for the others longer than twice the caller's own share (and a scheduler tick's worth) is a
  // worker that the OS took off its core mid-block: another process wants that core. Every loop then
  // waits for a scheduler slice, slower than running alone, so the caller runs the next loops alone,
  // twice as many after each stall in a row, and tries the others again after them.
  if (waited > 2 * own + kStallSlack) {
    loops_since_stall_ = 0;
    alone_left_ = alone_stretch_;
    alone_stretch_ = std::min(alone_stretch_ * 2, kMostLoopsAlone);
  } else if (++loops_since_stall_ >= kLeastLoopsAlone) {
    loops_since_stall_ = 0;
    alone_stretch_ = kLeastLoopsAlone;
  }
}

void WorkerPool::runBlocks(std::uint32_t generation, int blocks, BlockFunction call, void* context) {
  for (;;) {
    std::uint64_t next = next_.load();
    do {
      if ((next >> 32) != generation || (next & kBlockMask) >= static_cast<std::uint64_t>(blocks)) return;
    } while (!next_.compare_exchange_weak(next, next + 1));
    call(context, static_cast<int>(next & kBlockMask));
    if (done_.fetch_add(1) + 1 == blocks && caller_sleeping_.load()) {
      std::lock_guard<std::mutex> lock(mutex_);
      work_done_.notify_one();
    }
  }
}

void WorkerPool::workerLoop() {
  std::uint32_t seen = 0;
  for (;;) {
    if (!spinUntil([&] { return generation_.load() != seen; })) {
      std::unique_lock<std::mutex> lock(mutex_);
      sleeping_workers_.fetch_add(1);
      work_ready_.wait(lock, [&] { return generation_.load() != seen; });
      sleeping_workers_.fetch_sub(1);
    }
    std::uint32_t generation;
    int blocks;
    BlockFunction call;
    void* context;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
      generation = generation_.load();
      blocks = blocks_;
      call = call_;
      context = context_;
    }
    seen = generation;
    runBlocks(generation, blocks, call, context);
  }
}

}  // namespace vocal
