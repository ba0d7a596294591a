"""ROAR_PY's remote sensor wrappers: a sensor shared with a client, and the server's side of a client's sensor."""
import roar_py_interface as rpi
from roar_py_interface import spaces

from ..base import register_object_with_remote_message, RoarPyObjectWithRemoteMessage
from .remote_sensors import (_masked, RoarPyRemoteSensorObsInfo, RoarPyRemoteSensorObsInfoRequest,
                             RoarPyRemoteSharedSensor)


class RoarPyRemoteSharedSensorWrapper(RoarPyRemoteSharedSensor, rpi.RoarPySensorWrapper):
    """A sensor of this process shown read-only to another: readings without the actors they name."""

    def __init__(self, wrapped_object: rpi.RoarPySensor):
        rpi.RoarPyWrapper.__init__(self, wrapped_object, "RoarPyRemoteSharedSensor")
        self._freeze()

    @property
    def name(self) -> str:
        return self._wrapped_object.name

    @property
    def control_timestep(self) -> float:
        return self._wrapped_object.control_timestep

    def get_gym_observation_spec(self) -> spaces.Space:
        return self._wrapped_object.get_gym_observation_spec()

    def get_last_observation(self):
        return _masked(self._wrapped_object.get_last_observation())

    def convert_obs_to_gym_obs(self, obs):
        return self._wrapped_object.convert_obs_to_gym_obs(obs)

    def is_closed(self) -> bool:
        return self._wrapped_object.is_closed()

    def get_last_gym_observation(self):
        return self._wrapped_object.get_last_gym_observation()


@register_object_with_remote_message(RoarPyRemoteSensorObsInfoRequest, RoarPyRemoteSensorObsInfo)
class RoarPyRemoteServerSensorWrapper(rpi.RoarPySensorWrapper, RoarPyObjectWithRemoteMessage[
        RoarPyRemoteSensorObsInfoRequest, RoarPyRemoteSensorObsInfo]):
    """A sensor of this process served to a client: read each tick, its reading and space sent."""

    def __init__(self, sensor: rpi.RoarPySensor):
        rpi.RoarPySensorWrapper.__init__(self, sensor, "RoarPyRemoteServerSensor")
        self._pack_obs_spec = True

    def _depack_info(self, data: RoarPyRemoteSensorObsInfoRequest) -> bool:
        if data.close:
            self.close()
        self._pack_obs_spec = data.need_obs_spec
        return True

    def _pack_info(self) -> RoarPyRemoteSensorObsInfo:
        return RoarPyRemoteSensorObsInfo.from_sensor(self, self._pack_obs_spec)

    async def _tick_remote(self):
        if not self.is_closed():
            await self.receive_observation()

    def get_last_observation(self):
        return _masked(self._wrapped_object.get_last_observation())
