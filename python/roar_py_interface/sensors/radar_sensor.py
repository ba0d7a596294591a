"""ROAR_PY's radar sensor and its detections."""
import dataclasses

import numpy as np

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyRadarSensorData(RoarPyRemoteSupportedSensorData):
    # N x 4 float32 detections in the column order of CARLA's radar measurement, as ROAR_PY's CARLA backend
    # passes them on: velocity (m/s along the line of sight, negative approaching), azimuth (rad, positive
    # right), altitude (rad, positive up), depth (m).
    radar_points_data: np.ndarray

    def get_gym_observation_spec(self) -> spaces.Space:
        n = len(self.radar_points_data)
        return spaces.Box(low=-np.inf, high=np.inf, shape=(n, 4), dtype=np.float32)

    def convert_obs_to_gym_obs(self):
        return self.radar_points_data


class RoarPyRadarSensor(RoarPySensor[RoarPyRadarSensorData]):
    sensordata_type = RoarPyRadarSensorData

    @property
    def horizontal_fov(self) -> float:
        raise NotImplementedError

    @property
    def points_per_second(self) -> float:
        raise NotImplementedError

    @property
    def max_distance(self) -> float:
        raise NotImplementedError

    @property
    def vertical_fov(self) -> float:
        raise NotImplementedError

    def get_gym_observation_spec(self) -> spaces.Space:
        return spaces.Box(low=-np.inf, high=np.inf, shape=(10000, 4), dtype=np.float32)

    def convert_obs_to_gym_obs(self, obs: RoarPyRadarSensorData):
        return obs.convert_obs_to_gym_obs()
