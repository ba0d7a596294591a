#include "roar/control/centreline_follower.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace roar::control {

CentrelineFollower::CentrelineFollower(const track::Track& track, const FollowerOptions& options)
    : track_(track), options_(options) {
  for (double v : {options.wheelbase, options.max_steer_angle, options.lookahead_min, options.lateral_accel,
                   options.braking_decel, options.max_speed}) {
    if (!(v > 0)) throw std::invalid_argument("centre-line follower: every limit and length must be positive");
  }
  const std::size_t n = track.size();
  profile_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    // Mean absolute curvature over the window smooths the noise of measured centre lines.
    double sum = 0.0;
    int count = 0;
    for (double d = -options.curvature_window; d <= options.curvature_window; d += 1.0, ++count) {
      sum += std::abs(track.curvatureAt(track.s(i) + d));
    }
    const double kappa = sum / count;
    profile_[i] = kappa > 1e-6 ? std::min(options.max_speed, std::sqrt(options.lateral_accel / kappa)) : options.max_speed;
  }
  // Braking: going backwards round the loop (twice, so the wrap-around settles), each point may be no
  // faster than what brakes down to the next one in time.
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t k = n; k-- > 0;) {
      const std::size_t next = (k + 1) % n;
      const double ds = (next == 0 ? track.length() : track.s(next)) - track.s(k);
      profile_[k] = std::min(profile_[k], std::sqrt(profile_[next] * profile_[next] + 2.0 * options.braking_decel * ds));
    }
  }
}

double CentrelineFollower::targetSpeedAt(double s) const {
  s = track_.wrap(s);
  const auto& pts = track_.points();
  std::size_t i = 0;
  // Binary search over progress.
  std::size_t lo = 0, hi = pts.size();
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (track_.s(mid) <= s ? lo : hi) = mid;
  }
  i = lo;
  const std::size_t j = (i + 1) % pts.size();
  const double seg = (j == 0 ? track_.length() : track_.s(j)) - track_.s(i);
  const double t = (s - track_.s(i)) / seg;
  return (1 - t) * profile_[i] + t * profile_[j];
}

sim::VehicleControl CentrelineFollower::update(const FollowerInput& input) {
  const track::Projection pr =
      have_s_ ? track_.projectNear(input.position, last_s_, 60.0) : track_.project(input.position);
  last_s_ = pr.s;
  have_s_ = true;
  const double speed = std::max(0.0, input.speed);

  const double lookahead = std::max(options_.lookahead_min, options_.lookahead_time * speed);
  const Eigen::Vector2d target = track_.poseAt(pr.s + lookahead).position;
  const Eigen::Vector2d rel = target - input.position;
  const double alpha = track::wrapAngle(std::atan2(rel.y(), rel.x()) - input.yaw);
  const double distance = std::max(rel.norm(), 1e-3);
  const double curvature = 2.0 * std::sin(alpha) / distance;
  const double steer_angle = std::atan(options_.wheelbase * curvature) +
                             options_.yaw_rate_gain * (speed * curvature - input.yaw_rate);

  sim::VehicleControl control;
  control.steer = std::clamp(steer_angle / options_.max_steer_angle, -1.0, 1.0);
  const double wanted = targetSpeedAt(pr.s + speed * options_.speed_preview);
  const double effort = options_.speed_gain * (wanted - speed);
  const double lateral = speed * speed * std::abs(track_.curvatureAt(pr.s + lookahead * 0.5));
  const double used = std::min(1.0, lateral / (options_.lateral_accel * options_.grip_margin));
  const double budget = std::max(options_.min_corner_throttle, std::sqrt(1.0 - used * used));
  control.throttle = std::clamp(effort, 0.0, budget);
  control.brake = std::clamp(-effort, 0.0, 1.0);
  return control;
}

}  // namespace roar::control
