"""ROAR_PY's LiDAR sensor and its point clouds."""
import dataclasses

import numpy as np

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyLiDARSensorData(RoarPyRemoteSupportedSensorData):
    channels: int               # lasers
    horizontal_angle: float     # rad, the rotor's angle at the end of the sweep
    lidar_points_data: np.ndarray  # N x 4 float32: x, y, z (m, sensor frame), intensity 0..1

    def get_gym_observation_spec(self) -> spaces.Space:
        return spaces.Box(low=np.array([[-np.inf, -np.inf, -np.inf, 0.0]] * len(self.lidar_points_data)),
                          high=np.array([[np.inf, np.inf, np.inf, 1.0]] * len(self.lidar_points_data)),
                          shape=(len(self.lidar_points_data), 4), dtype=np.float32)

    def convert_obs_to_gym_obs(self):
        return self.lidar_points_data


class RoarPyLiDARSensor(RoarPySensor[RoarPyLiDARSensorData]):
    sensordata_type = RoarPyLiDARSensorData

    @property
    def num_lasers(self) -> int:
        raise NotImplementedError()

    @property
    def max_distance(self) -> float:
        raise NotImplementedError()

    @property
    def min_distance(self) -> float:
        raise NotImplementedError()

    @property
    def points_per_second(self) -> float:
        raise NotImplementedError()

    @property
    def rotation_frequency(self) -> float:
        raise NotImplementedError()

    @property
    def upper_fov(self) -> float:
        raise NotImplementedError()

    @property
    def lower_fov(self) -> float:
        raise NotImplementedError()

    @property
    def horizontal_fov(self) -> float:
        raise NotImplementedError()

    def get_gym_observation_spec(self) -> spaces.Space:
        # ROAR_PY's: a fixed 10,000 rows whatever the sweep holds.
        return spaces.Box(low=-np.inf, high=np.inf, shape=(10000, 4), dtype=np.float32)

    def convert_obs_to_gym_obs(self, obs: RoarPyLiDARSensorData):
        return obs.convert_obs_to_gym_obs()
