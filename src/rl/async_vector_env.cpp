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
      done_ready_flags_(envs_.size(), 0) {
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

std::size_t AsyncVectorEnv::inFlight() const {
  std::lock_guard<std::mutex> lock(done_mutex_);
  return in_flight_;
}

bool AsyncVectorEnv::anyQueued() const {
  for (const auto& inbox : inboxes_) {
    if (inbox->queued.load(std::memory_order_acquire) > 0) return true;
  }
  return false;
}

bool AsyncVectorEnv::takeJob(std::size_t thread, std::size_t* env_id) {
  const std::size_t n = inboxes_.size();
  for (std::size_t k = 0; k < n; ++k) {
    Inbox& inbox = *inboxes_[(thread + k) % n];
    if (inbox.queued.load(std::memory_order_acquire) == 0) continue;
    std::lock_guard<std::mutex> lock(inbox.mutex);
    if (inbox.jobs.empty()) continue;  // taken meanwhile
    *env_id = inbox.jobs.front();
    inbox.jobs.pop_front();
    inbox.queued.fetch_sub(1, std::memory_order_acq_rel);
    return true;
  }
  return false;
}

void AsyncVectorEnv::push(std::size_t env_id) {
  Inbox& inbox = *inboxes_[env_id % inboxes_.size()];
  {
    std::lock_guard<std::mutex> lock(inbox.mutex);
    inbox.jobs.push_back(env_id);
    inbox.queued.fetch_add(1, std::memory_order_acq_rel);
  }
  // Checked under the lock a sleeper takes before it sleeps, so a job queued just before it sleeps wakes it.
  bool wake = false;
  {
    std::lock_guard<std::mutex> lock(idle_mutex_);
    wake = sleeping_ > 0;
  }
  if (wake) idle_.notify_one();
}

void AsyncVectorEnv::work(int thread) {
  const auto self = static_cast<std::size_t>(thread);
  for (;;) {
    std::size_t env_id = 0;
    if (takeJob(self, &env_id)) {
      run(env_id);
      continue;
    }
    if (spin_ && spinFor([&] { return anyQueued() || stopping_; }) && !stopping_) continue;
    std::unique_lock<std::mutex> lock(idle_mutex_);
    ++sleeping_;
    idle_.wait(lock, [&] { return stopping_ || anyQueued(); });
    --sleeping_;
    if (stopping_) return;
  }
}

void AsyncVectorEnv::run(std::size_t env_id) {
  Slot& slot = slots_[env_id];
  AsyncResult& result = slot.result;
  result.env_id = env_id;
  result.final_observation.reset();
  std::exception_ptr error;
  try {
    RacingEnv& env = *envs_[env_id];
    if (slot.reset_seed) {
      ResetResult r = env.reset(*slot.reset_seed);
      result.step = StepResult{};
      result.step.observation = std::move(r.observation);
      result.step.info = r.info;
    } else {
      env.step(slot.action, &result.step);
      if (result.step.done()) {
        result.final_observation = std::move(result.step.observation);
        result.step.observation = env.reset().observation;
      }
    }
  } catch (...) {
    error = std::current_exception();
  }
  const std::size_t number = next_number_.fetch_add(1, std::memory_order_acq_rel);
  if (sink_ && !error) sink_(number, result);
  {
    std::lock_guard<std::mutex> lock(done_mutex_);
    if (error && !error_) error_ = error;
    const std::size_t n = envs_.size();
    done_ids_[number % n] = env_id;
    done_ready_flags_[number % n] = 1;
    std::size_t ready = done_count_.load(std::memory_order_relaxed);
    while (ready < n && done_ready_flags_[(received_ + ready) % n]) ++ready;
    done_count_.store(ready, std::memory_order_release);
  }
  done_ready_.notify_one();
}

void AsyncVectorEnv::setResultSink(ResultSink sink) {
  if (inFlight() > 0) throw std::logic_error("AsyncVectorEnv::setResultSink: environments are in flight");
  sink_ = std::move(sink);
}

std::size_t AsyncVectorEnv::received() const {
  std::lock_guard<std::mutex> lock(done_mutex_);
  return received_;
}

void AsyncVectorEnv::reset(std::uint64_t seed) {
  if (inFlight() > 0) throw std::logic_error("AsyncVectorEnv::reset: environments are in flight; recv() them first");
  {
    std::lock_guard<std::mutex> lock(done_mutex_);
    in_flight_ += envs_.size();
  }
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
  {
    std::lock_guard<std::mutex> lock(done_mutex_);
    in_flight_ += env_ids.size();
  }
  for (std::size_t k = 0; k < env_ids.size(); ++k) {
    Slot& slot = slots_[env_ids[k]];
    slot.action = actions[k];  // assigned into the last action's storage
    slot.reset_seed.reset();
    busy_[env_ids[k]] = 1;
    push(env_ids[k]);
  }
}

std::vector<std::size_t> AsyncVectorEnv::recv(std::size_t batch_size) {
  std::vector<std::size_t> out;
  out.reserve(batch_size);
  {
    std::lock_guard<std::mutex> lock(done_mutex_);
    if (batch_size == 0 || batch_size > in_flight_) {
      throw std::invalid_argument("AsyncVectorEnv::recv: batch_size " + std::to_string(batch_size) + " with " +
                                  std::to_string(in_flight_) + " environment(s) in flight");
    }
  }
  // The caller's thread steps jobs (its own environments' first) while the batch is not complete.
  while (done_count_.load(std::memory_order_acquire) < batch_size) {
    std::size_t env_id = 0;
    if (!takeJob(0, &env_id)) break;
    run(env_id);
  }
  if (spin_) spinFor([&] { return done_count_.load(std::memory_order_acquire) >= batch_size; });
  std::unique_lock<std::mutex> lock(done_mutex_);
  done_ready_.wait(lock, [&] { return done_count_.load(std::memory_order_relaxed) >= batch_size; });
  const std::size_t n = envs_.size();
  for (std::size_t k = 0; k < batch_size; ++k) {
    const std::size_t at = (received_ + k) % n;
    out.push_back(done_ids_[at]);
    done_ready_flags_[at] = 0;
    busy_[out.back()] = 0;
  }
  received_ += batch_size;
  done_count_.store(done_count_.load(std::memory_order_relaxed) - batch_size, std::memory_order_release);
  in_flight_ -= batch_size;
  if (error_) {
    std::exception_ptr e = error_;
    error_ = nullptr;
    std::rethrow_exception(e);
  }
  return out;
}

}  // namespace roar::rl
