#pragma once
// EnvPool's asynchronous batching: actions go to chosen environments (send), and recv() returns the first
// batch_size environments to be done, so no thread waits for the slowest and there is no barrier across
// threads. Each thread has a set of environments (i % threads) and an inbox for their jobs, and steps them
// first; a thread whose inbox is empty takes a job from another's, so no core idles while work waits (the
// caller's thread, above all, is away in the learner's code between recv() and send()). The caller's thread
// is one of the `threads`: it steps jobs in recv() while the batch is not complete, and `threads` - 1
// workers step the rest. An environment is stepped by one thread at a time; its action and result live in a
// slot of its own, reused step after step, so nothing on the way is allocated by one thread and freed by
// another. An environment whose episode ended resets at once (auto-reset, as VectorEnv): its result holds the
// new episode's first observation and the old one's last observation in final_observation. The synchronous
// step is send to every environment then recv of all of them. The caller's side (send, recv, reset and the
// counts) is for one thread at a time.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
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
  // Results done and waiting for recv(), counted without waiting.
  std::size_t ready() const { return readyFromReceived(); }

  // Resets every idle environment (environment i with seed + i); each comes back through recv(). Throws
  // std::logic_error while any environment is in flight.
  void reset(std::uint64_t seed);
  // One action for each listed environment, which must be idle (its last result received) and listed once.
  // Throws std::invalid_argument or SpaceError naming the first bad one; nothing is sent then.
  void send(const std::vector<Value>& actions, const std::vector<std::size_t>& env_ids);
  // The ids of the first batch_size environments to be done (waits for them), in the order they were
  // done; each one's result is result(id). Throws std::invalid_argument when fewer than batch_size
  // environments are in flight, and rethrows an exception an environment threw while stepping.
  std::vector<std::size_t> recv(std::size_t batch_size);
  // Environment env_id's last result, written in place step after step (no allocation once its storage has
  // grown): valid from the recv() that returned env_id until env_id is sent again.
  const AsyncResult& result(std::size_t env_id) const { return slots_.at(env_id).result; }

  // Results are numbered in the order they are done (0, 1, ... from construction; recv() returns them in
  // that order, batch after batch). A sink is called by the thread that stepped an environment, with its
  // result's number, once the result is in its slot and before recv() can return it: it copies the result
  // where the caller wants it (rows of a batch known from the number) in parallel, on the threads that
  // stepped, instead of one after another in the caller's thread after recv(). Not for a result whose step
  // threw. Set while nothing is in flight; empty: none.
  using ResultSink = std::function<void(std::size_t number, const AsyncResult& result)>;
  void setResultSink(ResultSink sink);
  // The number of the next result recv() returns (every earlier one has been received).
  std::size_t received() const;

 private:
  // Per environment, on cache lines of its own: the action sent and the result, touched by the caller's
  // thread while the environment is idle and by the thread stepping it while it is in flight.
  struct alignas(64) Slot {
    Value action;
    std::optional<std::uint64_t> reset_seed;  // a reset instead of a step
    bool resetting = false;                   // stepped, its episode ended: the auto-reset is still to do
    AsyncResult result;
  };
  struct alignas(64) Inbox {  // one per thread, on cache lines of its own
    std::mutex mutex;
    std::deque<std::size_t> jobs;        // environment ids
    std::deque<std::size_t> resets;      // auto-resets of episodes the caller's thread ended; for workers
    std::atomic<std::size_t> queued{0};  // both sizes, read without the lock by threads looking for work
  };
  void work(int thread);
  // The next job for `thread`: its own inbox's first, else one taken from another inbox; false when every
  // inbox is empty.
  bool takeJob(std::size_t thread, std::size_t* env_id);
  bool anyQueued() const;
  void push(std::size_t env_id);  // to the inbox of the environment's owner; wakes a sleeping thread
  void pushTo(Inbox& inbox, std::size_t env_id, bool reset);
  // Steps (or resets) the environment into its slot on `thread`; its id joins the done queue.
  void run(std::size_t env_id, std::size_t thread);

  // Whether result number `number` is in its slot of the ring (set by the thread that stepped it, cleared
  // by recv()).
  bool readyAt(std::size_t number) const;
  std::size_t readyFromReceived() const;  // results ready from received_ on without a gap

  std::vector<std::unique_ptr<RacingEnv>> envs_;
  std::vector<std::unique_ptr<Inbox>> inboxes_;
  std::vector<std::thread> threads_;
  std::vector<Slot> slots_;
  std::vector<char> busy_;  // per environment, touched by the caller's thread only
  ResultSink sink_;
  // The handover of a result takes no lock: its number comes from next_number_, its id goes into a ring of one
  // per environment (no more are ever done and not yet received) and a flag says it is there; recv() reads
  // them in number order. A lock (and a wake-up) only for a caller asleep waiting for results.
  alignas(64) std::atomic<std::size_t> next_number_{0};
  alignas(64) std::vector<std::size_t> done_ids_;
  std::vector<std::atomic<bool>> done_ready_flags_;  // value-initialised: all false
  // Touched by the caller's thread only (and read by inFlight(), received() and ready(), which it calls).
  alignas(64) std::size_t received_ = 0;  // numbers received
  std::size_t in_flight_ = 0;
  std::atomic<bool> caller_asleep_{false};
  std::mutex done_mutex_;
  std::condition_variable done_ready_;
  std::mutex error_mutex_;
  std::exception_ptr error_;  // guarded by error_mutex_
  std::atomic<bool> stopping_{false};
  // Threads asleep for want of a job, woken by any job sent: a job in one inbox is every idle thread's work.
  // A sender locks idle_mutex_ only when one is asleep.
  alignas(64) std::atomic<int> sleeping_{0};
  std::mutex idle_mutex_;
  std::condition_variable idle_;
  bool spin_ = false;  // waiting threads spin before they sleep (a core for each of them)
};

}  // namespace roar::rl
