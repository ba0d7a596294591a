#pragma once
// Engine with a full-throttle torque curve and engine braking, a gearbox with automatic shifting (with a
// torque gap while shifting, and kickdown to the strongest gear at full throttle, not back straight after a
// shift up unless the car has slowed) or manual selection, and
// open or limited-slip differentials (driveShares). The clutch slips below idle, so the car can pull away from rest,
// and, for a car that stands in neutral after it is put down (GearboxParams::engage_time), while it takes up the engine
// it let rev: the engine then turns on its own inertia until the clutch has brought it down to the wheels' speed. The
// torque follows the pedal with the engine's response time.
#include <array>

#include "roar/vehicle/vehicle_params.h"

namespace roar::vehicle {

// Each wheel's share of the drive torque (front left, front right, rear left, rear right; they sum to 1) for
// the wheels' angular speeds (rad/s): the front axle's share `front_share`, split as the differentials do.
std::array<double, 4> driveShares(const DifferentialParams& differential, double front_share,
                                  const std::array<double, 4>& wheel_omega);

struct DriveRequest {
  double throttle = 0.0;
  bool reverse = false;
  bool manual = false;
  int gear = 0;  // with manual
};

class Powertrain {
 public:
  explicit Powertrain(const VehicleParams& params);

  // Advances the gearbox by dt and returns the drive torque at the wheels (N m, summed over driven wheels,
  // positive forward) for the driven wheels' mean angular speed (rad/s).
  double update(const DriveRequest& request, double driven_wheel_omega, double dt);
  // True while a car put down stands in neutral, waiting to engage its first gear.
  bool standing() const { return standing_; }

  int gear() const { return gear_; }
  double engineRpm() const { return rpm_; }
  double engineTorqueAt(double rpm) const;  // full throttle, N m
  // The forward gear (1 = first) with the most wheel torque at full throttle for the driven wheels' speed
  // (rpm), among those whose engine speed stays `headroom_rpm` below the shift-up rpm (the top gear: below
  // the redline); 0 when none does. The gear the planner assumes and the one kickdown picks.
  int strongestGear(double wheel_rpm, double headroom_rpm = 0.0) const;
  // Wheel torque (N m, all driven wheels) at full throttle in a forward gear; below idle the clutch slips
  // and the engine gives its idle torque.
  double fullThrottleWheelTorque(int gear, double wheel_rpm) const;
  // In first gear at idle, the pedal's lag at rest; `put_down` (a car just spawned): standing in neutral
  // first, when the gearbox has an engage_time (CARLA's cars after they are spawned, not after they are moved).
  void reset(bool put_down);
  // In gear, the clutch closed and the torque settled at this throttle: a car set moving.
  void settle(double throttle);

 private:
  double ratio(int gear) const;
  // The engine's own torque at its speed now and this throttle (none past the redline).
  double ownTorque(double throttle) const;
  // A substep of the stand in neutral, the engine revving free: true while it lasts.
  bool standInNeutral(double throttle, double dt);
  // A substep of the slipping clutch after the stand: true, with the drive torque at the wheels, while it
  // slips; false once engine and wheels turn together.
  bool slipClutch(double throttle, double wheel_rpm, double dt, double* wheel_torque);

  EngineParams engine_;
  GearboxParams gearbox_;
  int gear_ = 1;
  double shift_timer_ = 0.0;
  double since_upshift_ = 0.0;      // s since the last automatic shift up
  double upshift_wheel_rpm_ = 0.0;  // the driven wheels' speed then
  bool floored_since_upshift_ = false;
  double rpm_ = 0.0;
  double throttle_level_ = 0.0;  // the pedal as the torque follows it (EngineParams::response_time)
  // Standing in neutral after it is put down, until engage_time after the first throttle (infinite until then).
  bool standing_ = false;
  double engage_timer_ = 0.0;
  bool clutch_slipping_ = false;
  double engine_omega_ = 0.0;  // rad/s, the engine's own speed while it is not locked to the wheels
};

}  // namespace roar::vehicle
