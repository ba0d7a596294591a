"""ROAR_PY's sensors: the data each one reads and the sensor base classes a backend implements.

Names, fields (and their order), observation spaces and gym conversions are ROAR_PY's
(``roar_py_interface/sensors/*.py`` at ROAR_PY's head); test_roar_py_conformance.py lists them.
"""
import asyncio
import dataclasses
import io
import typing

import numpy as np
from PIL import Image

from . import spaces, transforms
from .base import (RoarPyRemoteSupportedSensorData, RoarPyRemoteSupportedSensorSerializationScheme, RoarPySensor,
                   SerialisedDataError, remote_support_sensor_data_register)
from .occupancy_map import RoarPyOccupancyMapProducer

_Scheme = RoarPyRemoteSupportedSensorSerializationScheme


def _vector_space(size: int = 3, low=-np.inf, high=np.inf) -> spaces.Box:
    return spaces.Box(low=low, high=high, shape=(size,), dtype=np.float32)


def _jpeg(image: Image.Image) -> bytes:
    out = io.BytesIO()
    image.save(out, format="JPEG")
    return out.getvalue()


MAX_IMAGE_PIXELS = 1 << 25  # a camera frame from a peer: 32 megapixels (CARLA's largest cameras are 4K)


def _from_jpeg(data: bytes) -> Image.Image:
    """A JPEG a peer sent, its size checked from its header before its pixels are decoded."""
    try:
        image = Image.open(io.BytesIO(data))
        width, height = image.size
        if width * height > MAX_IMAGE_PIXELS:
            raise SerialisedDataError(f"a camera frame of {width}x{height} is more than {MAX_IMAGE_PIXELS} pixels")
        image.load()
    except SerialisedDataError:
        raise
    except Image.DecompressionBombError as error:  # PIL's own limit, met before the size is ours to check
        raise SerialisedDataError(f"a camera frame of more than {MAX_IMAGE_PIXELS} pixels ({error})") from None
    except (OSError, ValueError) as error:
        raise SerialisedDataError(f"a camera frame that is no image ({type(error).__name__}: {error})") from None
    return image


# ---- cameras -----------------------------------------------------------------------------------------------

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
    image_depth: np.ndarray  # H x W x 1 float32, metres; CARLA's far plane (1000 m) where nothing is hit
    is_log_scale: bool = False

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
    ss_label_color_map: typing.Dict[int, typing.Tuple[np.ndarray, str]] = dataclasses.field(
        default_factory=lambda: dict(CARLA_SEMANTIC_LABEL_COLOR_MAP))

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

    def __init__(self, name: str, control_timestep: float = 0.0,
                 target_data_type: typing.Type[RoarPyCameraSensorData] = RoarPyCameraSensorDataRGB):
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


# ---- LiDAR and radar -----------------------------------------------------------------------------------------

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

    def get_gym_observation_spec(self) -> spaces.Space:
        # ROAR_PY's: a fixed 10,000 rows whatever the sweep holds.
        return spaces.Box(low=-np.inf, high=np.inf, shape=(10000, 4), dtype=np.float32)

    def convert_obs_to_gym_obs(self, obs: RoarPyLiDARSensorData):
        return obs.convert_obs_to_gym_obs()


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


# ---- the car's motion ----------------------------------------------------------------------------------

@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyAccelerometerSensorData(RoarPyRemoteSupportedSensorData):
    acceleration: np.ndarray  # m/s^2, x y z

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()

    def convert_obs_to_gym_obs(self):
        return self.acceleration


class RoarPyAccelerometerSensor(RoarPySensor[RoarPyAccelerometerSensorData]):
    sensordata_type = RoarPyAccelerometerSensorData

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()


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


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyVelocimeterSensorData(RoarPyRemoteSupportedSensorData):
    velocity: np.ndarray  # m/s, x y z

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()

    def convert_obs_to_gym_obs(self):
        return self.velocity


class RoarPyVelocimeterSensor(RoarPySensor[RoarPyVelocimeterSensorData]):
    sensordata_type = RoarPyVelocimeterSensorData

    def get_gym_observation_spec(self) -> spaces.Space:
        return _vector_space()


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

    def __init__(self, control_timestep: float = 0.0, name: str = "framequat_sensor"):
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


