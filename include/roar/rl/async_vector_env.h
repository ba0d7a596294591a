#pragma once
// EnvPool's asynchronous batching: actions go to chosen environments (send), and recv() returns the first
// batch_size environments to be done, so no thread waits for the slowest and there is no barrier across
// threads. Each thread owns a fixed set of environments (i % threads) and steps only those: whatever it
// needs while stepping is its own. The caller's thread is one of them: it steps its set in recv(), while
// the batch is not complete, and `threads` - 1 workers step the others. An environment whose episode ended resets at
// once (auto-reset, as VectorEnv): its result holds the new episode's first observation and the old one's last
// observation in final_observation. The synchronous step is send to every environment then recv of all of them.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "roar/rl/racing_env.h"

namespace roar::rl {

struct AsyncResult {
  std::size_t env_id = 0;
  StepResult step;                         // after reset(): the first observation, reward 0, not done
  std::optional<Value> final_observation;  // set where an episode ended this step
};

class AsyncVectorEnv {
 public:
  // Every environment must have the same spaces; threads >= 1, the caller's included (1: recv() steps every
  // environment itself).
  AsyncVectorEnv(std::vector<std::unique_ptr<RacingEnv>> envs, int threads);
  ~AsyncVectorEnv();
  AsyncVectorEnv(const AsyncVectorEnv&) = delete;
  AsyncVectorEnv& operator=(const AsyncVectorEnv&) = delete;

  std::size_t size() const { return envs_.size(); }
  const Space& actionSpace() const { return envs_.front()->actionSpace(); }
  const Space& observationSpace() const { return envs_.front()->observationSpace(); }
  // Environments sent an action (or reset) whose result has not been received yet.
  std::size_t inFlight() const;

  // Resets every idle environment (environment i with seed + i); each comes back through recv(). Throws
  // std::logic_error while any environment is in flight.
  void reset(std::uint64_t seed);
  // One action for each listed environment, which must be idle (its last result received) and listed once.
  // Throws std::invalid_argument or SpaceError naming the first bad one; nothing is sent then.
  void send(const std::vector<Value>& actions, const std::vector<std::size_t>& env_ids);
  // The first batch_size results to be ready (waits for them), in the order they were done. Throws
  // std::invalid_argument when fewer than batch_size environments are in flight, and rethrows an
  // exception an environment threw while stepping.
  std::vector<AsyncResult> recv(std::size_t batch_size);

 private:
  struct Job {
    std::size_t env_id = 0;
    Value action;
    std::optional<std::uint64_t> reset_seed;
  };
  struct Inbox {  // one per thread
    std::mutex mutex;
    std::condition_variable ready;
    std::deque<Job> jobs;
    std::atomic<std::size_t> queued{0};  // jobs.size(), read without the lock by the thread spinning for work
  };
  void work(int thread);
  void run(Job job);  // steps (or resets) the job's environment; its result joins the done queue

  std::vector<std::unique_ptr<RacingEnv>> envs_;
  std::vector<std::unique_ptr<Inbox>> inboxes_;
  std::vector<std::thread> threads_;
  std::vector<char> busy_;  // per environment, touched by the caller's thread only
  mutable std::mutex done_mutex_;
  std::condition_variable done_ready_;
  std::deque<AsyncResult> done_;
  std::atomic<std::size_t> done_count_{0};  // done_.size(), read without the lock by recv() spinning
  std::exception_ptr error_;
  std::size_t in_flight_ = 0;
  std::atomic<bool> stopping_{false};
  bool spin_ = false;  // waiting threads spin before they sleep (a core for each of them)
};

}  // namespace roar::rl
