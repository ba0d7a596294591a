#pragma once
// What a car can do at the limit, for planning: grip from the friction circle with downforce, drive force
// per speed from the engine's torque curve and the gearbox, braking force, drag. Derived from the same
// VehicleParams the simulator reads, so planner and simulator share one source of truth.
#include <vector>

#include "roar/vehicle/vehicle_params.h"

namespace roar::planning {

struct VehicleLimits {
  double mass = 1850.0;                 // kg
  double rotating_mass = 40.0;          // kg: the wheels' inertia as mass at the road (sum I / r^2)
  double shift_time = 0.15;             // s without drive while the gearbox shifts
  double gravity = 9.81;                // m/s^2
  double friction = 1.0;                // tyre-road friction the plan uses (road friction x tyre grip x grip_use)
  double drag_coefficient = 0.35;       // N per (m/s)^2: 0.5 rho CdA
  double downforce_coefficient = 0.15;  // N per (m/s)^2: 0.5 rho ClA
  double rolling_resistance = 0.012;    // share of the weight
  double max_brake_force = 30000.0;     // N at the road, all wheels
  // Share of the grip the driven wheels can turn into drive force: the drive split between the axles,
  // the load on each (with weight transfer under acceleration) and traction control's limit per wheel.
  double traction_share = 1.0;
  double max_speed = 80.0;          // m/s: top speed (drive force = resistance) or gearing
  double drive_force_step = 0.5;    // m/s between entries of drive_force
  std::vector<double> drive_force;  // N at the road at full throttle in the best gear, per speed step
  std::vector<int> gear;            // that gear (1 = first), per speed step

  double driveForce(double speed) const;
  int gearAt(double speed) const;
  double effectiveMass() const { return mass + rotating_mass; }
  double dragForce(double speed) const { return drag_coefficient * speed * speed; }
  double resistance(double speed) const { return dragForce(speed) + rolling_resistance * mass * gravity; }
  // Total tyre force the road can take: friction x (weight + downforce).
  double gripForce(double speed) const { return friction * (mass * gravity + downforce_coefficient * speed * speed); }
  // Highest speed on a curvature (1/m) where the grip carries the centripetal force alone. Over a crest
  // (`vertical_curvature`, 1/m in the vertical plane, negative over a crest) the car weighs less: it
  // corners slower there, and goes no faster than keeps kMinCrestLoad of its weight on the tyres
  // (SpeedProfile.ACrestSlowsTheCornerOnItAndTheCarKeepsItsWheelsDown).
  double corneringSpeed(double curvature, double vertical_curvature = 0.0) const;
  static constexpr double kMinCrestLoad = 0.6;
  // Longitudinal force left once the cornering force m v^2 kappa is taken from the friction circle.
  double longitudinalGrip(double speed, double curvature) const;
};

// `road_friction` is the track's; `grip_use` (0, 1] the share of it the plan dares to use, which also
// covers what the tyre model loses to load sensitivity and weight transfer.
VehicleLimits vehicleLimits(const vehicle::VehicleParams& params, double road_friction, double grip_use);

}  // namespace roar::planning
