"""ROAR_PY's sensors over roar_sim's sensor topics.

Each sensor is a roar_sim sensor on the car (attached with /roar_sim/attach_sensor, so rviz and rosbag see
it like any other) whose topic this process subscribes to. In synchronous mode a step's reply names the
stamp of every sensor's newest reading, and receive_observation waits for exactly that reading.
"""
import math
import threading
import time
import typing

import numpy as np
import rospy

import roar_py_interface as rpi
from roar_py_interface import sensors as data

from . import connection, conversions

SIM_NODE = "/roar_sim"
READING_TIMEOUT = 30.0  # wall seconds a reading roar_sim announced may take to arrive


class RosSensorMixin:
    """What every roar_py_ros sensor shares: its car, its roar_sim name, its topic and its last reading."""

    def _setup(self, vehicle, sim_name: str, topic: typing.Optional[str], msg_class, convert):
        self._vehicle = vehicle
        self.sim_name = sim_name
        self.topic = topic
        self._convert = convert
        self._cond = threading.Condition()
        self._msg = None
        self._msg_stamp = -1.0
        self._returned_stamp = -1.0
        self._last_obs = None
        self._last_obs_stamp = None
        self._closed = False
        self._sub = None
        if topic is not None:
            self._sub = rospy.Subscriber(topic, msg_class, self._on_message, queue_size=4, tcp_nodelay=True,
                                         buff_size=1 << 24)

    def _wait_connected(self, timeout: float = 10.0):
        """Until roar_sim itself has the connection to this subscriber: a reading published before that is
        lost, and rospy reports its side connected a moment before roar_sim's side is."""
        if self._sub is None:
            return
        deadline = time.time() + timeout
        while not connection.publisher_connected(SIM_NODE, self.topic, rospy.get_name()):
            if time.time() > deadline:
                raise RuntimeError(f"sensor '{self.name}': roar_sim did not connect {self.topic} within {timeout:.0f} s")
            time.sleep(0.002)

    def _on_message(self, msg):
        with self._cond:
            self._msg = msg
            self._msg_stamp = msg.header.stamp.to_sec()
            self._cond.notify_all()

    def _check_open(self):
        if self._closed:
            raise RuntimeError(f"sensor '{self.name}' is closed")
        self._vehicle._check_open()

    async def receive_observation(self):
        self._check_open()
        world = self._vehicle._world
        if not world.is_asynchronous:
            expected = self._vehicle._expected_stamp(self.sim_name)
            if expected is None:
                # No step since the sensor came: tick once so that it has a reading (CARLA would block).
                await world.step()
                expected = self._vehicle._expected_stamp(self.sim_name)
            msg, stamp = self._wait_for(lambda: self._msg_stamp >= (expected or 0.0) - 1e-9 and self._msg is not None)
        else:
            msg, stamp = self._wait_for(lambda: self._msg is not None)
        if self._last_obs_stamp != stamp or self._last_obs is None:
            self._last_obs = self._convert(msg)
            self._last_obs_stamp = stamp
        return self._last_obs

    def _wait_for(self, ready):
        deadline = time.time() + READING_TIMEOUT
        with self._cond:
            while not ready():
                if not self._vehicle._world._instance._sim_alive():
                    raise RuntimeError(f"sensor '{self.name}': roar_sim has gone away")
                remaining = deadline - time.time()
                if remaining <= 0:
                    raise RuntimeError(f"sensor '{self.name}': no reading on {self.topic} within {READING_TIMEOUT:.0f} s "
                                       f"(the newest is of t = {self._msg_stamp:.3f} s; "
                                       f"{self._sub.get_num_connections() if self._sub else 0} connection(s))")
                self._cond.wait(min(remaining, 0.5))
            return self._msg, self._msg_stamp

    def get_last_observation(self):
        return self._last_obs

    def close(self):
        if self._closed:
            return
        self._closed = True
        if self._sub is not None:
            self._sub.unregister()
        self._vehicle._sensor_closed(self)

    def is_closed(self) -> bool:
        return self._closed


class RoarPyRosCameraSensor(RosSensorMixin, rpi.RoarPyCameraSensor):
    def __init__(self, vehicle, name, sim_name, target_datatype, fov, width, height, rate):
        rpi.RoarPyCameraSensor.__init__(self, name, 1.0 / rate)
        from sensor_msgs.msg import Image

        self.target_datatype = target_datatype
        self._fov, self._width, self._height = fov, width, height
        self._setup(vehicle, sim_name, f"/{vehicle.ros_name}/camera/{sim_name}/image", Image,
                    lambda m: conversions.camera_data(m, target_datatype))

    @property
    def image_size_width(self) -> int:
        return self._width

    @property
    def image_size_height(self) -> int:
        return self._height

    @property
    def fov(self) -> float:
        return self._fov

    def get_gym_observation_spec(self):
        return self.target_datatype.gym_observation_space(self._width, self._height)


