#include "scaling_table.h"

#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <vector>

#include "roar/rl/async_vector_env.h"
#include "roar/rl/vector_env.h"
#include "statistics.h"

namespace roar::bench {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// What one measurement does: every configuration steps the same environments (environment i reset with
// seed 1 + i, driven by the same policy) the same number of steps each, so the three columns do the same
// work, episode for episode, and differ only in how threads share it. (Timed for a fixed time instead, a
// 1 s window of one environment alone varied by a third with the stretch of track and the resets in it.)
struct Work {
  EnvFactory make_env;
  Policy policy;
  bool camera = false;
  int envs_per_thread = 2;
  long steps_per_env = 0;
};

std::vector<std::unique_ptr<rl::RacingEnv>> makeEnvs(const Work& w, int count) {
  std::vector<std::unique_ptr<rl::RacingEnv>> envs;
  for (int i = 0; i < count; ++i) envs.push_back(w.make_env(w.camera));
  return envs;
}

// One step of an environment outside any pool, reset when its episode ends, and the policy's next action.
void stepAlone(const Work& w, rl::RacingEnv& env, rl::Value* action, rl::StepResult* result) {
  env.step(*action, result);
  if (result->done()) result->observation = env.reset().observation;
  *action = w.policy(env.actionSpace(), result->observation);
}

// One environment's steps per second, stepped alone (reset with seed 1) for `seconds`.
double aloneRate(const Work& w, double seconds) {
  auto env = w.make_env(w.camera);
  rl::Value action = w.policy(env->actionSpace(), env->reset(1).observation);
  rl::StepResult result;
  long steps = 0;
  const auto start = Clock::now();
  while (secondsSince(start) < seconds) {
    stepAlone(w, *env, &action, &result);
    ++steps;
  }
  return static_cast<double>(steps) / secondsSince(start);
}

// One process, `threads` threads, envs_per_thread environments each, stepped in lockstep.
double synchronousRate(const Work& w, int threads) {
  rl::VectorEnv vec(makeEnvs(w, w.envs_per_thread * threads), threads);
  std::vector<rl::Value> actions;
  for (auto& r : vec.reset(1)) actions.push_back(w.policy(vec.actionSpace(), r.observation));
  const auto start = Clock::now();
  for (long k = 0; k < w.steps_per_env; ++k) {
    const rl::VectorStepResult& r = vec.step(actions);
    for (std::size_t i = 0; i < actions.size(); ++i) actions[i] = w.policy(vec.actionSpace(), r.steps[i].observation);
  }
  return static_cast<double>(w.steps_per_env) * static_cast<double>(actions.size()) / secondsSince(start);
}

// One process, `threads` threads (the caller's and threads - 1 workers), envs_per_thread environments each,
// batches of one a thread: EnvPool's asynchronous mode. Timed until the first environment has made its steps:
// from then on fewer environments than the threads can keep busy are left, a stretch (8-10% of the run here)
// that a learner sending every environment again never has.
double asynchronousRate(const Work& w, int threads) {
  const std::size_t count = static_cast<std::size_t>(w.envs_per_thread * threads);
  rl::AsyncVectorEnv pool(makeEnvs(w, static_cast<int>(count)), threads);
  pool.reset(1);
  std::vector<std::size_t> ids = pool.recv(count);
  std::vector<long> left(count, w.steps_per_env);
  std::vector<rl::Value> actions;
  for (const std::size_t id : ids) actions.push_back(w.policy(pool.actionSpace(), pool.result(id).step.observation));
  const auto start = Clock::now();
  pool.send(actions, ids);
  long steps = 0;
  bool one_done = false;
  while (!one_done) {
    ids = pool.recv(static_cast<std::size_t>(threads));
    actions.clear();
    steps += static_cast<long>(ids.size());
    for (const std::size_t id : ids) {
      one_done = one_done || --left[id] == 0;
      actions.push_back(w.policy(pool.actionSpace(), pool.result(id).step.observation));
    }
    if (!one_done) pool.send(actions, ids);
  }
  const double rate = static_cast<double>(steps) / secondsSince(start);
  pool.recv(pool.inFlight());
  return rate;
}

// A measurement made in a forked child (its own process: nothing shared with this one but the pages it was
// forked with). Its result is read by finishChild; started children run at the same time.
struct Child {
  pid_t pid = -1;
  int result_fd = -1;
};

Child startChild(const std::function<double()>& measure) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const double rate = measure();
    const ssize_t written = write(fds[1], &rate, sizeof rate);
    _exit(written == sizeof rate ? 0 : 1);
  }
  close(fds[1]);
  return {pid, fds[0]};
}

// The child's result (0 if it gave none), once it has finished.
double finishChild(const Child& child) {
  if (child.pid < 0) return 0.0;
  double rate = 0.0;
  if (read(child.result_fd, &rate, sizeof rate) != sizeof rate) rate = 0.0;
  close(child.result_fd);
  waitpid(child.pid, nullptr, 0);
  return rate;
}

