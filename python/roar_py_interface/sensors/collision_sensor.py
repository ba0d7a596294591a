"""ROAR_PY's collision sensor."""
import dataclasses
import typing

import numpy as np

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor
from ._common import _vector_space


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyCollisionSensorData(RoarPyRemoteSupportedSensorData):
    actor: typing.Any           # the car the sensor is on
    other_actor: typing.Any     # what it hit (another car's actor, or None for the barriers and ground)
    impulse_normal: np.ndarray  # N s, world frame

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()

    def convert_obs_to_gym_obs(self):
        return self.impulse_normal


class RoarPyCollisionSensor(RoarPySensor[RoarPyCollisionSensorData]):
    sensordata_type = RoarPyCollisionSensorData

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()
