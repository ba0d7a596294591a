"""ROAR_PY's remote actor wrappers: an actor shared with a client, and the server's side of a client's actor."""
import typing

import numpy as np
import roar_py_interface as rpi
from roar_py_interface import spaces

from ..base import register_object_with_remote_message, RoarPyObjectWithRemoteMessage
from ..sensors import RoarPyRemoteServerSensorWrapper, RoarPyRemoteSharedSensor, RoarPyRemoteSharedSensorWrapper
from .remote_actors import _log, RoarPyRemoteActorObsInfo, RoarPyRemoteActorObsInfoRequest, RoarPyRemoteSharedActor


class RoarPyRemoteSharedActorWrapper(rpi.RoarPyActorWrapper, RoarPyRemoteSharedActor):
    """An actor of this process shown read-only to another, its sensors shared read-only too."""

    def __init__(self, wrapped_object: rpi.RoarPyActor):
        rpi.RoarPyActorWrapper.__init__(self, wrapped_object, "RoarPyRemoteSharedActorWrapper")
        self._freeze()

    def get_sensors(self) -> typing.List[rpi.RoarPySensor]:
        return [s if isinstance(s, RoarPyRemoteSharedSensor) else RoarPyRemoteSharedSensorWrapper(s)
                for s in self._wrapped_object.get_sensors()]

    apply_action = RoarPyRemoteSharedActor.apply_action
    receive_observation = RoarPyRemoteSharedActor.receive_observation
    close = RoarPyRemoteSharedActor.close
    reset = RoarPyRemoteSharedActor.reset


def _refreshed(known: dict, current: typing.Iterable, make, next_id: int) -> typing.Tuple[dict, int]:
    """known (id -> wrapper) for the objects now current: wrappers kept by identity, new ids for new ones."""
    by_object = {id(w._wrapped_object): (oid, w) for oid, w in known.items()}
    refreshed = {}
    for obj in current:
        if id(obj) in by_object:
            oid, wrapper = by_object[id(obj)]
        else:
            oid, wrapper, next_id = next_id, make(obj), next_id + 1
        refreshed[oid] = wrapper
    return refreshed, next_id


@register_object_with_remote_message(RoarPyRemoteActorObsInfoRequest, RoarPyRemoteActorObsInfo)
class RoarPyRemoteServerActorWrapper(rpi.RoarPyActorWrapper, RoarPyObjectWithRemoteMessage[
        RoarPyRemoteActorObsInfoRequest, RoarPyRemoteActorObsInfo]):
    """An actor of this process driven by a client: its action applied and its sensors read each tick.
    Action values go to the actor as they come, so the actor clamps them as over CARLA; an action that
    does not unflatten in its space (wrong length, not finite) is dropped, as ROAR_PY's server drops it."""

    def __init__(self, wrapped_object: rpi.RoarPyActor):
        rpi.RoarPyActorWrapper.__init__(self, wrapped_object, "RoarPyRemoteServerActorWrapper")
        self.sensors_map: typing.Dict[int, RoarPyRemoteServerSensorWrapper] = {}
        self._last_sensor_id = 0
        self._need_action_space_spec = True
        self._next_action = None
        self._dropped_warned = False
        self._action_bounds = (None, None, None)  # (the action space, its flattened low, high)
        self._refresh_sensor_list()

    def _refresh_sensor_list(self) -> None:
        self.sensors_map, self._last_sensor_id = _refreshed(
            self.sensors_map, self._wrapped_object.get_sensors(), RoarPyRemoteServerSensorWrapper, self._last_sensor_id)

    def _flat_bounds(self, spec) -> typing.Tuple[np.ndarray, np.ndarray]:
        """The action space's flattened range, finite in float32; worked out once per space (every action of
        every client passes here)."""
        if self._action_bounds[0] is not spec:
            bounds = spaces.flatten_space(spec)
            limit = float(np.finfo(np.float32).max)
            self._action_bounds = (spec, np.maximum(np.asarray(bounds.low, dtype=np.float64), -limit),
                                   np.minimum(np.asarray(bounds.high, dtype=np.float64), limit))
        return self._action_bounds[1], self._action_bounds[2]

    def _unflattened(self, flat: np.ndarray):
        spec = self._wrapped_object.get_action_spec()
        low, high = self._flat_bounds(spec)
        flat = np.asarray(flat, dtype=np.float64).ravel()
        if flat.size != low.size or not np.all(np.isfinite(flat)):
            if not self._dropped_warned:
                self._dropped_warned = True
                _log.warning("actor '%s': dropped an action of %d value(s) (finite: %s); its space flattens to %d",
                             self.name, flat.size, bool(np.all(np.isfinite(flat))), low.size)
            return None
        # Clamped to the space's range, as CARLA clamps a control, so that no finite value overflows its dtype
        # (test_roar_py_remote test_a_huge_finite_action_is_clamped_not_the_end_of_the_session).
        return spaces.unflatten(spec, np.clip(flat, low, high))

    def _depack_info(self, data: RoarPyRemoteActorObsInfoRequest) -> bool:
        self._next_action = None if data.action is None else self._unflattened(data.action)
        if data.close:
            self._wrapped_object.close()
        self._need_action_space_spec = data.need_action_space_spec
        self._refresh_sensor_list()
        for oid, sensor_request in data.sensors_request.items():
            if oid in self.sensors_map:
                self.sensors_map[oid]._depack_info(sensor_request)
        return True

    def _pack_info(self) -> RoarPyRemoteActorObsInfo:
        self._refresh_sensor_list()
        sensor_map = {oid: sensor._pack_info() for oid, sensor in self.sensors_map.items()}
        return RoarPyRemoteActorObsInfo.from_actor(self._wrapped_object, sensor_map, self._need_action_space_spec)

    async def receive_observation(self):
        if self._next_action is not None:
            await self._wrapped_object.apply_action(self._next_action)
            self._next_action = None
        return await self._wrapped_object.receive_observation()

    async def _tick_remote(self):
        if not self.is_closed():
            await self.receive_observation()
