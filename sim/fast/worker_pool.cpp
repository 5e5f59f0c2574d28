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

WorkerPool::WorkerPool(int threads)
    : done_(std::make_unique<Flag[]>(static_cast<std::size_t>(std::max(1, threads)))) {
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
  const std::uint64_t generation = generation_.fetch_add(1, std::memory_order_release) + 1;
  generation_.notify_all();
  job(0);
  for (std::size_t w = 0; w < workers_.size(); ++w) {
    for (int spin = 0; done_[w].generation.load(std::memory_order_acquire) != generation; ++spin) {
      if (spin < kSpinsBeforeSleep) {
        spin_pause();
      } else {
        std::this_thread::yield();
      }
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
    done_[index - 1].generation.store(now, std::memory_order_release);
  }
}

int automatic_threads(int edges) {
  const int hardware = std::max(1u, std::thread::hardware_concurrency());
  return std::clamp(1 + edges / kEdgesPerExtraThread, 1, hardware);
}

}  // namespace rheo::fast
