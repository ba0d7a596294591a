#include "scaling_table.h"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <vector>

#include "roar/rl/async_vector_env.h"
#include "roar/rl/vector_env.h"

namespace roar::bench {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// One process, `threads` threads, two environments each, stepped in lockstep.
double synchronousRate(const EnvFactory& make_env, const Policy& policy, bool camera, int threads, double seconds) {
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  for (int i = 0; i < 2 * threads; ++i) envs.push_back(make_env(camera));
  rl::VectorEnv vec(std::move(envs), threads);
  std::vector<rl::Value> actions;
  for (auto& r : vec.reset(1)) actions.push_back(policy(vec.actionSpace(), r.observation));
  long steps = 0;
  const auto start = Clock::now();
  while (secondsSince(start) < seconds) {
    const rl::VectorStepResult& r = vec.step(actions);
    for (std::size_t i = 0; i < actions.size(); ++i) actions[i] = policy(vec.actionSpace(), r.steps[i].observation);
    steps += static_cast<long>(actions.size());
  }
  return static_cast<double>(steps) / secondsSince(start);
}

// One process, `threads` threads (the caller's and threads - 1 workers), two environments each, batches of
// `threads`: EnvPool's asynchronous mode.
double asynchronousRate(const EnvFactory& make_env, const Policy& policy, bool camera, int threads, double seconds) {
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  for (int i = 0; i < 2 * threads; ++i) envs.push_back(make_env(camera));
  rl::AsyncVectorEnv pool(std::move(envs), threads);
  pool.reset(1);
  long steps = 0;
  const auto start = Clock::now();
  while (secondsSince(start) < seconds) {
    const std::vector<rl::AsyncResult> done = pool.recv(static_cast<std::size_t>(threads));
    std::vector<rl::Value> actions;
    std::vector<std::size_t> ids;
    for (const auto& r : done) {
      actions.push_back(policy(pool.actionSpace(), r.step.observation));
      ids.push_back(r.env_id);
    }
    pool.send(actions, ids);
    steps += static_cast<long>(done.size());
  }
  const double rate = static_cast<double>(steps) / secondsSince(start);
  pool.recv(pool.inFlight());
  return rate;
}

// `processes` forked processes, each one environment on one thread: the reference a process per core gives.
double processesRate(const EnvFactory& make_env, const Policy& policy, bool camera, int processes, double seconds) {
  std::vector<int> reads;
  std::vector<pid_t> children;
  for (int p = 0; p < processes; ++p) {
    int fds[2];
    if (pipe(fds) != 0) return 0.0;
    const pid_t child = fork();
    if (child == 0) {
      close(fds[0]);
      auto env = make_env(camera);
      rl::Value action = policy(env->actionSpace(), env->reset(1 + static_cast<std::uint64_t>(p)).observation);
      rl::StepResult result;
      long steps = 0;
      const auto start = Clock::now();
      while (secondsSince(start) < seconds) {
        env->step(action, &result);
        if (result.done()) result.observation = env->reset().observation;
        action = policy(env->actionSpace(), result.observation);
        ++steps;
      }
      const double rate = static_cast<double>(steps) / secondsSince(start);
      const ssize_t written = write(fds[1], &rate, sizeof rate);
      _exit(written == sizeof rate ? 0 : 1);
    }
    close(fds[1]);
    reads.push_back(fds[0]);
    children.push_back(child);
  }
  double total = 0.0;
  for (std::size_t p = 0; p < children.size(); ++p) {
    double rate = 0.0;
    if (read(reads[p], &rate, sizeof rate) == sizeof rate) total += rate;
    close(reads[p]);
    waitpid(children[p], nullptr, 0);
  }
  return total;
}

}  // namespace

void printScalingTable(const EnvFactory& make_env, const Policy& policy, int max_threads, double seconds) {
  std::printf(
      "\nScaling: the RL environment on Roar Sprint, steps/s in one process against as many single-thread "
      "processes (%.0f s each)\n",
      seconds);
  std::printf("%-7s %7s %12s %12s %12s %10s %10s\n", "obs", "threads", "sync", "async", "processes", "sync/proc",
              "async/proc");
  for (bool camera : {false, true}) {
    for (int threads = 1; threads <= max_threads; ++threads) {
      const double sync = synchronousRate(make_env, policy, camera, threads, seconds);
      const double async = asynchronousRate(make_env, policy, camera, threads, seconds);
      const double procs = processesRate(make_env, policy, camera, threads, seconds);
      std::printf("%-7s %7d %12.0f %12.0f %12.0f %10.2f %10.2f\n", camera ? "camera" : "state", threads, sync, async,
                  procs, sync / procs, async / procs);
      std::fflush(stdout);
    }
  }
  std::printf(
      "sync: VectorEnv, two environments a thread, every thread stepping each step; async: AsyncVectorEnv,\n"
      "two environments a thread (the caller's one of them), batches of one a thread; processes: one\n"
      "environment each, forked.\n");
}

}  // namespace roar::bench
