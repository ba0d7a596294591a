"""ROAR_PY's GNSS sensor."""
import dataclasses

import numpy as np

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyGNSSSensorData(RoarPyRemoteSupportedSensorData):
    altitude: float   # m
    latitude: float   # degrees north
    longitude: float  # degrees east

    def get_gym_observation_spec(self) -> spaces.Space:
        return spaces.Box(low=np.array([-np.inf, -90, -180]), high=np.array([np.inf, 90, 180]), dtype=np.float32)

    def convert_obs_to_gym_obs(self):
        return np.array([self.altitude, self.latitude, self.longitude])


class RoarPyGNSSSensor(RoarPySensor[RoarPyGNSSSensorData]):
    sensordata_type = RoarPyGNSSSensorData

    def get_gym_observation_spec(self) -> spaces.Space:
        return spaces.Box(low=np.array([-np.inf, -90, -180]), high=np.array([np.inf, 90, 180]), dtype=np.float32)
