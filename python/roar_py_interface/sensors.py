"""ROAR_PY's sensors: the data each one reads and the sensor base classes a backend implements."""
import asyncio
import typing
from dataclasses import dataclass, field

import numpy as np
from PIL import Image

from . import spaces

T = typing.TypeVar("T")


class RoarPySensor(typing.Generic[T]):
    """A sensor: ``receive_observation`` waits for its reading of the current step."""

    sensordata_type: typing.Type = object

    def __init__(self, name: str, control_timestep: float = 0.0):
        self.name = name
        self.control_timestep = control_timestep

    def get_gym_observation_spec(self) -> spaces.Space:
        raise NotImplementedError()

    async def receive_observation(self) -> T:
        raise NotImplementedError()

    def get_last_observation(self) -> typing.Optional[T]:
        raise NotImplementedError()

    def convert_obs_to_gym_obs(self, obs: T):
        return obs.convert_obs_to_gym_obs()

    def get_last_gym_observation(self):
        obs = self.get_last_observation()
        return None if obs is None else self.convert_obs_to_gym_obs(obs)

    def close(self):
        raise NotImplementedError()

    def is_closed(self) -> bool:
        raise NotImplementedError()

    def __del__(self):
        try:
            if not self.is_closed():
                self.close()
        except Exception:  # noqa: BLE001 - nothing may escape a finaliser
            pass


class _GymData:
    def to_gym(self):
        raise NotImplementedError()

    def convert_obs_to_gym_obs(self):
        return self.to_gym()


def _vector(value) -> np.ndarray:
    return np.asarray(value, dtype=np.float32).reshape(3)


# ---- cameras -----------------------------------------------------------------------------------------------

class RoarPyCameraSensorData(_GymData):
    def get_image(self) -> Image.Image:
        raise NotImplementedError()

    def get_size(self) -> typing.Tuple[int, int]:
        """(width, height) in pixels."""
        image = self.to_gym()
        return int(image.shape[1]), int(image.shape[0])

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        raise NotImplementedError()


@dataclass
class RoarPyCameraSensorDataRGB(RoarPyCameraSensorData):
    image_rgb: np.ndarray  # H x W x 3 uint8

    def get_image(self) -> Image.Image:
        return Image.fromarray(self.image_rgb, mode="RGB")

    def to_gym(self) -> np.ndarray:
        return self.image_rgb

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=255, shape=(height, width, 3), dtype=np.uint8)

    @staticmethod
    def from_image(image: Image.Image) -> "RoarPyCameraSensorDataRGB":
        return RoarPyCameraSensorDataRGB(np.asarray(image.convert("RGB"), dtype=np.uint8))


@dataclass
class RoarPyCameraSensorDataGreyscale(RoarPyCameraSensorData):
    image_greyscale: np.ndarray  # H x W x 1 uint8

    def get_image(self) -> Image.Image:
        return Image.fromarray(self.image_greyscale[:, :, 0], mode="L")

    def to_gym(self) -> np.ndarray:
        return self.image_greyscale

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=255, shape=(height, width, 1), dtype=np.uint8)

    @staticmethod
    def from_image(image: Image.Image) -> "RoarPyCameraSensorDataGreyscale":
        return RoarPyCameraSensorDataGreyscale(np.asarray(image.convert("L"), dtype=np.uint8)[:, :, None])


@dataclass
class RoarPyCameraSensorDataDepth(RoarPyCameraSensorData):
    image_depth: np.ndarray  # H x W x 1 float32, metres (inf: nothing within range)
    is_log_scale: bool = False

    def get_image(self) -> Image.Image:
        depth = self.image_depth[:, :, 0]
        finite = depth[np.isfinite(depth)]
        top = float(finite.max()) if finite.size else 1.0
        return Image.fromarray(np.where(np.isfinite(depth), depth / max(top, 1e-9), 1.0).astype(np.float32), mode="F")

    def to_gym(self) -> np.ndarray:
        return self.image_depth

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=np.inf, shape=(height, width, 1), dtype=np.float32)


# roar_sim's semantic classes (its semantic camera's mono8 ids) and their display colours.
SEMANTIC_LABEL_COLOR_MAP: typing.Dict[int, typing.Tuple[np.ndarray, str]] = {
    0: (np.array([70, 130, 180], np.uint8), "sky"),
    1: (np.array([128, 64, 128], np.uint8), "road"),
    2: (np.array([157, 234, 50], np.uint8), "lane_marking"),
    3: (np.array([244, 35, 232], np.uint8), "kerb"),
    4: (np.array([190, 153, 153], np.uint8), "barrier"),
    5: (np.array([152, 251, 152], np.uint8), "ground"),
    6: (np.array([0, 0, 142], np.uint8), "vehicle"),
}


@dataclass
class RoarPyCameraSensorDataSemanticSegmentation(RoarPyCameraSensorData):
    image_ss: np.ndarray  # H x W x 1 uint64 class ids
    ss_label_color_map: typing.Dict[int, typing.Tuple[np.ndarray, str]] = field(
        default_factory=lambda: dict(SEMANTIC_LABEL_COLOR_MAP))

    def get_image(self) -> Image.Image:
        palette = np.zeros((256, 3), np.uint8)
        for label, (colour, _) in self.ss_label_color_map.items():
            palette[int(label)] = colour
        return Image.fromarray(palette[self.image_ss[:, :, 0].astype(np.uint8)], mode="RGB")

    def to_gym(self) -> np.ndarray:
        return self.image_ss

    @staticmethod
    def gym_observation_space(width: int, height: int) -> spaces.Space:
        return spaces.Box(low=0, high=255, shape=(height, width, 1), dtype=np.uint64)