class RoarPyRosLiDARSensor(RosSensorMixin, rpi.RoarPyLiDARSensor):
    def __init__(self, vehicle, name, sim_name, spec: dict, rate):
        rpi.RoarPyLiDARSensor.__init__(self, name, 1.0 / rate)
        from sensor_msgs.msg import PointCloud2

        self.num_lasers = spec["num_lasers"]
        self.max_distance = spec["max_distance"]
        self.points_per_second = spec["points_per_second"]
        self.rotation_frequency = spec["rotation_frequency"]
        self.upper_fov, self.lower_fov = spec["upper_fov"], spec["lower_fov"]
        self.horizontal_fov = spec["horizontal_fov"]
        self.max_points = int(math.ceil(self.points_per_second / rate)) + self.num_lasers

        def convert(msg):
            points = conversions.lidar_points(msg)
            angle = float(math.atan2(points[-1, 1], points[-1, 0])) if len(points) else 0.0
            return data.RoarPyLiDARSensorData(points, self.num_lasers, angle, self.max_points)

        self._setup(vehicle, sim_name, f"/{vehicle.ros_name}/lidar/{sim_name}/points", PointCloud2, convert)

    def get_gym_observation_spec(self):
        return rpi.spaces.Box(low=-np.inf, high=np.inf, shape=(self.max_points, 4), dtype=np.float32)


def _vector_sensor(base, msg_module: str, msg_name: str, topic_suffix: str, convert):
    class Sensor(RosSensorMixin, base):
        def __init__(self, vehicle, name, sim_name, rate):
            base.__init__(self, name, 1.0 / rate)
            module = __import__(msg_module, fromlist=[msg_name])
            self._setup(vehicle, sim_name, f"/{vehicle.ros_name}/{sim_name}{topic_suffix}", getattr(module, msg_name),
                        convert)

    Sensor.__name__ = "RoarPyRos" + base.__name__[len("RoarPy"):]
    Sensor.__qualname__ = Sensor.__name__
    return Sensor


RoarPyRosAccelerometerSensor = _vector_sensor(
    rpi.RoarPyAccelerometerSensor, "geometry_msgs.msg", "Vector3Stamped", "",
    lambda m: data.RoarPyAccelerometerSensorData(conversions.vec3(m.vector)))
RoarPyRosGyroscopeSensor = _vector_sensor(
    rpi.RoarPyGyroscopeSensor, "geometry_msgs.msg", "Vector3Stamped", "",
    lambda m: data.RoarPyGyroscopeSensorData(conversions.vec3(m.vector)))
RoarPyRosRollPitchYawSensor = _vector_sensor(
    rpi.RoarPyRollPitchYawSensor, "geometry_msgs.msg", "Vector3Stamped", "",
    lambda m: data.RoarPyRollPitchYawSensorData(conversions.vec3(m.vector)))
RoarPyRosLocationInWorldSensor = _vector_sensor(
    rpi.RoarPyLocationInWorldSensor, "geometry_msgs.msg", "PointStamped", "",
    lambda m: data.RoarPyLocationInWorldSensorData(m.point.x, m.point.y, m.point.z))
RoarPyRosVelocimeterSensor = _vector_sensor(
    rpi.RoarPyVelocimeterSensor, "geometry_msgs.msg", "TwistStamped", "/twist_map",
    lambda m: data.RoarPyVelocimeterSensorData(conversions.vec3(m.twist.linear)))
RoarPyRosGNSSSensor = _vector_sensor(
    rpi.RoarPyGNSSSensor, "sensor_msgs.msg", "NavSatFix", "",
    lambda m: data.RoarPyGNSSSensorData(m.latitude, m.longitude, m.altitude))


class RoarPyRosOccupancyMapSensor(RosSensorMixin, rpi.RoarPyOccupancyMapSensor):
    def __init__(self, vehicle, name, sim_name, width, height, rate):
        rpi.RoarPyOccupancyMapSensor.__init__(self, name, 1.0 / rate)
        from sensor_msgs.msg import Image

        self.width, self.height = width, height
        self._setup(vehicle, sim_name, f"/{vehicle.ros_name}/occupancy_map/{sim_name}/image", Image,
                    lambda m: data.RoarPyOccupancyMapSensorData(conversions.image_array(m)[:, :, 0]))

    def get_gym_observation_spec(self):
        return rpi.spaces.Box(low=0, high=255, shape=(self.height, self.width), dtype=np.uint8)


class RoarPyRosCollisionSensor(rpi.RoarPyCollisionSensor):
    """Contacts roar_sim reports for the car (every car has them): in synchronous mode those of the last
    step, in asynchronous mode those since the last observation; impulses summed."""

    def __init__(self, vehicle, name):
        rpi.RoarPyCollisionSensor.__init__(self, name, 0.0)
        self._vehicle = vehicle
        self.sim_name = None
        self._closed = False
        self._last_obs = None

    async def receive_observation(self):
        if self._closed:
            raise RuntimeError(f"sensor '{self.name}' is closed")
        self._vehicle._check_open()
        events = self._vehicle._take_collisions()
        impulse = np.zeros(3)
        other = None
        for event in events:
            impulse += conversions.vec3(event.impulse)
            other = event.other
        self._last_obs = data.RoarPyCollisionSensorData(self._vehicle, other, impulse)
        return self._last_obs

    def get_last_observation(self):
        return self._last_obs

    def close(self):
        if not self._closed:
            self._closed = True
            self._vehicle._sensor_closed(self)

    def is_closed(self) -> bool:
        return self._closed
