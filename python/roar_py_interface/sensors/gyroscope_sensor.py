"""ROAR_PY's gyroscope sensor."""
import dataclasses

import numpy as np

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor
from ._common import _vector_space


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyGyroscopeSensorData(RoarPyRemoteSupportedSensorData):
    angular_velocity: np.ndarray  # rad/s, x y z

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()

    def convert_obs_to_gym_obs(self):
        return self.angular_velocity


class RoarPyGyroscopeSensor(RoarPySensor[RoarPyGyroscopeSensorData]):
    sensordata_type = RoarPyGyroscopeSensorData

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()
