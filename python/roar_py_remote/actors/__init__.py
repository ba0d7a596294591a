"""Actors over ROAR_PY's remote protocol: the server sends an actor's sensors and (until the client has it)
its action space; the client sends its next action flattened in that space, and may close the actor."""
import dataclasses
import logging
import typing

import numpy as np

import roar_py_interface as rpi
from roar_py_interface import spaces

from .. import wire
from ..base import RoarPyObjectWithRemoteMessage, register_object_with_remote_message
from ..sensors import (RoarPyRemoteClientSensor, RoarPyRemoteSensorObsInfo, RoarPyRemoteSensorObsInfoRequest,
                       RoarPyRemoteServerSensorWrapper, RoarPyRemoteSharedSensor, RoarPyRemoteSharedSensorWrapper,
                       _Frozen)

_log = logging.getLogger("roar_py_remote")


class RoarPyRemoteSharedActor(_Frozen, rpi.RoarPyActor):
    """An actor another program may look at but neither drive, read, reset nor change."""

    async def apply_action(self, action: typing.Any) -> bool:
        return False

    async def receive_observation(self) -> typing.Dict[str, typing.Any]:
        raise PermissionError("Cannot receive observation from a shared actor")

    def close(self) -> None:
        pass

    async def reset(self) -> None:
        raise PermissionError("Cannot reset a shared actor")


@dataclasses.dataclass
class RoarPyRemoteActorObsInfo:
    name: typing.Optional[str]
    control_timestep: float
    sensors_map: typing.Dict[int, RoarPyRemoteSensorObsInfo]
    is_closed: bool
    action_spec: typing.Optional[str]

    def get_action_spec(self) -> typing.Optional[spaces.Space]:
        if self.action_spec is None:
            return None
        return wire.unpack_space(self.action_spec, f"actor '{self.name}' action_spec")

    @staticmethod
    def from_actor(actor: rpi.RoarPyActor, sensor_data_map: typing.Dict[int, RoarPyRemoteSensorObsInfo],
                   pack_action_spec: bool) -> "RoarPyRemoteActorObsInfo":
        return RoarPyRemoteActorObsInfo(
            name=actor.name, control_timestep=actor.control_timestep, sensors_map=sensor_data_map,
            is_closed=actor.is_closed(),
            action_spec=wire.pack_space(actor.get_action_spec()) if pack_action_spec else None)


@dataclasses.dataclass
class RoarPyRemoteActorObsInfoRequest:
    close: bool
    sensors_request: typing.Dict[int, RoarPyRemoteSensorObsInfoRequest]
    need_action_space_spec: bool
    action: typing.Optional[np.ndarray]


def _sync_map(known: dict, infos: dict, make, update: bool = True) -> None:
    """Makes the objects new in infos (and with update, updates the others from theirs); the ones no
    longer there are marked closed and forgotten."""
    for oid, info in infos.items():
        if oid not in known:
            known[oid] = make(info)
        elif update:
            known[oid]._depack_info(info)
    for oid in [oid for oid in known if oid not in infos]:
        known[oid]._closed = True
        del known[oid]


@register_object_with_remote_message(RoarPyRemoteActorObsInfo, RoarPyRemoteActorObsInfoRequest)
class RoarPyRemoteClientActor(rpi.RoarPyActor, RoarPyObjectWithRemoteMessage[RoarPyRemoteActorObsInfo,
                                                                              RoarPyRemoteActorObsInfoRequest]):
    """A server's actor seen from the client: its sensors, and its action sent with the next step."""

    def __init__(self, start_info: RoarPyRemoteActorObsInfo):
        rpi.RoarPyActor.__init__(self, start_info.name if start_info.name is not None else "RoarPyRemoteClientActor",
                                 start_info.control_timestep)
        self.new_request_info = RoarPyRemoteActorObsInfoRequest(close=False, sensors_request={},
                                                                need_action_space_spec=True, action=None)
        self._closed = False
        self._next_action: typing.Optional[np.ndarray] = None
        self._internal_sensors_map: typing.Dict[int, RoarPyRemoteClientSensor] = {}
        self._internal_action_spec: typing.Optional[spaces.Space] = None
        self._depack_info(start_info)

    def _depack_info(self, data: RoarPyRemoteActorObsInfo) -> bool:
        self._control_timestep = data.control_timestep
        self._closed = data.is_closed
        _sync_map(self._internal_sensors_map, data.sensors_map, RoarPyRemoteClientSensor)
        new_action_spec = data.get_action_spec()
        if new_action_spec is not None:
            self._internal_action_spec = new_action_spec
            self.new_request_info.need_action_space_spec = False
        return True

    def _pack_info(self) -> RoarPyRemoteActorObsInfoRequest:
        self.new_request_info.sensors_request = {oid: s._pack_info() for oid, s in self._internal_sensors_map.items()}
        self.new_request_info.action, self._next_action = self._next_action, None
        return self.new_request_info

    def get_sensors(self) -> typing.List[rpi.RoarPySensor]:
        return [s for s in self._internal_sensors_map.values() if not s.is_closed()]

    def get_action_spec(self) -> spaces.Space:
        return self._internal_action_spec

    async def _apply_action(self, action: typing.Any) -> bool:
        """Flattened in the server's action space now, so that a missing field is reported here."""
        if self._internal_action_spec is None:
            raise RuntimeError(f"actor '{self.name}': the server has not sent its action space yet")
        try:
            self._next_action = np.asarray(spaces.flatten(self._internal_action_spec, action), dtype=np.float64)
        except KeyError as missing:
            raise ValueError(f"apply_action: action field {missing} is missing; the action space has "
                             f"{list(self._internal_action_spec.spaces)}") from None
        return True

    def close(self):
        self.new_request_info.close = True

    def is_closed(self) -> bool:
        return self._closed


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
        self._refresh_sensor_list()

    def _refresh_sensor_list(self) -> None:
        self.sensors_map, self._last_sensor_id = _refreshed(
            self.sensors_map, self._wrapped_object.get_sensors(), RoarPyRemoteServerSensorWrapper, self._last_sensor_id)

    def _unflattened(self, flat: np.ndarray):
        spec = self._wrapped_object.get_action_spec()
        flat = np.asarray(flat, dtype=np.float64).ravel()
        if flat.size != spaces.flatdim(spec) or not np.all(np.isfinite(flat)):
            if not self._dropped_warned:
                self._dropped_warned = True
                _log.warning("actor '%s': dropped an action of %d value(s) (finite: %s); its space flattens to %d",
                             self.name, flat.size, bool(np.all(np.isfinite(flat))), spaces.flatdim(spec))
            return None
        # Clamped to the space's range, as CARLA clamps a control, so that no finite value overflows its dtype
        # (test_roar_py_remote test_a_huge_finite_action_is_clamped_not_the_end_of_the_session).
        bounds = spaces.flatten_space(spec)
        limit = float(np.finfo(np.float32).max)
        low = np.maximum(np.asarray(bounds.low, dtype=np.float64), -limit)
        high = np.minimum(np.asarray(bounds.high, dtype=np.float64), limit)
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


__all__ = ["RoarPyRemoteSharedActor", "RoarPyRemoteActorObsInfo", "RoarPyRemoteActorObsInfoRequest",
           "RoarPyRemoteClientActor", "RoarPyRemoteSharedActorWrapper", "RoarPyRemoteServerActorWrapper"]
