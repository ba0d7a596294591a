"""roar_sim's messages as ROAR_PY's numpy values, and ROAR_PY's actions as roar_sim's controls.

ROAR_PY and roar_sim share the frame (x forward, y left, z up, radians); they differ in the sign of steer:
ROAR_PY's (CARLA's) is positive to the right, roar_sim's (REP-103) positive to the left.
"""
import math
import typing

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


def camera_data(msg, target: typing.Type[data.RoarPyCameraSensorData]):
    image = image_array(msg)
    if target is data.RoarPyCameraSensorDataRGB:
        return data.RoarPyCameraSensorDataRGB(image)
    if target is data.RoarPyCameraSensorDataGreyscale:
        return data.RoarPyCameraSensorDataGreyscale(image)
    if target is data.RoarPyCameraSensorDataDepth:
        return data.RoarPyCameraSensorDataDepth(image.astype(np.float32), False)
    return data.RoarPyCameraSensorDataSemanticSegmentation(image.astype(np.uint64))


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


def check_action(action: typing.Mapping[str, typing.Any], spec) -> typing.Dict[str, float]:
    """The action's values as floats, or ValueError naming the field that is missing, extra or outside the
    spec."""
    if not hasattr(action, "keys"):
        raise ValueError(f"apply_action: an action is a dict of {sorted(spec.spaces.keys())}, got {type(action).__name__}")
    unknown = sorted(set(action.keys()) - set(spec.spaces.keys()))
    if unknown:
        raise ValueError(f"apply_action: unknown action field(s) {unknown}; the action spec has {list(spec.spaces.keys())}")
    out = {}
    for key, space in spec.spaces.items():
        if key not in action:
            raise ValueError(f"apply_action: action field '{key}' is missing; the action spec has {list(spec.spaces.keys())}")
        try:
            value = np.asarray(action[key], dtype=np.float64).reshape(-1)
        except (TypeError, ValueError):
            raise ValueError(f"apply_action: action field '{key}' is not a number: {action[key]!r}") from None
        if value.size != 1 or not np.isfinite(value[0]):
            raise ValueError(f"apply_action: action field '{key}' must be one finite number, got {action[key]!r}")
        v = float(value[0])
        if hasattr(space, "low"):
            low, high = float(np.min(space.low)), float(np.max(space.high))
        elif hasattr(space, "start"):
            low, high = float(space.start), float(space.start + space.n - 1)
        else:
            low, high = 0.0, 1.0
        if not (low - 1e-6 <= v <= high + 1e-6):
            raise ValueError(f"apply_action: action field '{key}' = {v} is outside [{low}, {high}]")
        out[key] = v
    return out


def to_vehicle_control(values: typing.Mapping[str, float], auto_gear: bool):
    """A checked action as roar_sim's VehicleControl (steer turned to roar_sim's sign)."""
    from roar_ros.msg import VehicleControl

    control = VehicleControl()
    control.throttle = values["throttle"]
    control.steer = -values["steer"]
    control.brake = values["brake"]
    control.hand_brake = values["hand_brake"] >= 0.5
    control.reverse = values["reverse"] >= 0.5
    if not auto_gear:
        control.manual_gear_shift = True
        control.gear = int(round(values["target_gear"]))
    return control
