"""ROAR_PY's vehicles: the action spaces of cars with an automatic or a manual gearbox."""
from .. import spaces
from .actor import RoarPyActor


def vehicle_action_spec(auto_gear: bool = True, num_gears: int = 6) -> spaces.Dict:
    """ROAR_PY's vehicle actions: throttle, steer (positive right), brake, hand_brake, reverse, and
    target_gear for a manual gearbox. A plain dict as ROAR_PY's, so the Dict space sorts its keys (brake
    first) and flattened actions have ROAR_PY's layout (test_roar_py_interface
    test_vehicle_action_spec_flattens_in_roar_pys_order)."""
    spec = {
        "throttle": spaces.Box(low=0.0, high=1.0, shape=(1,)),
        "steer": spaces.Box(low=-1.0, high=1.0, shape=(1,)),
        "brake": spaces.Box(low=0.0, high=1.0, shape=(1,)),
        "hand_brake": spaces.Box(low=0.0, high=1.0, shape=(1,)),
        "reverse": spaces.MultiBinary(1),
    }
    if not auto_gear:
        spec["target_gear"] = spaces.Discrete(num_gears, start=1)
    return spaces.Dict(spec)


class RoarPyVehicleAutoGearActor(RoarPyActor):
    def __init__(self, name: str = "vehicle_autogear", control_timestep: float = 0.05,
                 force_real_control_timestep: bool = False):
        super().__init__(name=name, control_timestep=control_timestep,
                         force_real_control_timestep=force_real_control_timestep)

    def get_action_spec(self) -> spaces.Space:
        return vehicle_action_spec(auto_gear=True)


class RoarPyVehicleManualGearActor(RoarPyActor):
    def __init__(self, name: str = "vehicle_manualgear", control_timestep: float = 0.05,
                 force_real_control_timestep: bool = False, num_gears: int = 6):
        super().__init__(name=name, control_timestep=control_timestep,
                         force_real_control_timestep=force_real_control_timestep)
        self.num_gears = num_gears

    def get_action_spec(self) -> spaces.Space:
        return vehicle_action_spec(auto_gear=False, num_gears=self.num_gears)


class RoarPyBaseVehicle(RoarPyActor):
    """A backend's car: ROAR_PY's action spec for its gearbox (auto_gear, num_gears)."""

    auto_gear = True
    num_gears = 6

    def get_action_spec(self) -> spaces.Space:
        return vehicle_action_spec(getattr(self, "auto_gear", True), getattr(self, "num_gears", 6))
