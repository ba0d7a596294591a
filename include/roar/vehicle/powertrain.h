#pragma once
// Engine with a full-throttle torque curve and engine braking, a gearbox with automatic shifting (with a
// torque gap while shifting, and kickdown to the strongest gear at full throttle, not back straight after a
// shift up unless the car has slowed) or manual selection, and
// open differentials. The clutch is modelled only as slipping below idle, so the car can pull away from rest.
#include "roar/vehicle/vehicle_params.h"

namespace roar::vehicle {

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
  void reset();

 private:
  double ratio(int gear) const;

  EngineParams engine_;
  GearboxParams gearbox_;
  int gear_ = 1;
  double shift_timer_ = 0.0;
  double since_upshift_ = 0.0;      // s since the last automatic shift up
  double upshift_wheel_rpm_ = 0.0;  // the driven wheels' speed then
  bool floored_since_upshift_ = false;
  double rpm_ = 0.0;
};

}  // namespace roar::vehicle
