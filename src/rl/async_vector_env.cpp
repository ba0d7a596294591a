#include "roar/rl/async_vector_env.h"

#include <stdexcept>
#include <string>

#include "roar/rl/spin_wait.h"

namespace roar::rl {

AsyncVectorEnv::AsyncVectorEnv(std::vector<std::unique_ptr<RacingEnv>> envs, int threads)
    : envs_(std::move(envs)),
      slots_(envs_.size()),
      busy_(envs_.size(), 0),
      done_ids_(envs_.size(), 0),
      done_ready_flags_(envs_.size()) {
  if (envs_.empty()) throw std::invalid_argument("AsyncVectorEnv needs at least one environment");
  if (threads < 1) throw std::invalid_argument("AsyncVectorEnv: threads must be at least 1");
  for (const auto& e : envs_) {
    if (toYaml(e->actionSpace()) != toYaml(actionSpace()) ||
        toYaml(e->observationSpace()) != toYaml(observationSpace())) {
      throw std::invalid_argument("AsyncVectorEnv: the environments' spaces differ");
    }
  }
  const int n = std::min<int>(threads, static_cast<int>(envs_.size()));
  // Spinning pays only with a core for every spinning thread (the workers and the caller's): on fewer,
  // a spinning thread takes the core from the one it waits for.
  spin_ = static_cast<unsigned>(n) <= std::thread::hardware_concurrency();
  for (int t = 0; t < n; ++t) inboxes_.push_back(std::make_unique<Inbox>());
  // Inbox 0 is the caller's: it steps jobs itself in recv() (a thread of its own for them
  // would leave the caller's core idle while it waits, or, on as many threads as cores, take a core from a
  // worker: 0.68 of the processes' steps/s at 2 threads on 2 cores).
  for (int t = 1; t < n; ++t) threads_.emplace_back([this, t] { work(t); });
}

AsyncVectorEnv::~AsyncVectorEnv() {
  {
    std::lock_guard<std::mutex> lock(idle_mutex_);
    stopping_ = true;
  }
  idle_.notify_all();
  for (auto& t : threads_) t.join();
}

std::size_t AsyncVectorEnv::inFlight() const { return in_flight_; }

bool AsyncVectorEnv::readyAt(std::size_t number) const {
  return done_ready_flags_[number % envs_.size()].load(std::memory_order_seq_cst);
}

std::size_t AsyncVectorEnv::readyFromReceived() const {
  std::size_t ready = 0;
  while (ready < in_flight_ && readyAt(received_ + ready)) ++ready;
  return ready;
}

bool AsyncVectorEnv::anyQueued() const {
  for (const auto& inbox : inboxes_) {
    if (inbox->queued.load(std::memory_order_seq_cst) > 0) return true;
  }
  return false;
}

bool AsyncVectorEnv::takeJob(std::size_t thread, std::size_t* env_id) {
  const std::size_t n = inboxes_.size();
  const bool caller = thread == 0;
  for (std::size_t k = 0; k < n; ++k) {
    Inbox& inbox = *inboxes_[(thread + k) % n];
    if (inbox.queued.load(std::memory_order_acquire) == 0) continue;
    std::lock_guard<std::mutex> lock(inbox.mutex);
    // A worker takes resets first: their environments have been stepped already, and the caller waits.
    std::deque<std::size_t>& from = !caller && !inbox.resets.empty() ? inbox.resets : inbox.jobs;
    if (from.empty()) continue;  // taken meanwhile, or only resets (which the caller leaves to the workers)
    *env_id = from.front();
    from.pop_front();
    inbox.queued.fetch_sub(1, std::memory_order_acq_rel);
    return true;
  }
  return false;
}

void AsyncVectorEnv::push(std::size_t env_id) { pushTo(*inboxes_[env_id % inboxes_.size()], env_id, false); }

void AsyncVectorEnv::pushTo(Inbox& inbox, std::size_t env_id, bool reset) {
  {
    std::lock_guard<std::mutex> lock(inbox.mutex);
    (reset ? inbox.resets : inbox.jobs).push_back(env_id);
    inbox.queued.fetch_add(1, std::memory_order_seq_cst);
  }
  // A sleeper counts itself in sleeping_ and then looks for a job; this queued the job and then reads
  // sleeping_ (both sequentially consistent), so one of the two sees the other. The lock waits until a
  // sleeper counted here is in its wait, so the notification reaches it.
  if (sleeping_.load(std::memory_order_seq_cst) > 0) {
    { std::lock_guard<std::mutex> lock(idle_mutex_); }
    idle_.notify_one();
  }
}

void AsyncVectorEnv::work(int thread) {
  const auto self = static_cast<std::size_t>(thread);
  for (;;) {
    std::size_t env_id = 0;
    if (takeJob(self, &env_id)) {
      run(env_id, self);
      continue;
    }
    if (spin_ && spinFor([&] { return anyQueued() || stopping_; }) && !stopping_) continue;
    std::unique_lock<std::mutex> lock(idle_mutex_);
    sleeping_.fetch_add(1, std::memory_order_seq_cst);
    idle_.wait(lock, [&] { return stopping_ || anyQueued(); });
    sleeping_.fetch_sub(1, std::memory_order_seq_cst);
    if (stopping_) return;
  }
}

void AsyncVectorEnv::run(std::size_t env_id, std::size_t thread) {
  Slot& slot = slots_[env_id];
  AsyncResult& result = slot.result;
  std::exception_ptr error;
  try {
    RacingEnv& env = *envs_[env_id];
    if (slot.resetting) {
      slot.resetting = false;
      result.step.observation = env.reset().observation;
    } else if (slot.reset_seed) {
      result.env_id = env_id;
      result.final_observation.reset();
      ResetResult r = env.reset(*slot.reset_seed);
      result.step = StepResult{};
      result.step.observation = std::move(r.observation);
      result.step.info = r.info;
    } else {
      result.env_id = env_id;
      result.final_observation.reset();
      env.step(slot.action, &result.step);
      if (result.step.done()) {
        result.final_observation = std::move(result.step.observation);
        // An auto-reset takes as long as seven steps (the car settles, 280 us): on the caller's thread it
        // kept the results it holds from the learner, and a worker that had stepped what was queued idled
        // for want of the actions that follow them (5% of its time at 2 environments a thread). A worker
        // does it instead.
        if (thread == 0 && inboxes_.size() > 1) {
          slot.resetting = true;
          pushTo(*inboxes_[1 + env_id % (inboxes_.size() - 1)], env_id, true);
          return;
        }
        result.step.observation = env.reset().observation;
      }
    }
  } catch (...) {
    error = std::current_exception();
  }
  if (error) {
    std::lock_guard<std::mutex> lock(error_mutex_);
    if (!error_) error_ = error;
  }
  const std::size_t number = next_number_.fetch_add(1, std::memory_order_acq_rel);
  if (sink_ && !error) sink_(number, result);
  done_ids_[number % envs_.size()] = env_id;
  // Published by the flag (the caller reads the id after it); then, as push() does with sleeping threads,
  // the caller is woken only if it has said it sleeps.
  done_ready_flags_[number % envs_.size()].store(true, std::memory_order_seq_cst);
  if (caller_asleep_.load(std::memory_order_seq_cst)) {
    { std::lock_guard<std::mutex> lock(done_mutex_); }
    done_ready_.notify_one();
  }
}

void AsyncVectorEnv::setResultSink(ResultSink sink) {
  if (inFlight() > 0) throw std::logic_error("AsyncVectorEnv::setResultSink: environments are in flight");
  sink_ = std::move(sink);
}

std::size_t AsyncVectorEnv::received() const { return received_; }

void AsyncVectorEnv::reset(std::uint64_t seed) {
  if (inFlight() > 0) throw std::logic_error("AsyncVectorEnv::reset: environments are in flight; recv() them first");
  in_flight_ += envs_.size();
  for (std::size_t i = 0; i < envs_.size(); ++i) {
    busy_[i] = 1;
    slots_[i].reset_seed = seed + i;
    push(i);
  }
}

void AsyncVectorEnv::send(const std::vector<Value>& actions, const std::vector<std::size_t>& env_ids) {
  if (actions.size() != env_ids.size()) {
    throw std::invalid_argument("AsyncVectorEnv::send: " + std::to_string(actions.size()) + " actions for " +
                                std::to_string(env_ids.size()) + " environment ids");
  }
  std::vector<char> listed(envs_.size(), 0);
  for (std::size_t k = 0; k < env_ids.size(); ++k) {
    const std::size_t id = env_ids[k];
    if (id >= envs_.size()) {
      throw std::invalid_argument("AsyncVectorEnv::send: env_ids[" + std::to_string(k) + "] = " + std::to_string(id) +
                                  " is not an environment (0.." + std::to_string(envs_.size() - 1) + ")");
    }
    if (busy_[id] || listed[id]) {
      throw std::invalid_argument("AsyncVectorEnv::send: environment " + std::to_string(id) +
                                  (listed[id] ? " is listed twice" : " is still stepping: recv() its result first"));
    }
    listed[id] = 1;
    check(actionSpace(), actions[k], "actions[" + std::to_string(k) + "]");
  }
  in_flight_ += env_ids.size();
  for (std::size_t k = 0; k < env_ids.size(); ++k) {
    Slot& slot = slots_[env_ids[k]];
    slot.action = actions[k];  // assigned into the last action's storage
    slot.reset_seed.reset();
    busy_[env_ids[k]] = 1;
    push(env_ids[k]);
  }
}

std::vector<std::size_t> AsyncVectorEnv::recv(std::size_t batch_size) {
  if (batch_size == 0 || batch_size > in_flight_) {
    throw std::invalid_argument("AsyncVectorEnv::recv: batch_size " + std::to_string(batch_size) + " with " +
                                std::to_string(in_flight_) + " environment(s) in flight");
  }
  const auto batchReady = [&] { return readyAt(received_ + batch_size - 1) && readyFromReceived() >= batch_size; };
  // The caller's thread steps jobs (its own environments' first) while the batch is not complete.
  while (!batchReady()) {
    std::size_t env_id = 0;
    if (!takeJob(0, &env_id)) break;
    run(env_id, 0);
  }
  if (spin_) spinFor(batchReady);
  if (!batchReady()) {
    std::unique_lock<std::mutex> lock(done_mutex_);
    caller_asleep_.store(true, std::memory_order_seq_cst);
    done_ready_.wait(lock, batchReady);
    caller_asleep_.store(false, std::memory_order_relaxed);
  }
  std::vector<std::size_t> out;
  out.reserve(batch_size);
  const std::size_t n = envs_.size();
  for (std::size_t k = 0; k < batch_size; ++k) {
    const std::size_t at = (received_ + k) % n;
    out.push_back(done_ids_[at]);
    done_ready_flags_[at].store(false, std::memory_order_relaxed);
    busy_[out.back()] = 0;
  }
  received_ += batch_size;
  in_flight_ -= batch_size;
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(error_mutex_);
    std::swap(error, error_);
  }
  if (error) std::rethrow_exception(error);
  return out;
}

}  // namespace roar::rl
