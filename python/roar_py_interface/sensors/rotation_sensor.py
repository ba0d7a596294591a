"""ROAR_PY's rotation sensors: the frame's quaternion and roll, pitch and yaw, each from the other."""
import dataclasses
import typing

import numpy as np

from .. import spaces, transforms
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor
from ._common import _vector_space


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyFrameQuatSensorData(RoarPyRemoteSupportedSensorData):
    frame_quaternion: np.ndarray  # normalised (w, x, y, z)

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space(4, -1.0, 1.0)

    def convert_obs_to_gym_obs(self):
        return self.frame_quaternion


class RoarPyFrameQuatSensor(RoarPySensor[RoarPyFrameQuatSensorData]):
    sensordata_type = RoarPyFrameQuatSensorData

    def __init__(self, control_timestep: float, name: str = "framequat_sensor"):
        super().__init__(name, control_timestep)

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space(4, -1.0, 1.0)


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyRollPitchYawSensorData(RoarPyRemoteSupportedSensorData):
    roll_pitch_yaw: np.ndarray  # rad, each in [-pi, pi)

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space(3, -np.pi, np.pi)

    def convert_obs_to_gym_obs(self):
        return self.roll_pitch_yaw


class RoarPyRollPitchYawSensor(RoarPySensor[RoarPyRollPitchYawSensorData]):
    sensordata_type = RoarPyRollPitchYawSensorData

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space(3, -np.pi, np.pi)


class RoarPyRollPitchYawSensorFromFrameQuat(RoarPyRollPitchYawSensor):
    """Roll, pitch and yaw read from a frame-quaternion sensor."""

    def __init__(self, framequat_sensor: RoarPyFrameQuatSensor, name: typing.Optional[str] = None):
        super().__init__(name=framequat_sensor.name + " -> rpy" if name is None else name,
                         control_timestep=framequat_sensor.control_timestep)
        self.framequat_sensor = framequat_sensor
        self._last_obs = None

    async def receive_observation(self) -> RoarPyRollPitchYawSensorData:
        reading = await self.framequat_sensor.receive_observation()
        self._last_obs = RoarPyRollPitchYawSensorData(transforms.quat2euler(reading.frame_quaternion))
        return self._last_obs

    def get_last_observation(self) -> typing.Optional[RoarPyRollPitchYawSensorData]:
        return self._last_obs

    def close(self):
        return self.framequat_sensor.close()

    def is_closed(self) -> bool:
        return self.framequat_sensor.is_closed()


class RoarPyFrameQuatSensorFromRollPitchYaw(RoarPyFrameQuatSensor):
    """A frame quaternion read from a roll-pitch-yaw sensor (how ROAR_PY's CARLA backend makes one)."""

    def __init__(self, rpy_sensor: RoarPyRollPitchYawSensor, name: typing.Optional[str] = None):
        super().__init__(name=rpy_sensor.name + " -> framequat" if name is None else name,
                         control_timestep=rpy_sensor.control_timestep)
        self.rpy_sensor = rpy_sensor
        self._last_obs = None

    async def receive_observation(self) -> RoarPyFrameQuatSensorData:
        reading = await self.rpy_sensor.receive_observation()
        self._last_obs = RoarPyFrameQuatSensorData(transforms.euler2quat(*reading.roll_pitch_yaw))
        return self._last_obs

    def get_last_observation(self) -> typing.Optional[RoarPyFrameQuatSensorData]:
        return self._last_obs

    def close(self):
        return self.rpy_sensor.close()

    def is_closed(self) -> bool:
        return self.rpy_sensor.is_closed()
