"""roar_sim's messages as ROAR_PY's numpy values, and ROAR_PY's actions as roar_sim's controls.

ROAR_PY and roar_sim share the frame (x forward, y left, z up, radians); they differ in the sign of steer:
ROAR_PY's (CARLA's) is positive to the right, roar_sim's (REP-103) positive to the left.
"""
import math
import typing
import warnings

import numpy as np

from roar_py_interface import sensors as data


def quaternion_to_rpy(q) -> np.ndarray:
    """[roll, pitch, yaw] of a geometry_msgs Quaternion (REP-103 static xyz)."""
    x, y, z, w = q.x, q.y, q.z, q.w
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.array([roll, pitch, yaw])


def rpy_to_quaternion(rpy) -> typing.Tuple[float, float, float, float]:
    """(x, y, z, w)."""
    roll, pitch, yaw = (float(a) for a in rpy)
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy)


def rotation_matrix(q) -> np.ndarray:
    x, y, z, w = q.x, q.y, q.z, q.w
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def vec3(v) -> np.ndarray:
    return np.array([v.x, v.y, v.z])


def image_array(msg) -> np.ndarray:
    """An Image's pixels as H x W x C without row padding."""
    dtype, channels = {"rgb8": (np.uint8, 3), "mono8": (np.uint8, 1), "32FC1": (np.float32, 1)}[msg.encoding]
    row = np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.step)
    pixel_bytes = np.dtype(dtype).itemsize * channels
    image = np.ascontiguousarray(row[:, :msg.width * pixel_bytes]).view(dtype)
    if msg.is_bigendian and np.dtype(dtype).itemsize > 1:
        image = image.byteswap()
    return image.reshape(msg.height, msg.width, channels)


# roar_sim's semantic classes (roar/sensors/semantic.h) as CARLA's semantic tags, which ROAR_PY programs
# written for CARLA compare against: sky, road, lane marking, kerb, barrier, ground, vehicle.
CARLA_TAG_OF_SEMANTIC_CLASS = np.array([13, 7, 6, 8, 17, 22, 10] + [0] * 249, dtype=np.uint64)
# CARLA's depth camera reads its far plane where it sees nothing.
CARLA_DEPTH_FAR_M = 1000.0


def latest_collision(events):
    """The event CARLA's collision sensor would have left last: of the latest tick's (one per body hit), the
    hardest; None without any."""
    if not events:
        return None
    latest = max(e.header.stamp for e in events)
    return max((e for e in events if e.header.stamp == latest), key=lambda e: vec3(e.impulse) @ vec3(e.impulse))


def camera_data(msg, target: typing.Type[data.RoarPyCameraSensorData]):
    """A camera image as ROAR_PY's CARLA backend gives it: RGB H x W x 3, greyscale H x W, depth H x W float64
    metres (1000 m where nothing is seen), semantic H x W x 1 CARLA tags."""
    image = image_array(msg)
    if target is data.RoarPyCameraSensorDataRGB:
        return data.RoarPyCameraSensorDataRGB(image)
    if target is data.RoarPyCameraSensorDataGreyscale:
        return data.RoarPyCameraSensorDataGreyscale(image[:, :, 0])
    if target is data.RoarPyCameraSensorDataDepth:
        depth = image[:, :, 0].astype(np.float64)
        depth[~np.isfinite(depth) | (depth > CARLA_DEPTH_FAR_M)] = CARLA_DEPTH_FAR_M
        return data.RoarPyCameraSensorDataDepth(depth, False)
    return data.RoarPyCameraSensorDataSemanticSegmentation(CARLA_TAG_OF_SEMANTIC_CLASS[image],
                                                           data.CARLA_SEMANTIC_LABEL_COLOR_MAP)


_POINT_FIELD_TYPES = {1: np.int8, 2: np.uint8, 3: np.int16, 4: np.uint16, 5: np.int32, 6: np.uint32, 7: np.float32,
                      8: np.float64}


def lidar_points(msg) -> np.ndarray:
    """A PointCloud2's x, y, z and intensity as N x 4 float32."""
    fields = {f.name: f for f in msg.fields}
    missing = [n for n in ("x", "y", "z", "intensity") if n not in fields]
    if missing:
        raise ValueError(f"a LiDAR point cloud needs the fields x, y, z, intensity; {missing} missing")
    dtype = np.dtype({"names": ["x", "y", "z", "intensity"],
                      "formats": [_POINT_FIELD_TYPES[fields[n].datatype] for n in ("x", "y", "z", "intensity")],
                      "offsets": [fields[n].offset for n in ("x", "y", "z", "intensity")],
                      "itemsize": msg.point_step})
    count = msg.width * msg.height
    points = np.frombuffer(msg.data, dtype=dtype, count=count)
    out = np.empty((count, 4), np.float32)
    for i, name in enumerate(("x", "y", "z", "intensity")):
        out[:, i] = points[name]
    return out


class RoarPyCompatibilityWarning(UserWarning):
    """Something a ROAR_PY program did that CARLA takes and roar_py_ros takes as CARLA does (an action field
    ignored, a value clamped): said once per car and field."""


