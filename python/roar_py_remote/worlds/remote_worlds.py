"""ROAR_PY's remote worlds: the messages a world's state and requests travel in, and the client's world."""
import copy
import dataclasses
import logging
import typing

import roar_py_interface as rpi

from ..actors.remote_actors import (_sync_map, RoarPyRemoteActorObsInfo, RoarPyRemoteActorObsInfoRequest,
                                    RoarPyRemoteClientActor)
from ..base import register_object_with_remote_message, RoarPyObjectWithRemoteMessage
from ..sensors import RoarPyRemoteClientSensor, RoarPyRemoteSensorObsInfo, RoarPyRemoteSensorObsInfoRequest


_log = logging.getLogger("roar_py_remote")


@dataclasses.dataclass
class RoarPyRemoteWorldInitInfo:
    maneuverable_waypoints: typing.Optional[typing.List[rpi.RoarPyWaypoint]]
    comprehensive_waypoints: typing.Optional[typing.Dict[typing.Union[int, str, typing.Any],
                                                         typing.List[rpi.RoarPyWaypoint]]]
    is_asynchronous: bool


@dataclasses.dataclass
class RoarPyRemoteWorldObsInfo:
    init_info: typing.Optional[RoarPyRemoteWorldInitInfo]
    stepped: bool
    stepped_dt: float
    actor_info_map: typing.Dict[int, RoarPyRemoteActorObsInfo]
    sensor_info_map: typing.Dict[int, RoarPyRemoteSensorObsInfo]
    last_step_t: float


@dataclasses.dataclass
class RoarPyRemoteWorldObsInfoRequest:
    need_init_info: bool
    step: bool
    actor_request_map: typing.Dict[int, RoarPyRemoteActorObsInfoRequest]
    sensor_request_map: typing.Dict[int, RoarPyRemoteSensorObsInfoRequest]


def _without_reading(info: RoarPyRemoteSensorObsInfo) -> RoarPyRemoteSensorObsInfo:
    bare = copy.copy(info)
    bare.last_data = None
    return bare


@register_object_with_remote_message(RoarPyRemoteWorldObsInfo, RoarPyRemoteWorldObsInfoRequest)
class RoarPyRemoteClientWorld(rpi.RoarPyWorld, RoarPyObjectWithRemoteMessage[RoarPyRemoteWorldObsInfo,
                                                                             RoarPyRemoteWorldObsInfoRequest]):
    """The server's world as it last sent it: actors and sensors update on step()."""

    def __init__(self, start_info: RoarPyRemoteWorldObsInfo) -> None:
        rpi.RoarPyWorld.__init__(self)
        self._actor_map: typing.Dict[int, RoarPyRemoteClientActor] = {}
        self._sensor_map: typing.Dict[int, RoarPyRemoteClientSensor] = {}
        self._is_asynchronous = False
        self._last_step_t = 0.0
        self._maneuverable_waypoints = None
        self._comprehensive_waypoints = None
        self._new_info: typing.Optional[RoarPyRemoteWorldObsInfo] = None
        self._req_need_init_info = True
        self._depack_info(start_info)

    @property
    def is_asynchronous(self) -> bool:
        return self._is_asynchronous

    def get_actors(self) -> typing.List[RoarPyRemoteClientActor]:
        return list(self._actor_map.values())

    def get_sensors(self) -> typing.List[RoarPyRemoteClientSensor]:
        return list(self._sensor_map.values())

    @property
    def maneuverable_waypoints(self):
        return self._maneuverable_waypoints

    @property
    def comprehensive_waypoints(self):
        return self._comprehensive_waypoints

    @property
    def last_tick_elapsed_seconds(self) -> float:
        return self._last_step_t

    async def step(self) -> float:
        """Applies the newest message received: 0 if the server has not stepped since the last step."""
        if self._new_info is None or not self._new_info.stepped:
            return 0.0
        for oid, info in self._new_info.actor_info_map.items():
            if oid in self._actor_map:
                self._actor_map[oid]._depack_info(info)
        for oid, info in self._new_info.sensor_info_map.items():
            if oid in self._sensor_map:
                self._sensor_map[oid]._depack_info(info)
        self._last_step_t = self._new_info.last_step_t
        dt, self._new_info = self._new_info.stepped_dt, None
        return dt

    def _depack_info(self, data: RoarPyRemoteWorldObsInfo) -> bool:
        if data.init_info is not None:
            self._maneuverable_waypoints = data.init_info.maneuverable_waypoints
            self._comprehensive_waypoints = data.init_info.comprehensive_waypoints
            self._is_asynchronous = data.init_info.is_asynchronous
            self._req_need_init_info = False
        # Readings of the objects already known are taken on step(), as the step's.
        _sync_map(self._actor_map, data.actor_info_map, RoarPyRemoteClientActor, update=False)
        _sync_map(self._sensor_map, data.sensor_info_map, lambda i: RoarPyRemoteClientSensor(_without_reading(i)),
                  update=False)
        if self._new_info is None:
            self._new_info = data
            self._new_info.init_info = None
            if not data.stepped:
                self._new_info.stepped_dt = 0.0
        else:
            if data.stepped:
                self._new_info.stepped = True
                self._new_info.stepped_dt += max(data.stepped_dt, 0.0)
            self._new_info.actor_info_map = data.actor_info_map
            self._new_info.sensor_info_map = data.sensor_info_map
            self._new_info.last_step_t = data.last_step_t
        return True

    def _pack_info(self) -> RoarPyRemoteWorldObsInfoRequest:
        return RoarPyRemoteWorldObsInfoRequest(
            need_init_info=self._req_need_init_info, step=True,
            actor_request_map={oid: actor._pack_info() for oid, actor in self._actor_map.items()},
            sensor_request_map={oid: sensor._pack_info() for oid, sensor in self._sensor_map.items()})
