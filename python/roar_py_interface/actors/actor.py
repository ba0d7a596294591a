"""ROAR_PY's actors: anything with sensors that takes actions, and the vehicles' action specs.

Observations and their spaces are built from ``get_sensors()`` alone, so that a wrapper which derives from
``RoarPyActor`` without calling its ``__init__`` and forwards every call to a wrapped vehicle (the
competition starter kit's ``RoarCompetitionAgentWrapper``) works as in ROAR_PY.
"""
import asyncio
import collections
import time
import typing

from .. import spaces
from ..base import RoarPySensor


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


def _free_numbered_name(taken, new_name: str, counter: int) -> str:
    while f"{new_name}_{counter}" in taken:
        counter += 1
    return f"{new_name}_{counter}"


def propose_name_and_modify_dict(diction: dict, new_name: str, counter: int = 0) -> str:
    """ROAR_PY's key for another sensor named new_name in diction: new_name if free; else the one there
    becomes new_name_1 (moved in diction) and this one new_name_2, _3, ..."""
    if counter >= 1:
        return _free_numbered_name(diction, new_name, counter)
    if f"{new_name}_1" not in diction:
        if new_name not in diction:
            return new_name
        diction[f"{new_name}_1"] = diction.pop(new_name)
    return _free_numbered_name(diction, new_name, 2)


def propose_name_and_modify_list(list_of_names: list, new_name: str, counter: int = 0) -> str:
    """propose_name_and_modify_dict for a list of keys: a name moved to new_name_1 goes to the list's end."""
    if counter >= 1:
        return _free_numbered_name(list_of_names, new_name, counter)
    if f"{new_name}_1" not in list_of_names:
        if new_name not in list_of_names:
            return new_name
        list_of_names.remove(new_name)
        list_of_names.append(f"{new_name}_1")
    return _free_numbered_name(list_of_names, new_name, 2)


class RoarPyObservation(dict):
    """An actor's observation: a dict of each sensor's reading by its key. A sensor left with the default
    name of ROAR_PY's CARLA backend (carla_camera, carla_lidar_sensor, ...) can also be read by its kind
    (camera, lidar), as ROAR_PY's documentation reads it; keys and iteration are the real ones."""

    def __missing__(self, key):
        if isinstance(key, str):
            for alias in (f"carla_{key}", f"carla_{key}_sensor"):
                if dict.__contains__(self, alias):
                    return self[alias]
        raise KeyError(key)


class _Pending:
    """A gym value not converted yet: the conversion, run on the first read of its key."""

    __slots__ = ("convert",)

    def __init__(self, convert):
        self.convert = convert


class RoarPyGymObservation(dict):
    """An actor's gym observation: a dict of each sensor's gym value by its key, each converted when its key
    is first read (a camera's frame is rendered only then), so that a program keeping some keys, as
    gymnasium's FilterObservation does, pays for those alone (test_roar_py_interface
    test_a_gym_observation_converts_only_the_keys_read). Every way of reading a value converts it: indexing,
    get, items, values, pop, dict(...), {**...}, ==, pickling."""

    def __getitem__(self, key):
        value = dict.__getitem__(self, key)
        if type(value) is _Pending:
            value = value.convert()
            dict.__setitem__(self, key, value)
        return value

    def __iter__(self):  # a Python-level __iter__ makes dict(), {**} and update() read through __getitem__
        return dict.__iter__(self)

    def get(self, key, default=None):
        return self[key] if key in self else default

    def items(self):
        return [(k, self[k]) for k in self.keys()]

    def values(self):
        return [self[k] for k in self.keys()]

    def pop(self, key, *default):
        if key not in self:
            return dict.pop(self, key, *default)
        value = self[key]
        dict.__delitem__(self, key)
        return value

    def popitem(self):
        key = next(reversed(self.keys()))
        return key, self.pop(key)

    def setdefault(self, key, default=None):
        if key not in self:
            dict.__setitem__(self, key, default)
        return self[key]

    def copy(self):
        """A shallow copy sharing the conversions not yet run (each runs once per copy that reads it)."""
        return type(self)(dict.items(self))

    def __eq__(self, other):
        return dict(self.items()) == other

    __hash__ = None

    def __ne__(self, other):
        return not self == other

    def __repr__(self):
        return repr(dict(self.items()))

    def __reduce__(self):
        return dict, (self.items(),)


