#include "roar/vehicle/vehicle_control.h"

#include <algorithm>
#include <cmath>

namespace roar::vehicle {

VehicleControl parkedControl() {
  VehicleControl c;
  c.brake = 1.0;
  c.hand_brake = true;
  return c;
}

CheckedControl checkControl(const VehicleControl& control, int forward_gears) {
  CheckedControl out;
  out.control = control;
  auto check = [&](double* value, const char* field, double lo, double hi) {
    if (!std::isfinite(*value)) {
      out.rejected = true;
      out.problems.push_back(std::string(field) + " is " + (std::isnan(*value) ? "NaN" : "infinite"));
    } else if (*value < lo || *value > hi) {
      out.problems.push_back(std::string(field) + " " + std::to_string(*value) + " clamped to [" + std::to_string(lo) +
                             ", " + std::to_string(hi) + "]");
      *value = std::clamp(*value, lo, hi);
    }
  };
  check(&out.control.throttle, "throttle", 0.0, 1.0);
  check(&out.control.steer, "steer", -1.0, 1.0);
  check(&out.control.brake, "brake", 0.0, 1.0);
  if (control.manual_gear_shift && (control.gear < -1 || control.gear > forward_gears)) {
    out.rejected = true;
    out.problems.push_back("gear " + std::to_string(control.gear) + " does not exist (-1.." +
                           std::to_string(forward_gears) + ")");
  }
  return out;
}

}  // namespace roar::vehicle
