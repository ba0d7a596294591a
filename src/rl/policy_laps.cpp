#include "roar/rl/policy_laps.h"

#include <algorithm>

#include "roar/race/race_control.h"

namespace roar::rl {

double PolicyLaps::best() const { return laps.empty() ? 0.0 : *std::min_element(laps.begin(), laps.end()); }

namespace {

std::string endOf(const StepResult& r, const PolicyLaps& run, int laps) {
  if (r.info.collision_impulse > 0.0 || r.info.collided) return "collision";
  if (r.info.beyond_edge > race::RaceRules().track_limits_margin || r.info.off_track) return "off track";
  if (static_cast<int>(run.laps.size()) >= laps) return "laps done";
  if (r.info.stalled) return "stalled";
  if (r.info.wrong_way) return "wrong way";
  return "time limit";
}

}  // namespace

PolicyLaps driveLaps(RacingEnv& env, const MlpPolicy& policy, int laps, std::uint64_t seed) {
  PolicyLaps run;
  Value obs = env.reset(seed).observation;
  for (;;) {
    const StepResult r = env.step(policy.act(env.actionSpace(), obs));
    if (r.info.collision_impulse > 0.0 || r.terminated || r.info.beyond_edge > race::RaceRules().track_limits_margin) {
      run.clean = false;
    }
    if (r.info.laps > static_cast<int>(run.laps.size())) run.laps.push_back(r.info.last_lap_time);
    run.progress = r.info.progress;
    run.sim_time = r.info.episode_time;
    if (r.done() || static_cast<int>(run.laps.size()) >= laps || !run.clean) {
      run.ended = endOf(r, run, laps);
      return run;
    }
    obs = r.observation;
  }
}

EnvOptions lapEnvironment(EnvOptions base, const MlpPolicy& policy, double time_limit) {
  base.observation = policy.observation();
  base.spawn = SpawnMode::kGrid;
  base.termination.time_limit = time_limit;
  return base;
}

}  // namespace roar::rl
