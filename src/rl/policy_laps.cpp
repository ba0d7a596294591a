#include "roar/rl/policy_laps.h"

#include <algorithm>

#include "roar/race/race_control.h"

namespace roar::rl {

double PolicyLaps::best() const { return laps.empty() ? 0.0 : *std::min_element(laps.begin(), laps.end()); }

namespace {

// Why a step leaves the run unclean, empty while it is clean: a contact or a wheel beyond race control's track
// limits, or an episode the environment ended (its own off-track margin, driving the wrong way, a course's end).
std::string faultOf(const StepResult& r) {
  if (r.info.collision_impulse > 0.0) return "collision";
  if (r.info.beyond_edge > race::RaceRules().track_limits_margin || (r.terminated && r.info.off_track)) {
    return "off track";
  }
  if (!r.terminated) return "";
  return r.info.wrong_way ? "wrong way" : "course end";
}

}  // namespace

PolicyLaps driveLaps(RacingEnv& env, const MlpPolicy& policy, int laps, std::uint64_t seed) {
  PolicyLaps run;
  Value obs = env.reset(seed).observation;
  for (;;) {
    const StepResult r = env.step(policy.act(env.actionSpace(), obs));
    if (r.info.laps > static_cast<int>(run.laps.size())) run.laps.push_back(r.info.last_lap_time);
    run.progress = r.info.progress;
    run.sim_time = r.info.episode_time;
    run.ended = faultOf(r);
    run.clean = run.ended.empty();
    if (!run.clean) return run;
    if (static_cast<int>(run.laps.size()) >= laps || r.done()) {
      run.ended = static_cast<int>(run.laps.size()) >= laps ? "laps done" : r.info.stalled ? "stalled" : "time limit";
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
