#include "roar/planning/vehicle_limits.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "roar/vehicle/powertrain.h"

namespace roar::planning {

double VehicleLimits::driveForce(double speed) const {
  if (drive_force.empty()) return 0.0;
  const double x = std::max(0.0, speed) / drive_force_step;
  const std::size_t i = static_cast<std::size_t>(x);
  if (i + 1 >= drive_force.size()) return drive_force.back();
  const double t = x - static_cast<double>(i);
  return (1 - t) * drive_force[i] + t * drive_force[i + 1];
}

double VehicleLimits::corneringSpeed(double curvature, double vertical_curvature) const {
  // m v^2 |kappa| = mu (m g + m v^2 kappa_v + k v^2)  =>  v^2 = mu m g / (m |kappa| - mu m kappa_v - mu k)
  double speed = max_speed;
  const double denominator =
      mass * std::abs(curvature) - friction * (mass * vertical_curvature + downforce_coefficient);
  if (denominator > 0) speed = std::min(speed, std::sqrt(friction * mass * gravity / denominator));
  // Over a crest: m g + m v^2 kappa_v + k v^2 >= kMinCrestLoad m g.
  const double lift = -mass * vertical_curvature - downforce_coefficient;
  if (lift > 0) speed = std::min(speed, std::sqrt((1.0 - kMinCrestLoad) * mass * gravity / lift));
  return speed;
}

double VehicleLimits::longitudinalGrip(double speed, double curvature) const {
  const double grip = gripForce(speed);
  const double lateral = mass * speed * speed * std::abs(curvature);
  if (lateral >= grip) return 0.0;
  return std::sqrt(grip * grip - lateral * lateral);
}

int VehicleLimits::gearAt(double speed) const {
  if (gear.empty()) return 1;
  const std::size_t i =
      std::min(gear.size() - 1, static_cast<std::size_t>(std::max(0.0, speed) / drive_force_step + 0.5));
  return gear[i];
}

VehicleLimits vehicleLimits(const vehicle::VehicleParams& params, double road_friction, double grip_use) {
  if (!(road_friction > 0) || !(grip_use > 0 && grip_use <= 1)) {
    throw std::invalid_argument("vehicle limits: road friction must be positive and grip_use in (0, 1]");
  }
  VehicleLimits limits;
  limits.mass = params.chassis.mass;
  limits.friction = road_friction * params.tyre.grip * grip_use;
  limits.drag_coefficient = 0.5 * params.aero.air_density * params.aero.drag_area;
  limits.downforce_coefficient = 0.5 * params.aero.air_density * params.aero.downforce_area;
  limits.rolling_resistance = params.tyre.rolling_resistance;
  limits.shift_time = params.gearbox.shift_time;
  limits.rotating_mass = 0.0;
  for (const auto& wheel : params.wheels)
    limits.rotating_mass += params.tyre.wheel_inertia / (wheel.radius * wheel.radius);
  double brake_torque = 0.0;
  for (const auto& wheel : params.wheels) {
    brake_torque += wheel.front ? params.brakes.max_torque_front : params.brakes.max_torque_rear;
  }
  const double radius = params.wheels[0].radius;
  limits.max_brake_force = brake_torque / radius;

  // Drive force F puts d_axle F on an axle that can carry c_axle mu N_axle; accelerating moves F h / L of
  // load from the front to the rear axle. The tighter axle bounds F.
  {
    const double mu = limits.friction, weight = limits.mass * limits.gravity;
    const double x_front = params.wheels[0].position.x(), x_rear = params.wheels[2].position.x();
    const double wheelbase = x_front - x_rear;
    const double front_load = weight * (params.chassis.centre_of_mass.x() - x_rear) / wheelbase;
    const double rear_load = weight - front_load;
    const double transfer = params.chassis.centre_of_mass.z() / wheelbase;  // load moved per N of drive force
    const double tc = params.traction_control ? 0.95 : 1.0;                 // traction control keeps below the peak
    const double d_front = params.front_drive_share, d_rear = 1.0 - d_front;
    const double c_front = tc, c_rear = tc * (params.traction_control ? params.rear_grip_share : 1.0);
    double most = 1e300;
    if (d_front > 0) most = std::min(most, c_front * mu * front_load / (d_front + c_front * mu * transfer));
    if (d_rear > 0 && d_rear > c_rear * mu * transfer) {
      most = std::min(most, c_rear * mu * rear_load / (d_rear - c_rear * mu * transfer));
    }
    limits.traction_share = std::clamp(most / (mu * weight), 0.0, 1.0);
  }

  // Full throttle in the gear the automatic gearbox's kickdown picks (Powertrain::strongestGear).
  vehicle::Powertrain engine(params);
  limits.drive_force.clear();
  limits.gear.clear();
  limits.max_speed = 0.0;
  for (double v = 0.0;; v += limits.drive_force_step) {
    const double wheel_rpm = v / radius * 60.0 / (2.0 * M_PI);
    const int best_gear = engine.strongestGear(wheel_rpm);
    const double best = best_gear > 0 ? engine.fullThrottleWheelTorque(best_gear, wheel_rpm) / radius : 0.0;
    limits.drive_force.push_back(best);
    limits.gear.push_back(std::max(1, best_gear));
    if (best <= limits.resistance(v) || v > 150.0) {
      limits.max_speed = v;
      break;
    }
  }
  return limits;
}

}  // namespace roar::planning