class RoarPyCameraSensor(RoarPySensor[RoarPyCameraSensorData]):
    @property
    def image_size_width(self) -> int:
        raise NotImplementedError()

    @property
    def image_size_height(self) -> int:
        raise NotImplementedError()

    @property
    def fov(self) -> float:
        raise NotImplementedError()

    def convert_obs_to_gym_obs(self, obs: RoarPyCameraSensorData):
        return obs.to_gym()


# ---- LiDAR ---------------------------------------------------------------------------------------------------

@dataclass
class RoarPyLiDARSensorData(_GymData):
    lidar_points_data: np.ndarray  # N x 4 float32: x, y, z (m, sensor frame), intensity
    channels: int = 0
    horizontal_angle: float = 0.0  # rad, the rotor's angle at the end of the sweep
    max_points: int = 0            # rows of the gym observation (0: the points as they are)

    def to_gym(self) -> np.ndarray:
        if self.max_points <= 0:
            return self.lidar_points_data
        out = np.zeros((self.max_points, 4), np.float32)
        count = min(self.max_points, len(self.lidar_points_data))
        out[:count] = self.lidar_points_data[:count]
        return out


class RoarPyLiDARSensor(RoarPySensor[RoarPyLiDARSensorData]):
    pass


# ---- the car's motion ----------------------------------------------------------------------------------

@dataclass
class RoarPyAccelerometerSensorData(_GymData):
    accelerometer: np.ndarray  # m/s^2, x y z

    def to_gym(self) -> np.ndarray:
        return _vector(self.accelerometer)


@dataclass
class RoarPyGyroscopeSensorData(_GymData):
    gyroscope: np.ndarray  # rad/s, x y z

    def to_gym(self) -> np.ndarray:
        return _vector(self.gyroscope)


@dataclass
class RoarPyVelocimeterSensorData(_GymData):
    velocity: np.ndarray  # m/s, world frame

    def to_gym(self) -> np.ndarray:
        return _vector(self.velocity)


@dataclass
class RoarPyRollPitchYawSensorData(_GymData):
    roll_pitch_yaw: np.ndarray  # rad

    def to_gym(self) -> np.ndarray:
        return _vector(self.roll_pitch_yaw)


@dataclass
class RoarPyLocationInWorldSensorData(_GymData):
    x: float
    y: float
    z: float

    def to_gym(self) -> np.ndarray:
        return _vector([self.x, self.y, self.z])


@dataclass
class RoarPyGNSSSensorData(_GymData):
    latitude: float   # degrees
    longitude: float  # degrees
    altitude: float   # m

    def to_gym(self) -> np.ndarray:
        return np.array([self.latitude, self.longitude, self.altitude], np.float64)


@dataclass
class RoarPyCollisionSensorData(_GymData):
    actor: typing.Any          # the car the sensor is on
    other_actor: typing.Any    # what it hit: a vehicle's name, "barrier", "ground"; None: nothing
    impulse_normal: np.ndarray  # N s, summed over the step, world frame

    def to_gym(self) -> np.ndarray:
        return _vector(self.impulse_normal)


@dataclass
class RoarPyOccupancyMapSensorData(_GymData):
    occupancy_map: np.ndarray  # H x W uint8: road 255, another car 128, anything else 0; forward is up

    def get_image(self) -> Image.Image:
        return Image.fromarray(self.occupancy_map, mode="L")

    def to_gym(self) -> np.ndarray:
        return self.occupancy_map


def vector_space(low=-np.inf, high=np.inf) -> spaces.Space:
    return spaces.Box(low=low, high=high, shape=(3,), dtype=np.float32)


class RoarPyAccelerometerSensor(RoarPySensor[RoarPyAccelerometerSensorData]):
    def get_gym_observation_spec(self):
        return vector_space()


class RoarPyGyroscopeSensor(RoarPySensor[RoarPyGyroscopeSensorData]):
    def get_gym_observation_spec(self):
        return vector_space()


class RoarPyVelocimeterSensor(RoarPySensor[RoarPyVelocimeterSensorData]):
    def get_gym_observation_spec(self):
        return vector_space()


class RoarPyRollPitchYawSensor(RoarPySensor[RoarPyRollPitchYawSensorData]):
    def get_gym_observation_spec(self):
        return vector_space(-np.pi, np.pi)


class RoarPyLocationInWorldSensor(RoarPySensor[RoarPyLocationInWorldSensorData]):
    def get_gym_observation_spec(self):
        return vector_space()


class RoarPyGNSSSensor(RoarPySensor[RoarPyGNSSSensorData]):
    def get_gym_observation_spec(self):
        return spaces.Box(low=np.array([-90.0, -180.0, -np.inf]), high=np.array([90.0, 180.0, np.inf]),
                          dtype=np.float64)


class RoarPyCollisionSensor(RoarPySensor[RoarPyCollisionSensorData]):
    def get_gym_observation_spec(self):
        return vector_space()


class RoarPyOccupancyMapSensor(RoarPySensor[RoarPyOccupancyMapSensorData]):
    pass


async def gather_observations(sensors: typing.Sequence[RoarPySensor]) -> list:
    return list(await asyncio.gather(*(s.receive_observation() for s in sensors)))
