#pragma once
// Tracks a racing trajectory. Lateral: Stanley (front-axle cross-track and heading error with the line's
// curvature as feed-forward) or pure pursuit (speed-dependent lookahead), each with yaw-rate damping.
// Longitudinal: feed-forward of the profile's acceleration through the car's drive and brake forces, plus
// feedback on the speed error.
#include <Eigen/Core>

#include "roar/planning/trajectory.h"
#include "roar/planning/vehicle_limits.h"
#include "roar/vehicle/steering_curve.h"
#include "roar/vehicle/vehicle_control.h"

namespace roar::control {

enum class LateralMethod { kStanley, kPurePursuit };

struct TrackerOptions {
  // Pure pursuit by measurement (roar_bench, 3 circuits): the same lap times as Stanley within 0.4%, and
  // 20-30% less tracking error.
  LateralMethod lateral = LateralMethod::kPurePursuit;
  double wheelbase = 2.875;               // m
  double front_axle = 2.875;              // m ahead of base_link
  double stanley_gain = 2.5;              // 1/s: cross-track gain (rad of steering per m of error at 1 m/s)
  double stanley_softening = 2.0;         // m/s added to the speed under the cross-track term (gentle when slow)
  double steer_preview = 0.1;             // s: the line's curvature is read this far ahead (steering lag)
  double max_steer_angle = 0.61;          // rad at steer = 1
  vehicle::SteeringCurve steering_curve;  // share of max_steer_angle by speed (the car's); empty: all of it
  double lookahead_min = 6.0;             // m
  double lookahead_time = 0.3;            // s: lookahead = max(min, time * speed)
  // Steering added per rad/s of yaw rate missing from what the pursuit arc asks (v * kappa): pure pursuit
  // alone weaves when braking hard from high speed.
  double yaw_rate_gain = 0.1;  // rad per rad/s
  double speed_gain = 1.0;     // throttle or brake per m/s of speed error
  double speed_preview = 0.1;  // s: the profile is read this far ahead to cover the car's response
  // Throttle or brake per m/s of speed error on top of a recorded lap's own pedal (its speeds already hold the
  // car's response, so they are read where the car is).
  double recorded_speed_gain = 0.1;
  double max_speed = 0.0;  // m/s cap on the profile; 0: none
  // m: a car further than this from its trajectory is braked to a stop rather than steered at it (a window
  // of the map before a switch, or of a car somewhere else); 0: never. Wider than any road, so that a car
  // that has left the road is still brought back.
  double max_distance = 15.0;
};

struct TrackerInput {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // base_link in the map frame
  double yaw = 0.0;
  double speed = 0.0;          // m/s forward
  double yaw_rate = 0.0;       // rad/s counter-clockwise
  double lateral_speed = 0.0;  // m/s to the left, base_link frame (a car sliding: its speed is not all forward)
};

class TrajectoryTracker {
 public:
  // Throws std::invalid_argument for a non-positive length, angle or gain.
  TrajectoryTracker(const TrackerOptions& options, const planning::VehicleLimits& limits);

  // Validates (planning::TrajectoryError) and takes the trajectory; the old one stays on error.
  void setTrajectory(planning::Trajectory trajectory);
  bool hasTrajectory() const { return !trajectory_.points.empty(); }
  const planning::Trajectory& trajectory() const { return trajectory_; }

  // Without a trajectory: brakes.
  vehicle::VehicleControl update(const TrackerInput& input);

  double lateralError() const { return lateral_error_; }  // m, positive: the car is left of the line
  double progress() const { return progress_; }           // s on the trajectory
  // m from the car to the nearest point of its trajectory at the last update; beyond max_distance the
  // update braked.
  double distance() const { return distance_; }
  bool tooFar() const { return options_.max_distance > 0 && distance_ > options_.max_distance; }

  const TrackerOptions& options() const { return options_; }
  void setOptions(const TrackerOptions& options);

 private:
  double steeringAngle(const TrackerInput& in, double s, double speed) const;

  TrackerOptions options_;
  planning::VehicleLimits limits_;
  planning::Trajectory trajectory_;
  long hint_ = -1;
  double lateral_error_ = 0.0, target_speed_ = 0.0, progress_ = 0.0, distance_ = 0.0;
};

}  // namespace roar::control
