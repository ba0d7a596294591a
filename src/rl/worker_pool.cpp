#include "roar/rl/worker_pool.h"

#include <stdexcept>

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
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) return;
      seen = generation_;
    }
    runShare(share);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (--pending_ == 0) finished_.notify_one();
    }
  }
}

void WorkerPool::run(std::size_t count, const Job& job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    count_ = count;
    job_ = &job;
    error_ = nullptr;
    pending_ = static_cast<int>(workers_.size());
    ++generation_;
  }
  start_.notify_all();
  runShare(0);
  std::unique_lock<std::mutex> lock(mutex_);
  finished_.wait(lock, [&] { return pending_ == 0; });
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

}  // namespace roar::rl
