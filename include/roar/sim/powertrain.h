#pragma once
// Engine with a full-throttle torque curve and engine braking, a gearbox with automatic shifting (with a
// torque gap while shifting) or manual selection, and open differentials. The clutch is modelled only as
// slipping below idle, so the car can pull away from rest.
#include "roar/sim/vehicle_params.h"

namespace roar::sim {

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
  void reset();

 private:
  double ratio(int gear) const;

  EngineParams engine_;
  GearboxParams gearbox_;
  int gear_ = 1;
  double shift_timer_ = 0.0;
  double rpm_ = 0.0;
};

}  // namespace roar::sim
