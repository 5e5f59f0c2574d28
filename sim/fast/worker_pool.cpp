#include "sim/fast/worker_pool.hpp"

#include <algorithm>

namespace rheo::fast {
namespace {

// Spins before a worker sleeps on the generation counter: about 50-100 us on current
// x86 cores, longer than the gap between the two passes of a step.
constexpr int kSpinsBeforeSleep = 20000;

// Edges from which a second thread pays: a 26-neighbour lattice of about 10x10x10.
constexpr int kEdgesPerExtraThread = 8000;

}  // namespace

WorkerPool::WorkerPool(int threads) {
  for (int t = 1; t < std::max(1, threads); ++t) workers_.emplace_back([this, t] { work(t); });
}

WorkerPool::~WorkerPool() {
  stop_.store(true);
  generation_.fetch_add(1);
  generation_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void WorkerPool::run(const std::function<void(int)>& job) {
  if (workers_.empty()) {
    job(0);
    return;
  }
  job_ = &job;
  pending_.store(static_cast<int>(workers_.size()));
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  job(0);
  for (int spin = 0; pending_.load(std::memory_order_acquire) != 0; ++spin) {
    if (spin < kSpinsBeforeSleep) {
      spin_pause();
    } else {
      std::this_thread::yield();
    }
  }
  job_ = nullptr;
}

void WorkerPool::work(int index) {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t now = generation_.load(std::memory_order_acquire);
    for (int spin = 0; now == seen && spin < kSpinsBeforeSleep; ++spin) {
      spin_pause();
      now = generation_.load(std::memory_order_acquire);
    }
    if (now == seen) {
      generation_.wait(seen, std::memory_order_acquire);
      now = generation_.load(std::memory_order_acquire);
    }
    seen = now;
    if (stop_.load()) return;
    (*job_)(index);
    pending_.fetch_sub(1, std::memory_order_acq_rel);
  }
}

int automatic_threads(int edges) {
  const int hardware = std::max(1u, std::thread::hardware_concurrency());
  return std::clamp(1 + edges / kEdgesPerExtraThread, 1, hardware);
}

}  // namespace rheo::fast
