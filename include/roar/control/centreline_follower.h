#pragma once
// A first driver: follows the track's centre line with pure pursuit (speed-dependent lookahead) and holds a
// speed profile computed from the centre line's curvature (lateral limit) and braking distance.
// The racing stack's planner and controller replace it with a racing line.
#include <Eigen/Core>
#include <vector>

#include "roar/sim/vehicle_control.h"
#include "roar/track/track.h"

namespace roar::control {

struct FollowerOptions {
  double wheelbase = 2.875;        // m
  double max_steer_angle = 0.61;   // rad at steer = 1
  double lookahead_min = 6.0;      // m
  double lookahead_time = 0.5;     // s: lookahead = max(min, time * speed)
  // Yaw damping: steering added per rad/s of yaw rate missing from what the pursuit curve asks (v * kappa).
  // Pure pursuit alone weaves when braking hard from high speed.
  double yaw_rate_gain = 0.1;      // rad of steering per rad/s
  double lateral_accel = 7.0;      // m/s^2 allowed in corners
  double braking_decel = 7.0;      // m/s^2 planned for braking
  double max_speed = 60.0;         // m/s
  double curvature_window = 10.0;  // m: curvature is averaged over +- this distance
  double speed_gain = 0.4;         // throttle or brake per m/s of speed error
  double speed_preview = 0.3;      // s: the target is read this far ahead to cover the car's response
  // Throttle is capped where cornering already uses most of the grip (friction circle): at a lateral
  // acceleration of lateral_accel * grip_margin the cap reaches its floor of min_corner_throttle.
  double grip_margin = 1.2;
  double min_corner_throttle = 0.2;
};

struct FollowerInput {
  Eigen::Vector2d position;  // base_link in the map frame
  double yaw = 0.0;
  double speed = 0.0;        // m/s, forward
  double yaw_rate = 0.0;     // rad/s, counter-clockwise
};

class CentrelineFollower {
 public:
  // Throws std::invalid_argument for non-positive limits.
  CentrelineFollower(const track::Track& track, const FollowerOptions& options);

  sim::VehicleControl update(const FollowerInput& input);
  double targetSpeedAt(double s) const;
  double lastProgress() const { return last_s_; }

 private:
  const track::Track& track_;
  FollowerOptions options_;
  std::vector<double> profile_;  // target speed at each centre-line point
  double last_s_ = 0.0;
  bool have_s_ = false;
};

}  // namespace roar::control
