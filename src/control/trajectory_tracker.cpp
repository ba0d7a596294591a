#include "roar/control/trajectory_tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "roar/track/heading.h"

namespace roar::control {

namespace {

// m of trajectory over which the road's slope ahead is taken.
constexpr double kGradeBase = 20.0;

void check(const TrackerOptions& o) {
  for (double v : {o.wheelbase, o.max_steer_angle, o.lookahead_min, o.speed_gain}) {
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument("trajectory tracker: lengths, angles and gains must be positive");
  }
  for (double v :
       {o.lookahead_time, o.yaw_rate_gain, o.speed_preview, o.max_speed, o.max_distance, o.recorded_speed_gain}) {
    if (!(v >= 0) || !std::isfinite(v))
      throw std::invalid_argument("trajectory tracker: times, damping and caps must not be negative");
  }
}

}  // namespace

TrajectoryTracker::TrajectoryTracker(const TrackerOptions& options, const planning::VehicleLimits& limits)
    : options_(options), limits_(limits) {
  check(options_);
}

void TrajectoryTracker::setOptions(const TrackerOptions& options) {
  check(options);
  options_ = options;
}

void TrajectoryTracker::setTrajectory(planning::Trajectory trajectory) {
  planning::validate(trajectory);
  // A new window is searched whole; the same closed trajectory keeps its hint.
  if (!trajectory.closed || trajectory.points.size() != trajectory_.points.size()) hint_ = -1;
  trajectory_ = std::move(trajectory);
}

double TrajectoryTracker::steeringAngle(const TrackerInput& in, double s, double speed) const {
  if (options_.lateral == LateralMethod::kPurePursuit) {
    const double lookahead = std::max(options_.lookahead_min, options_.lookahead_time * speed);
    const Eigen::Vector2d rel = planning::sampleAt(trajectory_, s + lookahead).position - in.position;
    const double alpha = std::remainder(std::atan2(rel.y(), rel.x()) - in.yaw, 2.0 * M_PI);
    const double arc = 2.0 * std::sin(alpha) / std::max(rel.norm(), 1e-3);
    return std::atan(options_.wheelbase * arc) + options_.yaw_rate_gain * (speed * arc - in.yaw_rate);
  }
  const Eigen::Vector2d heading = track::forwardOf(in.yaw);
  const Eigen::Vector2d front = in.position + options_.front_axle * heading;
  const auto at_front = planning::project(trajectory_, front, static_cast<long>(hint_));
  const planning::TrajectoryPoint ref = planning::sampleAt(trajectory_, at_front.s);
  const double kappa = planning::sampleAt(trajectory_, at_front.s + speed * options_.steer_preview).curvature;
  const double heading_error = std::remainder(ref.yaw - in.yaw, 2.0 * M_PI);
  const double cross_track =
      std::atan(options_.stanley_gain * -at_front.lateral / (speed + options_.stanley_softening));
  return std::atan(options_.wheelbase * kappa) + heading_error + cross_track +
         options_.yaw_rate_gain * (speed * kappa - in.yaw_rate);
}

vehicle::VehicleControl TrajectoryTracker::update(const TrackerInput& in) {
  vehicle::VehicleControl control;
  if (!hasTrajectory()) {
    control.brake = 1.0;
    return control;
  }
  const auto projection = planning::project(trajectory_, in.position, trajectory_.closed ? hint_ : -1);
  hint_ = static_cast<long>(projection.segment);
  progress_ = projection.s;
  lateral_error_ = projection.lateral;
  distance_ = (planning::sampleAt(trajectory_, projection.s).position - in.position).norm();
  if (tooFar()) {
    target_speed_ = 0.0;
    control.brake = 1.0;
    return control;
  }
  // The speed the profile is a speed of, along the path: a car sliding at an angle has less of it forward,
  // and taken for slow it was floored mid-slide (trajectory_tracker_test ASlidingCarIsNotTakenForASlowOne).
  const double speed = in.speed > 0.0 ? std::hypot(in.speed, in.lateral_speed) : 0.0;

  const double lock = options_.max_steer_angle * vehicle::steeringShare(options_.steering_curve, std::abs(speed));
  control.steer = std::clamp(steeringAngle(in, projection.s, speed) / lock, -1.0, 1.0);

  if (std::isfinite(trajectory_.points.front().recorded_pedal)) {
    // A recorded lap: the pedal that drove it here, trimmed by the speed it had here.
    const planning::TrajectoryPoint here = planning::sampleAt(trajectory_, projection.s);
    target_speed_ = options_.max_speed > 0 ? std::min(here.speed, options_.max_speed) : here.speed;
    const double effort = here.recorded_pedal + options_.recorded_speed_gain * (target_speed_ - speed);
    control.throttle = std::clamp(effort, 0.0, 1.0);
    control.brake = std::clamp(-effort, 0.0, 1.0);
    return control;
  }
  const planning::TrajectoryPoint ahead =
      planning::sampleAt(trajectory_, projection.s + speed * options_.speed_preview);
  target_speed_ = options_.max_speed > 0 ? std::min(ahead.speed, options_.max_speed) : ahead.speed;
  const double acceleration = options_.max_speed > 0 && target_speed_ < ahead.speed ? 0.0 : ahead.acceleration;
  // Feed-forward: the force the profile's acceleration needs, gravity along the road's slope counted, as a
  // share of what engine or brakes give.
  const planning::TrajectoryPoint beyond = planning::sampleAt(trajectory_, ahead.s + kGradeBase);
  const double rise = beyond.s > ahead.s ? beyond.z - ahead.z : 0.0;
  const double slope = rise / std::hypot(std::max(beyond.s - ahead.s, 1e-9), rise);
  const double force = limits_.mass * (acceleration + limits_.gravity * slope) + limits_.resistance(speed);
  const double feed_forward =
      force >= 0 ? force / std::max(1.0, limits_.driveForce(speed)) : force / std::max(1.0, limits_.max_brake_force);
  const double effort = feed_forward + options_.speed_gain * (target_speed_ - speed);
  control.throttle = std::clamp(effort, 0.0, 1.0);
  control.brake = std::clamp(-effort, 0.0, 1.0);
  return control;
}

}  // namespace roar::control
