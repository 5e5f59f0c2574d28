// A fixed set of threads that run one job together and return: the fast CPU path splits
// each step's edge pass and particle pass across them (fast_simulator.hpp). A step takes
// tens of microseconds, so the workers spin briefly for the next job before they sleep;
// waking a sleeping thread costs more than a small model's whole step.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

namespace rheo::fast {

// The most threads the fast path runs (one particle sweep adds at most this many threads'
// force sums).
constexpr int kMaxThreads = 64;

class WorkerPool {
 public:
  // `threads` >= 1 threads in all: the caller's own and threads - 1 workers.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }

  // Runs job(t) for every t in [0, size()), t = 0 on the calling thread, and returns when
  // all have finished. The job must not throw (it records failures for the caller).
  void run(const std::function<void(int)>& job);

 private:
  void work(int index);

  // A counter on a cache line of its own, so that a thread's flag and the next job's
  // announcement each cost one transfer between cores.
  struct alignas(64) Flag {
    std::atomic<std::uint64_t> generation{0};
  };
  std::vector<std::thread> workers_;
  // The job and its number (written by the caller, read by the workers), and per worker the
  // number of the last job it finished.
  alignas(64) std::atomic<std::uint64_t> generation_{0};
  const std::function<void(int)>* job_ = nullptr;
  std::atomic<bool> stop_{false};
  std::unique_ptr<Flag[]> done_;
};

// A pause for a thread spinning on a flag another core will set.
inline void spin_pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

// The thread count the fast path uses when asked for 0 ("auto"): one thread for small
// models (a step of a few microseconds does not pay for waking a second thread), else
// every hardware thread.
int automatic_threads(int edges);

}  // namespace rheo::fast
