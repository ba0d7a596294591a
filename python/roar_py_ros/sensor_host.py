"""What a car and the world share as ROAR_PY's sensor hosts in roar_sim: attaching roar_sim sensors
(/roar_sim/attach_sensor, under the host's roar_sim name: a car's, or AttachSensor's WORLD for sensors on
no car), the stamps a step's reply names for them, and detaching them when closed."""
import re
import threading
import typing

import numpy as np
import yaml

import roar_py_interface as rpi

from . import sensors


def _finite_vector(value, what: str, length: int = 3) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be {length} numbers, got {value!r}") from None
    if v.size != length or not np.all(np.isfinite(v)):
        raise ValueError(f"{what} must be {length} finite numbers, got {value!r}")
    return v


# roar_sim's sensor keys as the ROAR_PY arguments they come from.
_ARGUMENT_OF_KEY = {"x": "location[0]", "y": "location[1]", "z": "location[2]", "roll": "roll_pitch_yaw[0]",
                    "pitch": "roll_pitch_yaw[1]", "yaw": "roll_pitch_yaw[2]", "rate": "control_timestep"}


def _roar_py_terms(message: str) -> str:
    """roar_sim's "sensor 'n': x: 500 is outside [-20, 20] m" with the ROAR_PY argument named too."""
    def name(match):
        key = match.group(1)
        return f": {_ARGUMENT_OF_KEY[key]} (roar_sim's {key}): " if key in _ARGUMENT_OF_KEY else match.group(0)

    return re.sub(r": ([a-z_]+): ", name, message, count=1)


def ros_safe(name: str) -> str:
    safe = re.sub(r"[^A-Za-z0-9_]", "_", name) or "sensor"
    return (safe if safe[0].isalpha() else "s_" + safe)[:56]  # roar_sim takes 64, a _N suffix the rest


