#pragma once
// A policy's laps from the pole position, judged clean as race control judges a car (no contact, never
// beyond the track-limits margin): what rl_train keeps the best policy by, and what a batch's policy cell
// measures.
#include <cstdint>
#include <string>
#include <vector>

#include "roar/rl/policy.h"
#include "roar/rl/racing_env.h"

namespace roar::rl {

struct PolicyLaps {
  std::vector<double> laps;  // s, each lap completed
  double progress = 0.0;     // m along the centre line when it ended
  double sim_time = 0.0;     // s driven
  bool clean = true;
  // Why it ended: "laps done", "time limit", "stalled" (clean), or "collision", "off track", "wrong way",
  // "course end" (not clean: a point-to-point course's end ends the episode, as rl_train always judged it).
  std::string ended;
  double best() const;  // 0 without a lap
};

// `policy` drives `env` (reset with `seed`) until `laps` laps are done, the car is not clean, or the episode
// ends; each step the policy's action for its observation.
PolicyLaps driveLaps(RacingEnv& env, const MlpPolicy& policy, int laps, std::uint64_t seed = 0);

// The environment a policy is judged in: `base` (its training environment) observed as the policy observes,
// from the pole position, for at most `time_limit` seconds.
EnvOptions lapEnvironment(EnvOptions base, const MlpPolicy& policy, double time_limit);

}  // namespace roar::rl
