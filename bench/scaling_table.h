#pragma once
// roar_bench --scaling: the RL environment's steps per second for 1..N threads in one process (the
// synchronous VectorEnv and the asynchronous AsyncVectorEnv) against N single-thread processes doing the
// same work, with state and camera observations.
#include <functional>
#include <memory>
#include <string>

#include "roar/rl/action.h"
#include "roar/rl/racing_env.h"

namespace roar::bench {

// make_env: a new environment (state or camera observations); policy: an action for an observation.
using EnvFactory = std::function<std::unique_ptr<rl::RacingEnv>(bool camera)>;
using Policy = std::function<rl::Value(const rl::Space& actions, const rl::Value& observation)>;
struct ScalingOptions {
  int max_threads = 1;      // rows for 1..max_threads
  double seconds = 3.0;     // about this much work a thread in each measurement
  int repeats = 3;          // rounds of the three measurements, taken in turn; the table prints medians
  int envs_per_thread = 2;  // in the pools and in each process alike
};
void printScalingTable(const EnvFactory& make_env, const Policy& policy, const ScalingOptions& options);

}  // namespace roar::bench