class SensorHost:
    """A car's or the world's sensors: the host sets _world, ros_name and name, and calls _init_sensors."""

    def _init_sensors(self):
        self._sensors: typing.List[rpi.RoarPySensor] = []
        self._lock = threading.Lock()
        self._expected: typing.Dict[str, float] = {}

    def _take_sensor_stamps(self, snapshot):
        with self._lock:
            for name, stamp in zip(snapshot.sensor_names, snapshot.sensor_stamps):
                if stamp.to_sec() > 0:
                    self._expected[name] = stamp.to_sec()

    def _expected_stamp(self, sim_name: str) -> typing.Optional[float]:
        with self._lock:
            return self._expected.get(sim_name)

    def _sensor_closed(self, sensor):
        """A sensor closed: off the host here, and detached in roar_sim unless the host is going too."""
        if sensor in self._sensors:
            self._sensors.remove(sensor)
        sim_name = getattr(sensor, "sim_name", None)
        if sim_name and not self._closed and self._world._instance._sim_alive():
            from roar_ros.srv import DetachSensor

            self._world._services.call("/roar_sim/detach_sensor", DetachSensor, check=False, vehicle=self.ros_name,
                                       sensor=sim_name)

    def get_sensors(self) -> typing.Iterable[rpi.RoarPySensor]:
        return [s for s in self._sensors if not s.is_closed()]

    def _sim_sensor_name(self, name: str) -> str:
        taken = {getattr(s, "sim_name", None) for s in self._sensors}
        base = ros_safe(name)
        candidate, n = base, 2
        while candidate in taken:
            candidate, n = f"{base}_{n}", n + 1
        return candidate

    def _rate(self, control_timestep: float, what: str) -> float:
        if not np.isfinite(control_timestep) or control_timestep < 0:
            raise ValueError(f"{what}: control_timestep must be >= 0 s, got {control_timestep}")
        return 1.0 / (control_timestep if control_timestep > 0 else self._world.control_timestep)

    def _attach(self, spec: dict, make):
        """Attaches spec in roar_sim, then subscribes (make); a refusal raises ValueError naming the field."""
        self._check_open()
        from roar_ros.srv import AttachSensor, DetachSensor

        response = self._world._services.call("/roar_sim/attach_sensor", AttachSensor, check=False,
                                              vehicle=self.ros_name, sensor_yaml=yaml.safe_dump(spec, default_flow_style=True))
        if not response.success:
            raise ValueError(f"attaching sensor '{spec['name']}' to '{self.name}': {_roar_py_terms(response.message)}")
        try:
            sensor = make()
            sensor._wait_connected()
        except BaseException:
            self._world._services.call("/roar_sim/detach_sensor", DetachSensor, check=False, vehicle=self.ros_name,
                                       sensor=spec["name"])
            raise
        self._sensors.append(sensor)
        return sensor

    def _keep(self, sensor):
        self._check_open()
        self._sensors.append(sensor)
        return sensor

    @staticmethod
    def _mount(location, roll_pitch_yaw, what: str) -> dict:
        loc = _finite_vector(location, f"{what}: location")
        rpy = np.degrees(_finite_vector(roll_pitch_yaw, f"{what}: roll_pitch_yaw"))
        return {"x": float(loc[0]), "y": float(loc[1]), "z": float(loc[2]),
                "roll": float(rpy[0]), "pitch": float(rpy[1]), "yaw": float(rpy[2])}

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_camera_sensor(self, target_datatype: typing.Type[rpi.RoarPyCameraSensorData], location: np.ndarray,
                             roll_pitch_yaw: np.ndarray, fov: float = 90.0, image_width: int = 800,
                             image_height: int = 600, control_timestep: float = 0.0, attachment_type=None,
                             name: str = "carla_camera") -> rpi.RoarPyCameraSensor:
        kinds = {rpi.RoarPyCameraSensorDataRGB: "camera_rgb", rpi.RoarPyCameraSensorDataGreyscale: "camera_grey",
                 rpi.RoarPyCameraSensorDataDepth: "camera_depth",
                 rpi.RoarPyCameraSensorDataSemanticSegmentation: "camera_semantic"}
        if target_datatype not in kinds:
            raise ValueError(f"Unsupported target data type {target_datatype}: attach_camera_sensor takes "
                             f"{[k.__name__ for k in kinds]}")
        for value, what in ((image_width, "image_width"), (image_height, "image_height")):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                raise ValueError(f"attach_camera_sensor: {what} must be an int, got {value!r}")
        rate = self._rate(control_timestep, "attach_camera_sensor")
        sim_name = self._sim_sensor_name(name)
        spec = {"name": sim_name, "type": kinds[target_datatype], **self._mount(location, roll_pitch_yaw, "attach_camera_sensor"),
                "rate": rate, "fov": float(fov), "image_width": int(image_width), "image_height": int(image_height),
                "on_demand": True}
        return self._attach(spec, lambda: sensors.RoarPyRosCameraSensor(
            self, name, sim_name, target_datatype, float(fov), int(image_width), int(image_height), rate))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_lidar_sensor(self, location: np.ndarray, roll_pitch_yaw: np.ndarray, num_lasers: int = 32,
                            max_distance: float = 10.0, points_per_second: int = 56000,
                            rotation_frequency: float = 10.0, upper_fov: float = 10.0, lower_fov: float = -30.0,
                            horizontal_fov: float = 360.0, atmosphere_attenuation_rate: float = 0.004,
                            dropoff_general_rate: float = 0.45, dropoff_intensity_limit_below: float = 0.8,
                            control_timestep: float = 0.0, noise_std: float = 0.0, attachment_type=None,
                            name: str = "carla_lidar_sensor") -> rpi.RoarPyLiDARSensor:
        rate = self._rate(control_timestep, "attach_lidar_sensor")
        sim_name = self._sim_sensor_name(name)
        lidar = {"num_lasers": int(num_lasers), "max_distance": float(max_distance),
                 "points_per_second": float(points_per_second), "rotation_frequency": float(rotation_frequency),
                 "upper_fov": float(upper_fov), "lower_fov": float(lower_fov), "horizontal_fov": float(horizontal_fov),
                 "noise_std": float(noise_std)}
        spec = {"name": sim_name, "type": "lidar", **self._mount(location, roll_pitch_yaw, "attach_lidar_sensor"),
                "rate": rate, **lidar}
        return self._attach(spec, lambda: sensors.RoarPyRosLiDARSensor(self, name, sim_name, lidar, rate))


class WorldSensors(SensorHost):
    """The world's own sensors, on no car (ROAR_PY's world.attach_*_sensor without bind_to): cameras and
    LiDARs posed in the map frame, seeing every car."""

    name = "the world"

    def __init__(self, world):
        from roar_ros.srv import AttachSensorRequest

        self._world = world
        self.ros_name = AttachSensorRequest.WORLD
        self._closed = False
        self._init_sensors()

    def _check_open(self):
        self._world._check_open()

    def _release(self):
        """Forgets the sensors on this side (roar_sim's are gone with its map, or with it)."""
        self._closed = True
        for sensor in list(self._sensors):
            sensor.close()
        self._closed = False
