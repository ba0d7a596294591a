#include "roar/sim/safe_stop.h"

#include <algorithm>
#include <cmath>

#include "roar/track/heading.h"

namespace roar::sim {

vehicle::VehicleControl safeStopControl(const track::Track& track, const vehicle::VehicleState& state,
                                        const vehicle::VehicleParams& params, const SafeStopOptions& options) {
  if (std::abs(state.forward_speed) < options.stopped_speed) return vehicle::parkedControl();
  const Eigen::Vector2d position = state.pose.position.head<2>();
  const track::Projection here = track.projectAtHeight(state.pose.position);  // under a bridge, its own road
  const double lookahead = std::max(options.min_lookahead, options.lookahead_time * std::abs(state.forward_speed));
  const track::TrackPose ahead = track.poseAt(here.s + lookahead);
  // The car's lateral place, kept inside the edges (the middle of a road too narrow for the clearance).
  const double left = ahead.width_left - options.edge_clearance, right = ahead.width_right - options.edge_clearance;
  const double lateral =
      left + right > 0 ? std::clamp(here.lateral, -right, left) : 0.5 * (ahead.width_left - ahead.width_right);
  const Eigen::Vector2d target = ahead.position + lateral * track::leftOf(ahead.heading);
  // Pure pursuit from the rear axle's direction of travel (base_link's heading).
  const double heading = track::yawOf(state.pose.orientation);
  const Eigen::Vector2d to = target - position;
  double alpha = std::atan2(to.y(), to.x()) - heading;
  alpha = std::atan2(std::sin(alpha), std::cos(alpha));
  const double wheel_angle = std::atan2(2.0 * params.wheelbase() * std::sin(alpha), std::max(1.0, to.norm()));
  vehicle::VehicleControl control;
  control.steer = std::clamp(wheel_angle / params.steering.max_angle, -1.0, 1.0);
  control.brake = options.brake;
  return control;
}

}  // namespace roar::sim
