#include "roar/rl/episode_options.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace roar::rl {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

void validate(const RewardOptions& r) {
  for (double v : {r.progress_weight, r.centre_weight, r.backwards_weight, r.step_penalty, r.collision_penalty_scale,
                   r.collision_penalty_cap, r.off_track_penalty}) {
    require(std::isfinite(v), "reward: every weight and penalty must be a finite number");
  }
  require(r.centre_weight >= 0.0, "reward.centre_weight must not be negative");
  require(r.collision_penalty_cap >= 0.0, "reward.collision_penalty_cap must not be negative");
}

void validate(const TerminationOptions& t) {
  require(t.collision_threshold >= 0.0, "termination.collision_threshold must not be negative");
  require(std::isfinite(t.off_track_margin), "termination.off_track_margin must be a number");
  require(t.time_limit >= 0.0 && std::isfinite(t.time_limit), "termination.time_limit must be >= 0 (0: none)");
  require(t.stall_time >= 0.0, "termination.stall_time must be >= 0 (0: never)");
  require(t.max_backwards >= 0.0, "termination.max_backwards must be >= 0 (0: never)");
}

}  // namespace roar::rl
