"""ROAR_PY's wrappers: an object standing for another (its public attributes forwarded), the actor, sensor
and world wrappers, a wrapper that filters an actor's sensors, and the thread-safe and add-item wrappers
ROAR_PY's remote server builds on (``roar_py_thread_sync``, ``roar_py_append_item``,
``roar_py_remove_item`` mark a backend's methods)."""
import functools
import threading
import typing

from .. import spaces
from ..actors import RoarPyActor
from ..base import RoarPySensor
from ..worlds import RoarPyWaypoint, RoarPyWorld

_Wrapped = typing.TypeVar("_Wrapped")


class RoarPyWrapper(typing.Generic[_Wrapped]):
    def __init__(self, wrapped_object: typing.Union[_Wrapped, "RoarPyWrapper[_Wrapped]"], wrapper_name: str):
        self._wrapped_object = wrapped_object
        self._wrapper_name = wrapper_name

    def __getattr__(self, name: str) -> typing.Any:
        if name.startswith("_"):
            raise AttributeError(f"Cannot access private attribute '{name}' through a wrapper")
        return getattr(self._wrapped_object, name)

    def __str__(self) -> str:
        return self._wrapper_name + "(" + str(self._wrapped_object) + ")"

    @property
    def unwrapped(self) -> _Wrapped:
        if isinstance(self._wrapped_object, RoarPyWrapper):
            return self._wrapped_object.unwrapped
        return self._wrapped_object


class RoarPyActorWrapper(RoarPyWrapper[RoarPyActor], RoarPyActor):
    def __init__(self, wrapped_object: typing.Union[RoarPyActor, RoarPyWrapper[RoarPyActor]],
                 wrapper_name: str = "RoarPyActorWrapper"):
        RoarPyWrapper.__init__(self, wrapped_object, wrapper_name)
        self._last_action_t = 0.0
        self._last_obs = None

    @property
    def control_timestep(self) -> float:
        return self._wrapped_object.control_timestep

    @control_timestep.setter
    def control_timestep(self, value: float):
        self._wrapped_object.control_timestep = value

    @property
    def force_real_control_timestep(self) -> bool:
        return self._wrapped_object.force_real_control_timestep

    @force_real_control_timestep.setter
    def force_real_control_timestep(self, value: bool):
        self._wrapped_object.force_real_control_timestep = value

    @property
    def name(self) -> str:
        return self._wrapped_object.name

    @name.setter
    def name(self, value: str):
        self._wrapped_object.name = value

    def get_sensors(self) -> typing.Iterable[RoarPySensor]:
        return self._wrapped_object.get_sensors()

    def get_action_spec(self) -> spaces.Space:
        return self._wrapped_object.get_action_spec()

    async def _apply_action(self, action: typing.Any) -> bool:
        return await self._wrapped_object._apply_action(action)

    def close(self):
        self._wrapped_object.close()

    def is_closed(self) -> bool:
        return self._wrapped_object.is_closed()

    def __del__(self):
        pass  # the wrapped actor closes itself

    async def apply_action(self, action: typing.Any) -> bool:
        return await self._wrapped_object.apply_action(action)

    # Observations and their spaces are RoarPyActor's, built from this wrapper's get_sensors(), as ROAR_PY's
    # wrapper inherits them: a wrapper that shows other sensors observes those (RoarPyActorSensorFilterWrapper).


_SensorObsT = typing.TypeVar("_SensorObsT")


class RoarPySensorWrapper(RoarPyWrapper[RoarPySensor[_SensorObsT]], RoarPySensor[_SensorObsT]):
    def __init__(self, wrapped_object: typing.Union[RoarPySensor[_SensorObsT], RoarPyWrapper],
                 wrapper_name: str = "RoarPySensorWrapper"):
        RoarPyWrapper.__init__(self, wrapped_object, wrapper_name)

    @property
    def sensordata_type(self) -> typing.Type:
        return self._wrapped_object.sensordata_type

    @property
    def control_timestep(self) -> float:
        return self._wrapped_object.control_timestep

    @control_timestep.setter
    def control_timestep(self, value: float):
        self._wrapped_object.control_timestep = value

    @property
    def name(self) -> str:
        return self._wrapped_object.name

    @name.setter
    def name(self, value: str):
        self._wrapped_object.name = value

    def get_gym_observation_spec(self) -> spaces.Space:
        return self._wrapped_object.get_gym_observation_spec()

    async def receive_observation(self) -> _SensorObsT:
        return await self._wrapped_object.receive_observation()

    def get_last_observation(self) -> typing.Optional[_SensorObsT]:
        return self._wrapped_object.get_last_observation()

    def convert_obs_to_gym_obs(self, obs: _SensorObsT):
        return self._wrapped_object.convert_obs_to_gym_obs(obs)

    def close(self):
        self._wrapped_object.close()

    def is_closed(self) -> bool:
        return self._wrapped_object.is_closed()

    def __del__(self):
        pass  # the wrapped sensor closes itself

    def get_last_gym_observation(self) -> typing.Optional[typing.Any]:
        return self._wrapped_object.get_last_gym_observation()


