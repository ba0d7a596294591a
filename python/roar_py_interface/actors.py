"""ROAR_PY's actors: anything with sensors that takes actions, and the vehicle's action specs.

The base class builds observations and their spaces from ``get_sensors()`` alone, so that a wrapper which
derives from ``RoarPyActor`` without calling its ``__init__`` and forwards every call to a wrapped vehicle
works as in ROAR_PY.
"""
import asyncio
import collections
import time
import typing

from . import spaces
from .sensors import RoarPySensor


def observation_keys(sensors: typing.Sequence[RoarPySensor]) -> typing.List[str]:
    """Each sensor's key in an observation: its name, or name_1, name_2, ... when names repeat (ROAR_PY's)."""
    counts = collections.Counter(s.name for s in sensors)
    seen: typing.Dict[str, int] = collections.defaultdict(int)
    keys = []
    for sensor in sensors:
        if counts[sensor.name] == 1:
            keys.append(sensor.name)
        else:
            seen[sensor.name] += 1
            keys.append(f"{sensor.name}_{seen[sensor.name]}")
    return keys


class RoarPyActor:
    def __init__(self, name: str, control_timestep: float = 0.05, force_real_control_timestep: bool = False):
        self.name = name
        self.control_timestep = control_timestep
        self.force_real_control_timestep = force_real_control_timestep
        self._last_action_t = 0.0

    def get_sensors(self) -> typing.Iterable[RoarPySensor]:
        raise NotImplementedError()

    def get_action_spec(self) -> spaces.Space:
        raise NotImplementedError()

    async def _apply_action(self, action: typing.Any) -> bool:
        raise NotImplementedError()

    def close(self):
        raise NotImplementedError()

    def is_closed(self) -> bool:
        raise NotImplementedError()

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - nothing may escape a finaliser
            pass

    async def _pace(self):
        if not getattr(self, "force_real_control_timestep", False):
            return
        step = getattr(self, "control_timestep", 0.0)
        last = getattr(self, "_last_action_t", 0.0)
        now = time.time()
        if now - last < step:
            await asyncio.sleep(step - (now - last))
            self._last_action_t = last + step
        else:
            self._last_action_t = now

    async def apply_action(self, action: typing.Any) -> bool:
        await self._pace()
        return await self._apply_action(action)

    def get_gym_observation_spec(self) -> spaces.Space:
        sensors = list(self.get_sensors())
        return spaces.Dict(collections.OrderedDict(
            (key, s.get_gym_observation_spec()) for key, s in zip(observation_keys(sensors), sensors)))

    async def receive_observation(self) -> typing.Dict[str, typing.Any]:
        sensors = list(self.get_sensors())
        readings = await asyncio.gather(*(s.receive_observation() for s in sensors))
        return dict(zip(observation_keys(sensors), readings))

    def get_last_observation(self) -> typing.Optional[typing.Dict[str, typing.Any]]:
        sensors = list(self.get_sensors())
        out = {}
        for key, sensor in zip(observation_keys(sensors), sensors):
            obs = sensor.get_last_observation()
            if obs is None:
                return None
            out[key] = obs
        return out

    def get_last_gym_observation(self) -> typing.Optional[typing.Dict[str, typing.Any]]:
        obs = self.get_last_observation()
        return None if obs is None else self.convert_obs_to_gym_obs(obs)

    def convert_obs_to_gym_obs(self, observation: typing.Dict[str, typing.Any]) -> typing.Dict[str, typing.Any]:
        sensors = list(self.get_sensors())
        return {key: s.convert_obs_to_gym_obs(observation[key]) for key, s in zip(observation_keys(sensors), sensors)}


class RoarPyResettableActor:
    async def _reset(self) -> None:
        raise NotImplementedError()

    async def reset(self) -> None:
        if isinstance(self, RoarPyActor):
            await self._pace()
        await self._reset()


def vehicle_action_spec(auto_gear: bool = True, num_gears: int = 6) -> spaces.Dict:
    """ROAR_PY's vehicle actions: throttle, steer (positive right), brake, hand_brake, reverse, and
    target_gear for a manual gearbox."""
    spec = collections.OrderedDict([
        ("throttle", spaces.Box(low=0.0, high=1.0, shape=(1,))),
        ("steer", spaces.Box(low=-1.0, high=1.0, shape=(1,))),
        ("brake", spaces.Box(low=0.0, high=1.0, shape=(1,))),
        ("hand_brake", spaces.Box(low=0.0, high=1.0, shape=(1,))),
        ("reverse", spaces.MultiBinary(1)),
    ])
    if not auto_gear:
        spec["target_gear"] = spaces.Discrete(num_gears, start=1)
    return spaces.Dict(spec)


class RoarPyBaseVehicle(RoarPyActor):
    """A car: ROAR_PY's action spec and the state a backend reads."""

    auto_gear = True
    num_gears = 6

    def get_action_spec(self) -> spaces.Space:
        return vehicle_action_spec(getattr(self, "auto_gear", True), getattr(self, "num_gears", 6))
