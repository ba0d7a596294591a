#include "roar/rl/worker_pool.h"

#include <stdexcept>

#include "roar/rl/spin_wait.h"

namespace roar::rl {

WorkerPool::WorkerPool(int threads) {
  if (threads < 1) throw std::invalid_argument("WorkerPool needs at least one thread");
  for (int share = 1; share < threads; ++share) workers_.emplace_back([this, share] { work(share); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  start_.notify_all();
  for (auto& t : workers_) t.join();
}

void WorkerPool::runShare(int share) {
  const std::size_t n = static_cast<std::size_t>(threads());
  const std::size_t begin = count_ * static_cast<std::size_t>(share) / n;
  const std::size_t end = count_ * static_cast<std::size_t>(share + 1) / n;
  try {
    for (std::size_t i = begin; i < end; ++i) (*job_)(i, share);
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::current_exception();
  }
}

void WorkerPool::work(int share) {
  std::uint64_t seen = 0;
  for (;;) {
    spinFor([&] { return generation_.load(std::memory_order_acquire) != seen || stopping_; });
    if (generation_.load(std::memory_order_acquire) == seen) {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stopping_ || generation_.load(std::memory_order_acquire) != seen; });
    }
    if (stopping_) return;
    seen = generation_.load(std::memory_order_acquire);
    runShare(share);
    pending_.fetch_sub(1, std::memory_order_acq_rel);
  }
}

void WorkerPool::run(std::size_t count, const Job& job) {
  count_ = count;
  job_ = &job;
  error_ = nullptr;
  pending_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);
  {
    // Under the lock, so a worker between its last check and its wait cannot miss the notification.
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_acq_rel);
  }
  start_.notify_all();
  runShare(0);
  // The workers' shares take about as long as this thread's: spin, do not sleep.
  for (unsigned spins = 0; pending_.load(std::memory_order_acquire) != 0; ++spins) {
    if (spins < 100000) {
      relax();
    } else {
      std::this_thread::yield();  // a worker was descheduled: let it run
    }
  }
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

}  // namespace roar::rl