async def _wait_for_control_timestep(actor) -> None:
    """ROAR_PY's force_real_control_timestep: at most one action (or reset) per control_timestep of wall time."""
    if not getattr(actor, "force_real_control_timestep", False):
        return
    step = actor.control_timestep
    last = getattr(actor, "_last_action_t", 0.0)
    now = time.time()
    if now - last < step:
        await asyncio.sleep(step - (now - last))
        actor._last_action_t = last + step
    else:
        actor._last_action_t = now


class RoarPyActor:
    def __init__(self, name: str, control_timestep: float = 0.05, force_real_control_timestep: bool = False):
        self.name = name
        self._control_timestep = control_timestep
        self._force_real_control_timestep = force_real_control_timestep
        self._last_action_t = 0.0
        self._last_obs = None

    @property
    def control_timestep(self) -> float:
        return self._control_timestep

    @control_timestep.setter
    def control_timestep(self, value: float):
        self._control_timestep = value

    @property
    def force_real_control_timestep(self) -> bool:
        return self._force_real_control_timestep

    @force_real_control_timestep.setter
    def force_real_control_timestep(self, value: bool):
        self._force_real_control_timestep = value

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
            if not self.is_closed():
                self.close()
        except Exception:  # noqa: BLE001 - nothing may escape a finaliser
            pass

    async def apply_action(self, action: typing.Any) -> bool:
        await _wait_for_control_timestep(self)
        return await self._apply_action(action)

    def get_gym_observation_spec(self) -> spaces.Space:
        sensors = list(self.get_sensors())
        # A plain dict, which gymnasium's Dict sorts by key as over ROAR_PY: flattened observations are laid
        # out as over CARLA (test_roar_py_interface test_an_observation_space_is_sorted_by_key_as_roar_pys).
        return spaces.Dict({key: s.get_gym_observation_spec() for key, s in zip(observation_keys(sensors), sensors)})

    async def receive_observation(self) -> typing.Dict[str, typing.Any]:
        sensors = list(self.get_sensors())
        readings = await asyncio.gather(*(s.receive_observation() for s in sensors))
        self._last_obs = RoarPyObservation(zip(observation_keys(sensors), readings))
        return self._last_obs

    def get_last_observation(self) -> typing.Optional[typing.Dict[str, typing.Any]]:
        return getattr(self, "_last_obs", None)

    def get_last_gym_observation(self) -> typing.Optional[typing.Dict[str, typing.Any]]:
        obs = self.get_last_observation()
        return None if obs is None else self.convert_obs_to_gym_obs(obs)

    def convert_obs_to_gym_obs(self, observation: typing.Dict[str, typing.Any]) -> typing.Dict[str, typing.Any]:
        sensors = list(self.get_sensors())

        def pending(sensor, key):
            reading = observation[key]
            return _Pending(lambda: sensor.convert_obs_to_gym_obs(reading))

        return RoarPyGymObservation((key, pending(s, key)) for key, s in zip(observation_keys(sensors), sensors))


class RoarPyResettableActor:
    async def __reset(self) -> None:
        # ROAR_PY's hook, name-mangled as ROAR_PY's (_RoarPyResettableActor__reset); roar_ros's actors give _reset.
        await self._reset()

    async def _reset(self) -> None:
        raise NotImplementedError()

    async def reset(self) -> None:
        """Puts the actor back to its initial state."""
        if isinstance(self, RoarPyActor):
            await _wait_for_control_timestep(self)
        await self.__reset()
