"""ROAR_PY's remote sensors: the messages a sensor's readings and requests travel in, and the client's sensor."""
import asyncio
import base64
import binascii
import dataclasses
import time
import typing

import roar_py_interface as rpi
from roar_py_interface import spaces

from .. import wire
from ..base import register_object_with_remote_message, RoarPyObjectWithRemoteMessage


READING_TIMEOUT = 30.0  # wall seconds a client sensor waits for its first reading


_Scheme = rpi.RoarPyRemoteSupportedSensorSerializationScheme


class _Frozen:
    """Refuses attribute changes once built: what is shared with other programs is read-only."""

    def _freeze(self):
        object.__setattr__(self, "_frozen", True)

    def __setattr__(self, name: str, value: typing.Any) -> None:
        if getattr(self, "_frozen", False):
            raise PermissionError(f"Cannot set attribute '{name}' on a shared {type(self).__name__}")
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        raise PermissionError(f"Cannot delete attribute '{name}' on a shared {type(self).__name__}")


_ObsT = typing.TypeVar("_ObsT")


class RoarPyRemoteSharedSensor(_Frozen, rpi.RoarPySensor[_ObsT], typing.Generic[_ObsT]):
    """A sensor another program may look at but neither read nor change."""

    async def receive_observation(self) -> typing.Any:
        raise PermissionError("This sensor is shared, you cannot receive observation from it")

    def close(self):
        pass


def _masked(obs):
    """A reading as it may leave this process: a collision's actors stay here (as ROAR_PY's shared sensor
    masks them)."""
    if isinstance(obs, rpi.RoarPyCollisionSensorData):
        return rpi.RoarPyCollisionSensorData(actor=None, other_actor=None, impulse_normal=obs.impulse_normal)
    return obs


@dataclasses.dataclass
class RoarPyRemoteSensorObsInfo:
    name: typing.Optional[str]
    control_timestep: float
    last_data: typing.Optional[str]
    last_data_type: str
    obs_spec: typing.Optional[str]
    is_closed: bool

    def get_obs_spec(self) -> typing.Optional[spaces.Space]:
        if self.obs_spec is None:
            return None
        return wire.unpack_space(self.obs_spec, f"sensor '{self.name}' obs_spec")

    def get_last_obs_type(self) -> typing.Optional[typing.Type[rpi.RoarPyRemoteSupportedSensorData]]:
        """The class of the readings, as ROAR_PY's: None when the server sent no reading's type it knows."""
        return rpi.RoarPyRemoteSupportedSensorData._supported_data_types.get(self.last_data_type)

    def get_last_obs(self) -> typing.Optional[rpi.RoarPyRemoteSupportedSensorData]:
        if self.last_data is None:
            return None
        data_type = self.get_last_obs_type()
        if data_type is None:
            raise wire.WireFormatError(f"sensor '{self.name}': unknown data type '{self.last_data_type}'")
        try:
            return data_type.from_data(base64.b64decode(self.last_data, validate=True), _Scheme.MSGPACK_COMPRESSED)
        except (binascii.Error, ValueError, OSError) as error:
            raise wire.WireFormatError(f"sensor '{self.name}': its {self.last_data_type} does not decode "
                                       f"({error})") from None

    @staticmethod
    def from_sensor(sensor: rpi.RoarPySensor, pack_obs_spec: bool) -> "RoarPyRemoteSensorObsInfo":
        last_obs = sensor.get_last_observation()
        if last_obs is not None and not isinstance(last_obs, rpi.RoarPyRemoteSupportedSensorData):
            raise TypeError(f"sensor '{sensor.name}': a {type(last_obs).__name__} cannot be sent")
        return RoarPyRemoteSensorObsInfo(
            name=sensor.name,
            control_timestep=sensor.control_timestep,
            last_data=None if last_obs is None else base64.b64encode(
                last_obs.to_data(_Scheme.MSGPACK_COMPRESSED)).decode("ascii"),
            last_data_type=type(last_obs).__name__,
            obs_spec=wire.pack_space(sensor.get_gym_observation_spec()) if pack_obs_spec else None,
            is_closed=sensor.is_closed())


@dataclasses.dataclass
class RoarPyRemoteSensorObsInfoRequest:
    close: bool
    need_obs_spec: bool


@register_object_with_remote_message(RoarPyRemoteSensorObsInfo, RoarPyRemoteSensorObsInfoRequest)
class RoarPyRemoteClientSensor(rpi.RoarPySensor, RoarPyObjectWithRemoteMessage[RoarPyRemoteSensorObsInfo,
                                                                                RoarPyRemoteSensorObsInfoRequest]):
    """A server's sensor seen from the client: its newest reading as of the last step."""

    def __init__(self, start_info: RoarPyRemoteSensorObsInfo):
        rpi.RoarPySensor.__init__(self, start_info.name if start_info.name is not None else "RoarPyRemoteClientSensor",
                                  start_info.control_timestep)
        self._closed = False
        self._last_data = None
        self._new_data = None
        self._obs_spec = None
        self.new_request = RoarPyRemoteSensorObsInfoRequest(close=False, need_obs_spec=True)
        self._depack_info(start_info)

    def _depack_info(self, data: RoarPyRemoteSensorObsInfo) -> bool:
        self._control_timestep = data.control_timestep
        if data.get_last_obs_type() is not None:
            self.sensordata_type = data.get_last_obs_type()
        new_data = data.get_last_obs()
        if new_data is not None:
            self._new_data = new_data
        new_obs_spec = data.get_obs_spec()
        if new_obs_spec is not None:
            self._obs_spec = new_obs_spec
            self.new_request.need_obs_spec = False
        self._closed = data.is_closed
        return True

    def _pack_info(self) -> RoarPyRemoteSensorObsInfoRequest:
        return self.new_request

    def get_gym_observation_spec(self) -> spaces.Space:
        if self._obs_spec is None:
            raise RuntimeError(f"sensor '{self.name}': the server has not sent its observation space yet")
        return self._obs_spec

    async def receive_observation(self):
        deadline = time.time() + READING_TIMEOUT
        while self._new_data is None:
            if self._closed:
                raise RuntimeError(f"sensor '{self.name}' is closed")
            if time.time() > deadline:
                raise RuntimeError(f"sensor '{self.name}': no reading from the server within {READING_TIMEOUT:.0f} s "
                                   "(step the world to receive one)")
            await asyncio.sleep(0.001)
        self._last_data = self._new_data
        return self._last_data

    def get_last_observation(self):
        return self._last_data

    def convert_obs_to_gym_obs(self, obs):
        return obs.convert_obs_to_gym_obs()

    def close(self):
        self.new_request.close = True

    def is_closed(self) -> bool:
        return self._closed
