#pragma once
#include <string>
#include <vector>

namespace roar::vehicle {

// Driver inputs, the fields and ranges of ROAR_PY's vehicle action spec. Steer is positive to the left.
struct VehicleControl {
  double throttle = 0.0;  // 0..1
  double steer = 0.0;     // -1..1
  double brake = 0.0;     // 0..1
  bool hand_brake = false;
  bool reverse = false;
  bool manual_gear_shift = false;
  int gear = 0;  // with manual_gear_shift: -1 reverse, 0 neutral, 1..N
};

// The control the car is left with before any driver speaks, and when its driver falls silent.
VehicleControl parkedControl();

struct CheckedControl {
  VehicleControl control;             // clamped into range; meaningless when rejected
  bool rejected = false;              // a field was NaN or infinite, or the gear does not exist
  std::vector<std::string> problems;  // one line per field that was rejected or clamped
};

// Non-finite fields reject the whole control (physics never sees them); out-of-range fields are clamped.
CheckedControl checkControl(const VehicleControl& control, int forward_gears);

}  // namespace roar::vehicle
