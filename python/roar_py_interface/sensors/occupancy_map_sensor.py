"""ROAR_PY's occupancy map sensor."""
import dataclasses
import typing

import numpy as np
from PIL import Image

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor
from ..worlds.occupancy_map import RoarPyOccupancyMapProducer
from .location_in_world_sensor import RoarPyLocationInWorldSensor
from .rotation_sensor import RoarPyRollPitchYawSensor
from ._common import _from_jpeg, _jpeg, _Scheme


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyOccupancyMapSensorData(RoarPyRemoteSupportedSensorData):
    occupancy_map: Image.Image  # mode "L": road 255, elsewhere 0; the car's forward is up

    def convert_obs_to_gym_obs(self):
        return np.asarray(self.occupancy_map, dtype=np.uint8)[:, :, None]

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=255, shape=(height, width, 1), dtype=np.uint8)

    def get_gym_observation_spec(self) -> spaces.Space:
        return self.gym_observation_space(*self.occupancy_map.size)

    @staticmethod
    def from_image(image: Image.Image) -> "RoarPyOccupancyMapSensorData":
        return RoarPyOccupancyMapSensorData(image.convert("L"))

    def to_data(self, scheme: _Scheme) -> bytes:
        return _jpeg(self.occupancy_map)

    @staticmethod
    def from_data_custom(data: bytes, scheme: _Scheme) -> "RoarPyOccupancyMapSensorData":
        return RoarPyOccupancyMapSensorData.from_image(_from_jpeg(data))


class RoarPyOccupancyMapSensor(RoarPySensor[RoarPyOccupancyMapSensorData]):
    sensordata_type = RoarPyOccupancyMapSensorData

    def __init__(self, name: str = "occupancy_map_sensor"):
        super().__init__(name, 0.0)


class RoarPyOccupancyMapSensorImpl(RoarPyOccupancyMapSensor):
    """The occupancy map a producer draws around the location and yaw two other sensors read."""

    def __init__(self, producer: RoarPyOccupancyMapProducer, location_sensor: RoarPyLocationInWorldSensor,
                 rotation_sensor: RoarPyRollPitchYawSensor, name: str = "occupancy_map_sensor"):
        super().__init__(name)
        self._closed = False
        self.producer = producer
        self.location_sensor = location_sensor
        self.rotation_sensor = rotation_sensor
        self._last_data: typing.Optional[RoarPyOccupancyMapSensorData] = None

    async def get_2d_location(self) -> np.ndarray:
        location = await self.location_sensor.receive_observation()
        return np.array([location.x, location.y])

    async def get_rotation_yaw(self) -> float:
        rotation = await self.rotation_sensor.receive_observation()
        return rotation.roll_pitch_yaw[2]

    def get_gym_observation_spec(self) -> spaces.Space:
        return RoarPyOccupancyMapSensorData.gym_observation_space(self.producer.width, self.producer.height)

    async def receive_observation(self) -> RoarPyOccupancyMapSensorData:
        location = await self.get_2d_location()
        yaw = await self.get_rotation_yaw()
        self._last_data = RoarPyOccupancyMapSensorData.from_image(self.producer.plot_occupancy_map(location, yaw))
        return self._last_data

    def get_last_observation(self) -> typing.Optional[RoarPyOccupancyMapSensorData]:
        return self._last_data

    def close(self):
        self._closed = True

    def is_closed(self) -> bool:
        return self._closed
