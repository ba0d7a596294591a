#include "roar/planning/field_planner.h"

#include <cmath>
#include <stdexcept>

#include "roar/planning/speed_profile.h"
#include "roar/track/heading.h"

namespace roar::planning {

FieldPlanner::FieldPlanner(const track::Track& track, Trajectory line, const VehicleLimits& limits,
                           FieldOptions options)
    : line_(std::move(line)), limits_(limits), options_(options) {
  validate(line_);
  if (options_.overtaking) overtaker_ = std::make_unique<OvertakePlanner>(track, line_, limits_, options_.overtake);
}

void FieldPlanner::locate(const std::string& car, const Eigen::Vector3d& position, double speed, double time,
                          const std::optional<Eigen::Vector2d>& velocity) {
  Place& place = cars_[car];
  const double lateral_before = place.on_line.lateral;
  const bool first = place.hint < 0;
  const double s_before = place.on_line.s;
  place.on_line = first ? projectAtHeight(line_, position) : project(line_, position.head<2>(), place.hint);
  // Distance round the laps, so that a car a lap up is told from one just behind (blue flags).
  if (!progress_origin_) progress_origin_ = place.on_line.s;
  place.progress = first ? aheadOnLap(place.on_line.s, *progress_origin_, lapLength(line_))
                         : place.progress + aheadOnLap(place.on_line.s, s_before, lapLength(line_));
  // Its sideways motion, over a few messages: a car moving across is seen moving (a cut-in); and, where
  // its velocity is known, this moment's.
  const double dt = time - place.time;
  const bool since_last = dt > 1e-6 && dt < 1.0;  // a message after the last one, not after a gap
  place.lateral_velocity = std::numeric_limits<double>::quiet_NaN();
  if (velocity) {
    const double line_yaw = sampleAt(line_, place.on_line.s).yaw;
    place.lateral_velocity = velocity->dot(track::leftOf(line_yaw));
  }
  if (since_last) {
    const double moving = (place.on_line.lateral - lateral_before) / dt;
    place.lateral_speed += 0.3 * (moving - place.lateral_speed);
  } else {
    place.lateral_speed = 0.0;
  }
  place.time = time;
  place.hint = static_cast<long>(place.on_line.segment);
  // Smoothed over about 20 odometry messages (a second at 20 Hz): a car braking behind another for a
  // moment is not taken for a slow one. A car gaining speed as hard as it can shows what its engine (or
  // its grip) can do, not its pace: it lowers no estimate (a car is taken for a full-pace one until it
  // shows otherwise, so that a field accelerating away from the grid is not taken for a slow one). One
  // gaining at under half of that is driving its pace: on a long straight, where the line's speeds rise, a
  // slow car would otherwise be taken for as fast as when last seen all the way down it, and a pass of it
  // there would never draw alongside within the horizon.
  const double line_speed = sampleAt(line_, place.on_line.s).speed;
  place.held.observe(speed, line_speed, time);
  const double share = speed / std::max(1.0, line_speed);
  const bool gaining =
      speed > place.speed && !(since_last && (speed - place.speed) / dt < 0.5 * accelerationAt(limits_, speed, 0.0));
  place.speed = speed;
  if (place.line_share <= 0.0) {
    place.line_share = speed > 5.0 ? share : 1.0;  // at rest (on the grid): not yet known, taken as full pace
  } else if (!gaining || share > place.line_share) {
    place.line_share += 0.05 * (share - place.line_share);
  }
}

void FieldPlanner::setPace(const std::string& car, double pace) {
  if (!(pace > 0.0 && pace <= 1.0)) {
    throw std::invalid_argument("pace of '" + car + "' is " + std::to_string(pace) + ": it must be in (0, 1]");
  }
  pace_[car] = pace;
}

Trajectory FieldPlanner::window(const std::string& car) {
  const Place& place = cars_.at(car);
  const auto pace_it = pace_.find(car);
  const double pace = pace_it == pace_.end() ? 1.0 : pace_it->second;
  if (overtaker_) {
    std::vector<TrafficCar> traffic;
    for (const auto& [name, other] : cars_)
      traffic.push_back({name, other.on_line.s, other.on_line.lateral, other.speed, other.line_share,
                         other.lateral_speed, line_.closed && other.progress - place.progress > 0.5 * line_.length,
                         other.held.speed(), other.lateral_velocity});
    return overtaker_->plan(car, place.on_line.s, place.on_line.lateral, place.speed, traffic, options_.window_behind,
                            options_.window_ahead, pace);
  }
  Trajectory window = windowAround(line_, place.on_line.s, options_.window_behind, options_.window_ahead);
  scaleSpeeds(&window, pace);
  followCarAhead(car, place, &window, &follow_decisions_[car]);
  return window;
}

RaceDecision FieldPlanner::decision(const std::string& car) const {
  if (overtaker_) return overtaker_->decision(car);
  const auto it = follow_decisions_.find(car);
  return it == follow_decisions_.end() ? RaceDecision{} : it->second;
}

std::vector<PredictedPath> FieldPlanner::predictions(const std::string& car) const {
  return overtaker_ ? overtaker_->predictions(car) : std::vector<PredictedPath>{};
}

void FieldPlanner::followCarAhead(const std::string& car, const Place& place, Trajectory* window,
                                  RaceDecision* decision) const {
  double nearest = options_.window_ahead;
  const std::string* leader_name = nullptr;
  const Place* leader = nullptr;
  for (const auto& [name, other] : cars_) {
    if (name == car || std::abs(other.on_line.lateral) > options_.follow_lateral) continue;
    double ahead = other.on_line.s - place.on_line.s;
    ahead -= std::floor(ahead / line_.length) * line_.length;  // forward round the lap
    if (ahead > 0 && ahead < nearest) {
      nearest = ahead;
      leader = &other;
      leader_name = &name;
    }
  }
  *decision = RaceDecision{};
  if (leader) {
    followBehind(window, place.on_line.s, place.on_line.s + nearest, leader->speed,
                 options_.overtake.margins.follow_gap, limits_);
    decision->mode = RaceMode::kFollow;
    decision->other = *leader_name;
  }
}

}  // namespace roar::planning
