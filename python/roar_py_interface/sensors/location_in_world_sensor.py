"""ROAR_PY's location-in-world sensor."""
import dataclasses

import numpy as np

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor
from ._common import _vector_space


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyLocationInWorldSensorData(RoarPyRemoteSupportedSensorData):
    x: float  # m
    y: float
    z: float

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()

    def convert_obs_to_gym_obs(self):
        return np.array([self.x, self.y, self.z])


class RoarPyLocationInWorldSensor(RoarPySensor[RoarPyLocationInWorldSensorData]):
    sensordata_type = RoarPyLocationInWorldSensorData

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()
