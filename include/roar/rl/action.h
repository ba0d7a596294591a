#pragma once
// The action of one car: ROAR_PY's vehicle action spec (roar_py_interface RoarPyVehicleAutoGearActor /
// ManualGearActor), keys sorted as a Gymnasium Dict sorts them:
//   brake Box(0, 1, (1,)), hand_brake Box(0, 1, (1,)) (engaged above 0.5), reverse MultiBinary(1),
//   steer Box(-1, 1, (1,)) (positive turns left: the opposite of CARLA's sign), throttle Box(0, 1, (1,)),
//   and with manual gears target_gear Discrete(forward gears, start=1).
#include "roar/rl/space.h"
#include "roar/vehicle/vehicle_control.h"

namespace roar::rl {

struct ActionOptions {
  bool manual_gears = false;  // the action chooses the gear (target_gear); otherwise the gearbox shifts itself
};

Space actionSpace(const ActionOptions& options, int forward_gears);

// The control an action asks for. Throws SpaceError naming the key for an action outside `space`.
vehicle::VehicleControl toControl(const Space& space, const Value& action);

// The action of a control (its fields clamped into the space): how a driver's controls read as actions.
Value toAction(const Space& space, const vehicle::VehicleControl& control);

}  // namespace roar::rl
