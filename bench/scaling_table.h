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
void printScalingTable(const EnvFactory& make_env, const Policy& policy, int max_threads, double seconds);

}  // namespace roar::bench
