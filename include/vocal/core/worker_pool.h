#pragma once
// A small pool of threads for the odometry's data-parallel loops, made for a robot's shared CPU.
// OpenMP's threads spin at every barrier (libgomp's default wait policy, fixed when the library loads):
// with another process on the other core the spinning thread keeps its core from the thread that has
// the work (freiburg1_desk on a 2-vCPU VM with one busy process beside it: 26 fps fell to 7). Here idle
// workers spin only briefly (a frame's loops follow each
// other within microseconds), then sleep; the blocks of a loop are handed out one at a time, so a thread
// the OS does not schedule takes fewer of them instead of holding up the others; and where a thread is
// kept off its core mid-block (a scheduler slice, milliseconds) the caller runs the next loops alone
// for a while instead of waiting at every one. Blocks are fixed by the loop, not by the thread count,
// so a reduction kept per block and summed in block order gives the same bits with any number of
// threads, and whichever threads ran it.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace vocal {

// The threads `threads: 0` means: OMP_NUM_THREADS where it is set to a positive number (what robot
// integrators already use to hold a process to a budget), else the cores this process may run on
// (its CPU affinity: taskset, a cgroup's cpuset). `source`, when given, says which.
int defaultThreadCount(std::string* source = nullptr);

class WorkerPool {
 public:
  // `threads` in all, the calling thread included (1: everything runs on the caller, no thread is
  // started); 0: defaultThreadCount().
  explicit WorkerPool(int threads = 0);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  // How `threads` was chosen: "set", "OMP_NUM_THREADS" or "the cores".
  const std::string& threadSource() const { return thread_source_; }

  // Calls body(block, begin, end) for the blocks [0, count) splits into (`block_size` items each, the
  // last one shorter), each exactly once, on the pool's threads and the caller's; returns when all are
  // done. A call made while another is running (from a body, or from another thread) runs on its
  // caller alone. An exception from body ends the program (as one leaving an OpenMP loop does): the
  // loops here do not throw.
  template <class Body>
  void forBlocks(int count, int block_size, Body&& body) {
    if (count <= 0) return;
    if (block_size < 1) block_size = 1;
    struct Context {
      std::remove_reference_t<Body>* body;
      int count, block_size;
    } context{&body, count, block_size};
    run(blockCount(count, block_size), [](void* c, int block) noexcept {
      const Context& ctx = *static_cast<Context*>(c);
      const int begin = block * ctx.block_size;
      const int end = begin + ctx.block_size < ctx.count ? begin + ctx.block_size : ctx.count;
      (*ctx.body)(block, begin, end);
    }, &context);
  }

  // body(i) for every i in [0, count), handed out `block_size` at a time as forBlocks does: a loop
  // whose iterations need nothing of their block (a row of an image each).
  template <class Body>
  void forEach(int count, int block_size, Body&& body) {
    forBlocks(count, block_size, [&body](int, int begin, int end) {
      for (int i = begin; i < end; ++i) body(i);
    });
  }

  // A pool of one, shared: for callers given no pool (its loops run on whoever calls; safe from any thread).
  static WorkerPool& callerOnly();

  // Loops run on more than one block since the pool was made, and how many of them the caller ran
  // alone because the OS kept another thread of the pool off its core (the CPU is shared).
  long loops() const { return loops_; }
  long loopsAlone() const { return loops_alone_; }

  // The number of blocks forBlocks(count, block_size, ...) calls body for.
  static int blockCount(int count, int block_size) { return count <= 0 ? 0 : (count + block_size - 1) / block_size; }

 private:
  using BlockFunction = void (*)(void* context, int block) noexcept;
  void run(int blocks, BlockFunction call, void* context);
  void noteStragglers(std::chrono::steady_clock::duration own, std::chrono::steady_clock::duration waited);
  void workerLoop();
  // Claims and runs blocks of the job of `generation` until none is left or another job is up.
  void runBlocks(std::uint32_t generation, int blocks, BlockFunction call, void* context);

  std::string thread_source_;
  std::vector<std::thread> workers_;

  // The job: written under mutex_ with the generation it belongs to.
  std::mutex mutex_;
  std::condition_variable work_ready_, work_done_;
  std::atomic<std::uint32_t> generation_{0};
  BlockFunction call_ = nullptr;
  void* context_ = nullptr;
  int blocks_ = 0;
  // (generation << 32) | next block: a block is claimed only while its job is the current one, so a
  // worker that wakes late can never take a block of a newer job for the older one's body.
  std::atomic<std::uint64_t> next_{0};
  std::atomic<int> done_{0};
  std::atomic<int> sleeping_workers_{0};
  std::atomic<bool> caller_sleeping_{false};
  bool stop_ = false;
  std::atomic<bool> busy_{false};  // a call is running

  // Running alone while the cores are shared (noteStragglers; only the caller holding busy_ touches these).
  static constexpr int kLeastLoopsAlone = 64, kMostLoopsAlone = 4096;  // a frame has about 60 loops
  int alone_left_ = 0, alone_stretch_ = kLeastLoopsAlone, loops_since_stall_ = 0;
  long loops_ = 0, loops_alone_ = 0;
};

}  // namespace vocal