// `processes` forked processes, each one thread stepping its envs_per_thread environments in turn (process
// p's being the environments p * envs_per_thread.. of the pools): the reference a process per core gives,
// the sum of the processes' rates.
double processesRate(const Work& w, int processes) {
  std::vector<Child> children;
  for (int p = 0; p < processes; ++p) {
    children.push_back(startChild([&w, p] {
      std::vector<std::unique_ptr<rl::RacingEnv>> envs = makeEnvs(w, w.envs_per_thread);
      std::vector<rl::Value> actions;
      for (int e = 0; e < w.envs_per_thread; ++e) {
        const auto seed = static_cast<std::uint64_t>(1 + w.envs_per_thread * p + e);
        actions.push_back(w.policy(envs[e]->actionSpace(), envs[e]->reset(seed).observation));
      }
      rl::StepResult result;
      const auto start = Clock::now();
      for (long k = 0; k < w.steps_per_env; ++k) {
        for (std::size_t e = 0; e < envs.size(); ++e) {
          stepAlone(w, *envs[e], &actions[e], &result);
        }
      }
      return static_cast<double>(w.steps_per_env) * static_cast<double>(envs.size()) / secondsSince(start);
    }));
  }
  double total = 0.0;
  for (const Child& child : children) total += finishChild(child);
  return total;
}

// One environment's steps per second alone on each core the process may use, each measured in a child pinned
// to it, one core at a time. On a virtual machine the cores need not be alike (on the 2-core CI machine one
// ran 30% slower than the other for minutes, then as fast): a column that lands on the slow one reads low,
// whatever its design. Printed beside the table so that its ratios can be read against them.
void printCoreSpeeds(const Work& w, const char* when) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) return;
  std::printf("one environment alone on each core (%s):", when);
  double slowest = 0.0, fastest = 0.0;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (!CPU_ISSET(cpu, &allowed)) continue;
    const double rate = finishChild(startChild([&w, cpu] {
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(cpu, &one);
      return sched_setaffinity(0, sizeof one, &one) == 0 ? aloneRate(w, 1.0) : 0.0;
    }));
    std::printf(" cpu%d %.0f", cpu, rate);
    slowest = slowest == 0.0 ? rate : std::min(slowest, rate);
    fastest = std::max(fastest, rate);
  }
  std::printf(" steps/s (slowest / fastest %.2f)\n", fastest > 0.0 ? slowest / fastest : 0.0);
  std::fflush(stdout);
}

// Steps per environment for about `seconds` of a thread's work: one environment's rate over half a second.
long stepsPerEnv(const Work& w, double seconds) {
  return std::max(1L, static_cast<long>(aloneRate(w, 0.5) * seconds / w.envs_per_thread));
}

}  // namespace

void printScalingTable(const EnvFactory& make_env, const Policy& policy, const ScalingOptions& options) {
  std::printf(
      "\nScaling: the RL environment on Roar Sprint, steps/s in one process against as many single-thread "
      "processes (about %.1f s of work a thread, %d environments a thread, median of %d rounds)\n",
      options.seconds, options.envs_per_thread, options.repeats);
  std::printf("%-7s %7s %9s %12s %12s %12s %10s %10s %12s %12s\n", "obs", "threads", "steps/env", "sync", "async",
              "processes", "sync/proc", "async/proc", "sync range", "async range");
  const Work state_work{make_env, policy, false, options.envs_per_thread, 0};
  printCoreSpeeds(state_work, "state observations, before");
  for (bool camera : {false, true}) {
    Work work{make_env, policy, camera, options.envs_per_thread, 0};
    work.steps_per_env = stepsPerEnv(work, options.seconds);
    for (int threads = 1; threads <= options.max_threads; ++threads) {
      // Measured in turn, round after round, so a slow spell of the machine falls on all three alike.
      std::vector<double> sync, async, procs, sync_ratio, async_ratio;
      for (int round = 0; round < options.repeats; ++round) {
        sync.push_back(synchronousRate(work, threads));
        async.push_back(asynchronousRate(work, threads));
        procs.push_back(processesRate(work, threads));
        sync_ratio.push_back(sync.back() / procs.back());
        async_ratio.push_back(async.back() / procs.back());
      }
      const auto [sync_min, sync_max] = std::minmax_element(sync_ratio.begin(), sync_ratio.end());
      const auto [async_min, async_max] = std::minmax_element(async_ratio.begin(), async_ratio.end());
      std::printf("%-7s %7d %9ld %12.0f %12.0f %12.0f %10.2f %10.2f %7.2f-%.2f %7.2f-%.2f\n",
                  camera ? "camera" : "state", threads, work.steps_per_env, median(sync), median(async), median(procs),
                  median(sync_ratio), median(async_ratio), *sync_min, *sync_max, *async_min, *async_max);
      std::fflush(stdout);
    }
  }
  printCoreSpeeds(state_work, "state observations, after");
  std::printf(
      "sync: VectorEnv, every thread stepping each step; async: AsyncVectorEnv (the caller's thread one of\n"
      "them), batches of one a thread; processes: forked, one thread each, their rates summed. Every column\n"
      "steps the same environments the same steps; ratios are the median of the rounds' own, and their range.\n");
}

}  // namespace roar::bench
