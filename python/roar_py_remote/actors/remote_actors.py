"""ROAR_PY's remote actors: the messages an actor's state and requests travel in, and the client's actor."""
import dataclasses
import logging
import typing

import numpy as np
import roar_py_interface as rpi
from roar_py_interface import spaces

from .. import wire
from ..base import register_object_with_remote_message, RoarPyObjectWithRemoteMessage
from ..sensors.remote_sensors import (_Frozen, RoarPyRemoteClientSensor, RoarPyRemoteSensorObsInfo,
                                     RoarPyRemoteSensorObsInfoRequest)


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