# The numbers CARLA's VehicleControl takes from a ROAR_PY action and their ranges (CARLA clamps to them),
# and its switches: hand_brake is on from 0.5, reverse whenever it is not 0 (ROAR_PY's CARLA backend).
ACTION_RANGES = {"throttle": (0.0, 1.0), "steer": (-1.0, 1.0), "brake": (0.0, 1.0)}
ACTION_SWITCHES = ("hand_brake", "reverse")


class OnceWarnings:
    """An object's RoarPyCompatibilityWarnings, each (by its key) said once."""

    def __init__(self, who: str):
        self.who = who
        self._said: typing.Set[str] = set()

    def warn(self, key: str, message: str, stacklevel: int) -> None:
        """stacklevel: as warnings.warn's, counted from the caller of this."""
        if key not in self._said:
            self._said.add(key)
            warnings.warn(f"{self.who}: {message}", RoarPyCompatibilityWarning, stacklevel=stacklevel + 1)


class ActionReader:
    """ROAR_PY's action as ROAR_PY's CARLA backend turns it into CARLA's VehicleControl, and as CARLA takes
    that: each field read as one number (arrays of one element too); a field the car's action spec does not
    have (target_gear on an automatic car) ignored; a value outside its range clamped; each said once with
    a RoarPyCompatibilityWarning. What CARLA cannot take either is refused with ValueError naming the
    field: a missing field, a non-number, NaN or infinity, several numbers."""

    def __init__(self, who: str, auto_gear: bool, num_gears: int):
        self.who = who
        self.auto_gear = auto_gear
        self.num_gears = num_gears
        self.warnings = OnceWarnings(who)

    def _warn_once(self, key: str, message: str):
        self.warnings.warn(key, f"{message} (as CARLA does; said once)", stacklevel=4)

    def _number(self, action, key: str) -> float:
        if key not in action:
            raise ValueError(f"apply_action: action field '{key}' is missing (CARLA's vehicle control needs it); "
                             f"an action has {self.fields()}")
        try:
            value = np.asarray(action[key], dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"apply_action: action field '{key}' is not a number: {action[key]!r}") from None
        if value.size != 1:
            raise ValueError(f"apply_action: action field '{key}' must be one number, got {value.size}: {action[key]!r}")
        number = float(value.reshape(-1)[0])
        if not math.isfinite(number):
            raise ValueError(f"apply_action: action field '{key}' must be finite, got {number}")
        return number

    def _clamped(self, key: str, number: float, low: float, high: float) -> float:
        if number < low or number > high:
            self._warn_once(key, f"action field '{key}' = {number} is outside [{low}, {high}]: clamped")
            return min(max(number, low), high)
        return number

    def fields(self) -> typing.List[str]:
        return list(ACTION_RANGES) + list(ACTION_SWITCHES) + ([] if self.auto_gear else ["target_gear"])

    def read(self, action: typing.Mapping[str, typing.Any]) -> typing.Dict[str, float]:
        if not hasattr(action, "keys") or not hasattr(action, "__getitem__"):
            raise ValueError(f"apply_action: an action is a dict of {self.fields()}, got {type(action).__name__}")
        for key in sorted(set(action.keys()) - set(self.fields()), key=str):
            what = "the car has an automatic gearbox" if key == "target_gear" else "not a field of the action spec"
            self._warn_once(f"extra:{key}", f"action field '{key}' ignored ({what})")
        values = {key: self._clamped(key, self._number(action, key), *ACTION_RANGES[key]) for key in ACTION_RANGES}
        values["hand_brake"] = 1.0 if self._number(action, "hand_brake") >= 0.5 else 0.0
        values["reverse"] = 0.0 if self._number(action, "reverse") == 0.0 else 1.0
        if not self.auto_gear:
            gear = self._number(action, "target_gear")
            values["target_gear"] = float(round(self._clamped("target_gear", gear, -1.0, float(self.num_gears))))
        return values


def to_vehicle_control(values: typing.Mapping[str, float], auto_gear: bool):
    """A read action as roar_sim's VehicleControl (steer turned to roar_sim's sign)."""
    from roar_ros.msg import VehicleControl

    control = VehicleControl()
    control.throttle = values["throttle"]
    control.steer = -values["steer"]
    control.brake = values["brake"]
    control.hand_brake = values["hand_brake"] != 0.0
    control.reverse = values["reverse"] != 0.0
    if not auto_gear:
        control.manual_gear_shift = True
        control.gear = int(values["target_gear"])
    return control


def radar_detections(msg) -> np.ndarray:
    """A radar cloud's detections as N x 4 float32 in CARLA's column order: velocity, azimuth, altitude, depth."""
    fields = {f.name: f for f in msg.fields}
    names = ("velocity", "azimuth", "altitude", "depth")
    missing = [n for n in names if n not in fields]
    if missing:
        raise ValueError(f"a radar cloud needs the fields {list(names)}; {missing} missing")
    dtype = np.dtype({"names": list(names), "formats": [_POINT_FIELD_TYPES[fields[n].datatype] for n in names],
                      "offsets": [fields[n].offset for n in names], "itemsize": msg.point_step})
    count = msg.width * msg.height
    detections = np.frombuffer(msg.data, dtype=dtype, count=count)
    out = np.empty((count, 4), np.float32)
    for i, name in enumerate(names):
        out[:, i] = detections[name]
    return out
