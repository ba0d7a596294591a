"""ROAR_PY's camera sensor and its data: RGB, greyscale, depth and semantic segmentation frames."""
import dataclasses
import typing

import numpy as np
from PIL import Image

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor
from ._common import _from_jpeg, _jpeg, _Scheme


class RoarPyCameraSensorData(RoarPyRemoteSupportedSensorData):
    def get_image(self) -> Image.Image:
        raise NotImplementedError()

    def to_gym(self) -> typing.Any:
        raise NotImplementedError()

    def get_size(self) -> typing.Tuple[int, int]:
        """(width, height) in pixels."""
        return self.get_image().size

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        raise NotImplementedError()

    def get_gym_observation_spec(self) -> spaces.Space:
        return self.__class__.gym_observation_space(*self.get_size())

    def convert_obs_to_gym_obs(self):
        return self.to_gym()


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyCameraSensorDataRGB(RoarPyCameraSensorData):
    image_rgb: np.ndarray  # H x W x 3 uint8

    def get_image(self) -> Image.Image:
        return Image.fromarray(self.image_rgb, mode="RGB")

    def to_gym(self) -> np.ndarray:
        return self.image_rgb

    def get_size(self) -> typing.Tuple[int, int]:
        return tuple(self.image_rgb.shape[1::-1])

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=255, shape=(height, width, 3), dtype=np.uint8)

    @staticmethod
    def from_image(image: Image.Image) -> "RoarPyCameraSensorDataRGB":
        return RoarPyCameraSensorDataRGB(np.asarray(image.convert("RGB"), dtype=np.uint8))

    def to_data(self, scheme: _Scheme) -> bytes:
        return _jpeg(self.get_image())

    @staticmethod
    def from_data_custom(data: bytes, scheme: _Scheme) -> "RoarPyCameraSensorDataRGB":
        return RoarPyCameraSensorDataRGB.from_image(_from_jpeg(data))


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyCameraSensorDataGreyscale(RoarPyCameraSensorData):
    image_greyscale: np.ndarray  # H x W uint8, as CARLA's backend gives it

    def get_image(self) -> Image.Image:
        return Image.fromarray(self.image_greyscale.reshape(self.image_greyscale.shape[:2]), mode="L")

    def to_gym(self) -> np.ndarray:
        return self.image_greyscale

    def get_size(self) -> typing.Tuple[int, int]:
        return tuple(self.image_greyscale.shape[1::-1])

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=255, shape=(height, width, 1), dtype=np.uint8)

    @staticmethod
    def from_image(image: Image.Image) -> "RoarPyCameraSensorDataGreyscale":
        return RoarPyCameraSensorDataGreyscale(np.asarray(image.convert("L"), dtype=np.uint8))

    def to_data(self, scheme: _Scheme) -> bytes:
        return _jpeg(self.get_image())

    @staticmethod
    def from_data_custom(data: bytes, scheme: _Scheme) -> "RoarPyCameraSensorDataGreyscale":
        return RoarPyCameraSensorDataGreyscale.from_image(_from_jpeg(data))


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyCameraSensorDataDepth(RoarPyCameraSensorData):
    image_depth: np.ndarray  # H x W float64 metres, as CARLA's backend gives it (1000 m where nothing is hit)
    is_log_scale: bool

    def get_image(self) -> Image.Image:
        # ROAR_PY's picture of depth: divided by the frame's spread of depths, as 8 bits.
        low, high = float(np.min(self.image_depth)), float(np.max(self.image_depth))
        normalised = self.image_depth / max(high - low, 1e-9)
        return Image.fromarray((normalised * 255).astype(np.uint8).reshape(self.image_depth.shape[:2]), mode="L")

    def to_gym(self) -> np.ndarray:
        return self.image_depth

    def get_size(self) -> typing.Tuple[int, int]:
        return tuple(self.image_depth.shape[1::-1])

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=np.inf, shape=(height, width, 1), dtype=np.float32)


# CARLA 0.9.12-0.9.14's semantic tags and colours, as ROAR_PY's CARLA backend labels its segmentation.
CARLA_SEMANTIC_LABEL_COLOR_MAP: typing.Dict[int, typing.Tuple[np.ndarray, str]] = {
    i: (np.array(colour, dtype=np.uint8), label) for i, (colour, label) in enumerate([
        ((0, 0, 0), "Unlabeled"), ((70, 70, 70), "Building"), ((100, 40, 40), "Fence"), ((55, 90, 80), "Other"),
        ((220, 20, 60), "Pedestrian"), ((153, 153, 153), "Pole"), ((157, 234, 50), "RoadLine"),
        ((128, 64, 128), "Road"), ((244, 35, 232), "Sidewalk"), ((107, 142, 35), "Vegetation"),
        ((0, 0, 142), "Car"), ((102, 102, 156), "Wall"), ((220, 220, 0), "TrafficSign"), ((70, 130, 180), "Sky"),
        ((81, 0, 81), "Ground"), ((150, 100, 100), "Bridge"), ((230, 150, 140), "RailTrack"),
        ((180, 165, 180), "GuardRail"), ((250, 170, 30), "TrafficLight"), ((110, 190, 160), "Static"),
        ((170, 120, 50), "Dynamic"), ((45, 60, 150), "Water"), ((145, 170, 100), "Terrain")])}


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyCameraSensorDataSemanticSegmentation(RoarPyCameraSensorData):
    image_ss: np.ndarray  # H x W x 1 uint64 semantic tags
    ss_label_color_map: typing.Dict[int, typing.Tuple[np.ndarray, str]]

    def get_image(self) -> Image.Image:
        palette = np.zeros((256, 3), np.uint8)
        for label, (colour, _) in self.ss_label_color_map.items():
            palette[int(label)] = colour
        return Image.fromarray(palette[self.image_ss[:, :, 0].astype(np.uint8)], mode="RGB")

    def to_gym(self) -> np.ndarray:
        return self.image_ss

    def get_size(self) -> typing.Tuple[int, int]:
        return tuple(self.image_ss.shape[1::-1])

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=np.iinfo(np.uint64).max, shape=(height, width, 1), dtype=np.uint64)


class RoarPyCameraSensor(RoarPySensor[RoarPyCameraSensorData]):
    sensordata_type = RoarPyCameraSensorData

    def __init__(self, name: str, control_timestep: float, target_data_type: typing.Type[RoarPyCameraSensorData]):
        super().__init__(name, control_timestep)
        self.sensordata_type = target_data_type

    @property
    def image_size_width(self) -> int:
        raise NotImplementedError()

    @property
    def image_size_height(self) -> int:
        raise NotImplementedError()

    @property
    def fov(self) -> float:
        raise NotImplementedError()

    def get_gym_observation_spec(self) -> spaces.Space:
        return self.sensordata_type.gym_observation_space(self.image_size_width, self.image_size_height)

    def convert_obs_to_gym_obs(self, obs: RoarPyCameraSensorData):
        return obs.to_gym()