# ---- the occupancy map -----------------------------------------------------------------------------------

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


# ---- custom sensors ------------------------------------------------------------------------------------

@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyCustomLambdaSensorData(RoarPyRemoteSupportedSensorData):
    flattened: np.ndarray
    space: spaces.Space

    @property
    def unflattened(self):
        return spaces.unflatten(self.space, self.flattened)

    def get_gym_observation_spec(self) -> spaces.Space:
        return self.space

    def convert_obs_to_gym_obs(self):
        return spaces.unflatten(self.space, self.flattened)

    def to_data(self, scheme: _Scheme) -> bytes:
        import msgpack
        import pickle
        import zlib

        return msgpack.packb({"flattened": self.flattened.tolist(), "space": zlib.compress(pickle.dumps(self.space))},
                             use_bin_type=True)

    @staticmethod
    def from_data_custom(data: bytes, scheme: _Scheme) -> "RoarPyCustomLambdaSensorData":
        """ROAR_PY's own encoding (a pickled space), unpickled only as a space and checked for size: a reading
        from a peer runs no code (space_pickle)."""
        import msgpack

        from .space_pickle import SpacePickleError, loads_space

        what = "RoarPyCustomLambdaSensorData"
        try:
            fields = msgpack.unpackb(data, raw=False, strict_map_key=False)
        except (ValueError, msgpack.ExtraData, msgpack.FormatError, msgpack.StackError) as error:
            raise SpacePickleError(f"{what}: not MessagePack ({error})") from None
        if not isinstance(fields, dict) or not isinstance(fields.get("flattened"), (list, tuple)) or \
                not isinstance(fields.get("space"), bytes):
            raise SpacePickleError(f"{what}: serialised data needs 'flattened' (a list) and 'space' (bytes)")
        space = loads_space(fields["space"], f"{what}.space", compressed=True)
        size = spaces.flatdim(space)
        if len(fields["flattened"]) != size:
            raise SpacePickleError(f"{what}.flattened: {len(fields['flattened'])} values for a space of {size}")
        try:
            flattened = np.asarray(fields["flattened"], dtype=np.float64)
        except (TypeError, ValueError):
            raise SpacePickleError(f"{what}.flattened: not a list of numbers") from None
        return RoarPyCustomLambdaSensorData(flattened=flattened, space=space)


class RoarPyCustomLambdaSensor(RoarPySensor[RoarPyCustomLambdaSensorData]):
    """A sensor whose reading is a value of data_space. ROAR_PY's class is abstract (a subclass implements
    receive_observation); here ``func`` (a function or coroutine function of no arguments returning a value
    of data_space) can stand in for that subclass."""

    sensordata_type = RoarPyCustomLambdaSensorData

    def __init__(self, name: str, control_timestep: float, data_space: spaces.Space,
                 func: typing.Optional[typing.Callable[[], typing.Any]] = None):
        super().__init__(name, control_timestep)
        self.data_space = data_space
        self._func = func
        self._last_obs: typing.Optional[RoarPyCustomLambdaSensorData] = None
        self._closed = False

    def get_gym_observation_spec(self) -> spaces.Space:
        return self.data_space

    def convert_obs_to_gym_obs(self, obs: RoarPyCustomLambdaSensorData):
        return obs.convert_obs_to_gym_obs()

    async def receive_observation(self) -> RoarPyCustomLambdaSensorData:
        if self._func is None:
            raise NotImplementedError(f"sensor '{self.name}': a RoarPyCustomLambdaSensor needs func= or a subclass "
                                      f"with receive_observation")
        if self._closed:
            raise RuntimeError(f"sensor '{self.name}' is closed")
        value = self._func()
        if asyncio.iscoroutine(value):
            value = await value
        if not self.data_space.contains(value):
            raise ValueError(f"sensor '{self.name}': its function returned {value!r}, not a value of {self.data_space}")
        self._last_obs = RoarPyCustomLambdaSensorData(spaces.flatten(self.data_space, value), self.data_space)
        return self._last_obs

    def get_last_observation(self) -> typing.Optional[RoarPyCustomLambdaSensorData]:
        return self._last_obs

    def close(self):
        self._closed = True

    def is_closed(self) -> bool:
        return self._closed
