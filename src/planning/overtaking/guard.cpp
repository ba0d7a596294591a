// The guard under every plan: whatever was chosen, no faster than a car ahead in the plan's own path allows.
#include <algorithm>
#include <cmath>

#include "roar/planning/overtaking/planner.h"
#include "roar/planning/speed_profile.h"
#include "tuning.h"

namespace roar::planning {

using namespace tuning;

void OvertakePlanner::guard(Trajectory* window, double s, double speed, const std::vector<TrafficCar>& others,
                            const std::vector<Prediction>& predicted, bool clear_pass) const {
  // Whatever was chosen, never faster than a car ahead in the plan's own path allows: the nearest car
  // ahead whose lateral place overlaps the plan's where it is is followed at a short gap.
  const double gap = levelDistance() + options_.guard.time * speed;
  const TrafficCar* nearest = nullptr;
  const Prediction* nearest_prediction = nullptr;
  double nearest_rel = 0.0;
  // Where a pass gets along its plan in one and two seconds (-inf: not reached within it).
  const double level = levelDistance();
  double travelled[3] = {0.0, -kInf, -kInf};
  if (clear_pass) {
    driveAlong(*window, s, speed, [&](std::size_t, double t, double s_now, double) {
      for (int i : {1, 2}) {
        if (t >= i && travelled[i] == -kInf) travelled[i] = s_now - s;
      }
      return t < 2.0;
    });
  }
  const double width = options_.car.width + options_.guard.lateral;
  for (std::size_t j = 0; j < others.size(); ++j) {
    const TrafficCar& o = others[j];
    const double rel = aheadOnLap(o.s, s, lapLength(line_));
    if (rel <= 0.0 || (nearest && rel >= nearest_rel)) continue;
    // In the path now, or in it over the next two seconds. For a clear pass (checked against every car's
    // prediction, with margins), later only while the car is still ahead then, and a car level now only by
    // moving across into it: the pass's own way back onto the line in front of the car it passes is not
    // that car in its path (held a gap behind it, the passer would brake beside it and fall back). Any
    // other plan (following is checked against nobody) keeps every time: a car falling in behind one
    // braking hard must not meet it where it would have been level.
    const bool level_now = rel < level;
    bool in_path = false;
    for (int i : {0, 1, 2}) {
      const double tau = i;
      if (clear_pass && i > 0 && predicted[j].at(tau) - travelled[i] < level) continue;
      const double at = rel + tau * o.speed;
      const double d = sampleAt(*window, s + at).offset - sampleAt(line_, s + at).offset;
      const double drift = o.lateral + o.lateral_speed * std::min(tau, options_.prediction.lateral_lookahead);
      const double theirs = tau == 0.0 ? o.lateral : plannedLateral(trustedPlan(o), drift, o.s + tau * o.speed);
      const bool moved_in = std::abs(d - o.lateral) >= width;
      in_path = in_path || (std::abs(d - theirs) < width && (i == 0 || !clear_pass || !level_now || moved_in));
    }
    if (!in_path) continue;
    nearest = &o;
    nearest_prediction = &predicted[j];
    nearest_rel = rel;
  }
  if (!nearest) return;
  // Without guard_predicted, or already nearer than the gap: held from where the car ahead is now.
  if (!options_.guard.predicted || nearest_rel < gap) {
    followBehind(window, s, s + nearest_rel, nearest->speed, gap, limits_, speed);
    return;
  }
  // guard_predicted: held to that car's speed from where, driving the window, the car would first come
  // within the gap of it as it is predicted to go on (held short of where it is now at its speed now, a car
  // 5% faster needs (v^2 - v_ahead^2) / 2a more room to go faster: 17 m at 60 m/s for 3 m/s).
  const Prediction& ahead = *nearest_prediction;
  double meet_s = kInf, meet_speed = nearest->speed;
  driveAlong(*window, s, speed, [&](std::size_t, double t, double s_now, double) {
    if (t > options_.prediction.horizon) return false;
    if (s_now - s < ahead.at(t) - gap) return true;
    meet_s = s_now;
    meet_speed = (ahead.at(t + kPredictionStep) - ahead.at(t)) / kPredictionStep;
    return false;
  });
  if (std::isfinite(meet_s)) followBehind(window, s, meet_s + gap, std::max(0.0, meet_speed), gap, limits_);
}

}  // namespace roar::planning