class RoarPyWorldWrapper(RoarPyWrapper[RoarPyWorld], RoarPyWorld):
    def __init__(self, wrapped_object: typing.Union[RoarPyWorld, RoarPyWrapper[RoarPyWorld]],
                 wrapper_name: str = "RoarPyWorldWrapper"):
        RoarPyWrapper.__init__(self, wrapped_object, wrapper_name)

    @property
    def is_asynchronous(self) -> bool:
        return self._wrapped_object.is_asynchronous

    @is_asynchronous.setter
    def is_asynchronous(self, value: bool):
        self._wrapped_object.is_asynchronous = value

    def get_actors(self) -> typing.Iterable[RoarPyActor]:
        return self._wrapped_object.get_actors()

    def get_sensors(self) -> typing.Iterable[RoarPySensor]:
        return self._wrapped_object.get_sensors()

    @property
    def maneuverable_waypoints(self) -> typing.Optional[typing.Iterable[RoarPyWaypoint]]:
        return self._wrapped_object.maneuverable_waypoints

    @property
    def comprehensive_waypoints(self) -> typing.Optional[typing.Dict[typing.Any, typing.List[RoarPyWaypoint]]]:
        return self._wrapped_object.comprehensive_waypoints

    async def step(self) -> float:
        return await self._wrapped_object.step()

    @property
    def last_tick_elapsed_seconds(self) -> float:
        return self._wrapped_object.last_tick_elapsed_seconds


class RoarPyThreadSafeWrapper(RoarPyWrapper[_Wrapped]):
    """Marks the wrapped object with a lock that its ``roar_py_thread_sync`` methods hold while they run
    (and hand on to the actors, sensors and worlds they return). An object is wrapped once."""

    def __init__(self, wrapped_object: typing.Union[_Wrapped, RoarPyWrapper[_Wrapped]], tslock: threading.RLock):
        super().__init__(wrapped_object, wrapper_name="ThreadSafeWrapper")
        if hasattr(self.unwrapped, "_tslock"):
            raise RuntimeError("Cannot wrap object twice")
        setattr(self.unwrapped, "_tslock", tslock)


def roar_py_thread_sync(func):
    """A backend method that runs under the object's thread-safe lock when it has one (coroutine methods
    hold it until they finish)."""
    def wrap_result(self, result):
        if isinstance(result, (RoarPyActor, RoarPySensor, RoarPyWorld)) and not hasattr(result, "_tslock"):
            return RoarPyThreadSafeWrapper(result, self._tslock)
        return result

    if _is_coroutine_function(func):
        @functools.wraps(func)
        async def coroutine_wrapper(self, *args, **kwargs):
            if not hasattr(self, "_tslock"):
                return await func(self, *args, **kwargs)
            with self._tslock:
                return wrap_result(self, await func(self, *args, **kwargs))

        coroutine_wrapper.is_thread_sync = True
        return coroutine_wrapper

    @functools.wraps(func)
    def func_wrapper(self, *args, **kwargs):
        if not hasattr(self, "_tslock"):
            return func(self, *args, **kwargs)
        with self._tslock:
            return wrap_result(self, func(self, *args, **kwargs))

    func_wrapper.is_thread_sync = True
    return func_wrapper


def _is_coroutine_function(func) -> bool:
    import inspect

    return inspect.iscoroutinefunction(func)


class RoarPyAddItemWrapper(RoarPyWrapper[_Wrapped]):
    """Marks the wrapped object with callbacks that its ``roar_py_append_item`` and ``roar_py_remove_item``
    methods call with the item they add or remove. An object is wrapped once."""

    def __init__(self, wrapped_object: typing.Union[_Wrapped, RoarPyWrapper[_Wrapped]],
                 add_callback: typing.Optional[typing.Callable[[typing.Any], None]] = None,
                 remove_callback: typing.Optional[typing.Callable[[typing.Any], None]] = None):
        super().__init__(wrapped_object, wrapper_name="AddItemWrapper")
        target = self.unwrapped
        if hasattr(target, "_append_item_cb") or hasattr(target, "_remove_item_cb"):
            raise RuntimeError("Cannot wrap object twice")
        if add_callback is not None:
            setattr(target, "_append_item_cb", add_callback)
        if remove_callback is not None:
            setattr(target, "_remove_item_cb", remove_callback)


def roar_py_append_item(func):
    @functools.wraps(func)
    def func_wrapper(self, *args, **kwargs):
        result = func(self, *args, **kwargs)
        if hasattr(self, "_append_item_cb"):
            self._append_item_cb(result)
        return result

    func_wrapper.is_append_item = True
    return func_wrapper


def roar_py_remove_item(func):
    @functools.wraps(func)
    def func_wrapper(self, item, *args, **kwargs):
        result = func(self, item, *args, **kwargs)
        if hasattr(self, "_remove_item_cb"):
            self._remove_item_cb(item)
        return result

    func_wrapper.is_remove_item = True
    return func_wrapper
