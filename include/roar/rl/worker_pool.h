#pragma once
// A fixed set of threads that run one job over an index range, split in even shares, and return when
// every share is done. The caller's thread takes the first share. For stepping environments in parallel
// tens of thousands of times a second: the threads spin briefly for the next job before they sleep, because
// waking a sleeping thread costs about as much as a step (tens of microseconds on a virtual machine).
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace roar::rl {

class WorkerPool {
 public:
  explicit WorkerPool(int threads);  // threads >= 1, the caller's included
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  // Calls job(i, thread) for every i in [0, count), thread in [0, threads()) being the one that runs it
  // (for per-thread state); rethrows the first exception a job threw.
  using Job = std::function<void(std::size_t index, int thread)>;
  void run(std::size_t count, const Job& job);

 private:
  void work(int share);
  void runShare(int share);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> pending_{0};
  std::atomic<bool> stopping_{false};
  std::size_t count_ = 0;
  const Job* job_ = nullptr;
  std::exception_ptr error_;  // guarded by mutex_
};

}  // namespace roar::rl
