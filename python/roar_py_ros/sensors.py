"""ROAR_PY's sensors over roar_sim.

Sensors CARLA renders or measures (cameras, LiDAR, radar, GNSS) are roar_sim sensors on the car (attached
with /roar_sim/attach_sensor, so rviz and rosbag see them like any other) whose topics this process
subscribes to; in synchronous mode a step's reply names the stamp of every sensor's newest reading, and
receive_observation waits for exactly that reading. Those ROAR_PY's CARLA backend reads from the actor's
state (location, velocity, rotation, acceleration, angular velocity, collisions, the occupancy map drawn
from waypoints) read the car's state from the step's reply, as CARLA's backend reads the actor: no topic.
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


class _VehicleSensor:
    """What every roar_py_ros sensor shares: its car, its last reading, and closing."""

    def _own(self, vehicle, sim_name):
        self._vehicle = vehicle
        self.sim_name = sim_name
        self._last_obs = None
        self._closed = False

    def _check_open(self):
        if self._closed:
            raise RuntimeError(f"sensor '{self.name}' is closed")
        self._vehicle._check_open()

    def _release(self):
        """What a sensor gives back when closed, beyond its place on the car."""

    def get_last_observation(self):
        return self._last_obs

    def close(self):
        if not self._closed:
            self._closed = True
            self._release()
            self._vehicle._sensor_closed(self)

    def is_closed(self) -> bool:
        return self._closed


class RosSensorMixin(_VehicleSensor):
    """A sensor read from its roar_sim topic: its topic, its newest message and the stamp it returned."""

    def _setup(self, vehicle, sim_name: str, topic: typing.Optional[str], msg_class, convert):
        self._own(vehicle, sim_name)
        self.topic = topic
        self._convert = convert
        self._cond = threading.Condition()
        self._msg = None
        self._msg_stamp = -1.0
        self._returned_stamp = -1.0
        self._last_obs_stamp = None
        self._sub = None
        if topic is not None:
            with connection.ros_threads():
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

    def _release(self):
        if self._sub is not None:
            self._sub.unregister()


def _lazy_data_class(base: type, field: str) -> type:
    """A subclass of a sensor data class whose `field` (pixels) is made on its first read: a frame or map
    nobody reads costs nothing. `get_size` answers without making it."""

    class Lazy(base):
        def __init__(self, make, size: typing.Tuple[int, int]):
            object.__setattr__(self, "_make", make)
            object.__setattr__(self, "_size", size)
            object.__setattr__(self, "_value", None)
            if base is data.RoarPyCameraSensorDataSemanticSegmentation:
                self.ss_label_color_map = data.CARLA_SEMANTIC_LABEL_COLOR_MAP
            if base is data.RoarPyCameraSensorDataDepth:
                self.is_log_scale = False  # metres, as ROAR_PY's CARLA backend converts depth

        def _read(self):
            if self._value is None:
                object.__setattr__(self, "_value", getattr(self._make(), field))
            return self._value

        def _store(self, value):
            object.__setattr__(self, "_value", value)

        def get_size(self) -> typing.Tuple[int, int]:
            return self._size

        def __repr__(self):
            # Not the dataclass's: asyncio and debuggers print results, and that must not make the pixels.
            state = "made" if self._value is not None else "made when first read"
            return f"{base.__name__}({self._size[0]}x{self._size[1]}, {state})"

    if base is data.RoarPyOccupancyMapSensorData:
        Lazy.get_gym_observation_spec = lambda self: base.gym_observation_space(*self._size)
    setattr(Lazy, field, property(Lazy._read, Lazy._store))
    Lazy.__name__ = Lazy.__qualname__ = base.__name__
    Lazy.__module__ = base.__module__
    return Lazy


_LAZY_CAMERA_DATA = {cls: _lazy_data_class(cls, field) for cls, field in (
    (data.RoarPyCameraSensorDataRGB, "image_rgb"), (data.RoarPyCameraSensorDataGreyscale, "image_greyscale"),
    (data.RoarPyCameraSensorDataDepth, "image_depth"),
    (data.RoarPyCameraSensorDataSemanticSegmentation, "image_ss"))}
_LAZY_OCCUPANCY_DATA = _lazy_data_class(data.RoarPyOccupancyMapSensorData, "occupancy_map")


class RoarPyRosCameraSensor(_VehicleSensor, rpi.RoarPyCameraSensor):
    """ROAR_PY's camera on roar_sim's on-demand camera. In synchronous mode receive_observation returns at
    once with the frame of the step, rendered (/roar_sim/render_sensor) when the program first reads its
    pixels, so a frame nobody reads costs nothing (the runner's 1024x768 camera most entries never look
    at); the pixels are those the camera would have published at that tick (test_roar_py_ros
    test_a_camera_frame_is_rendered_when_first_read_and_is_the_ticks_frame). In asynchronous mode its newest
    frame is rendered at once. rviz or rosbag subscribing to its topic makes it render every frame."""

    def __init__(self, vehicle, name, sim_name, target_datatype, fov, width, height, rate):
        rpi.RoarPyCameraSensor.__init__(self, name, 1.0 / rate, target_datatype)
        self._own(vehicle, sim_name)
        self.topic = f"/{vehicle.ros_name}/camera/{sim_name}/image"
        self.target_datatype = target_datatype
        self._fov, self._width, self._height = fov, width, height
        self._last_stamp = None

    @property
    def image_size_width(self) -> int:
        return self._width

    @property
    def image_size_height(self) -> int:
        return self._height

    @property
    def fov(self) -> float:
        return self._fov

    def _wait_connected(self):
        pass  # no topic: frames are asked for

    def _render(self, stamp: float):
        from roar_ros.srv import RenderSensor

        self._check_open()
        response = self._vehicle._world._services.call(
            "/roar_sim/render_sensor", RenderSensor, check=False, vehicle=self._vehicle.ros_name,
            sensor=self.sim_name, stamp=rospy.Time.from_sec(stamp))
        if not response.success:
            raise RuntimeError(f"sensor '{self.name}': {response.message}")
        return conversions.camera_data(response.image, self.target_datatype)

    async def receive_observation(self):
        self._check_open()
        world = self._vehicle._world
        if world.is_asynchronous:
            self._last_obs, self._last_stamp = self._render(0.0), None
            return self._last_obs
        expected = self._vehicle._expected_stamp(self.sim_name)
        if expected is None:
            # No step since the camera came: tick once so that it has a frame (CARLA would block).
            await world.step()
            expected = self._vehicle._expected_stamp(self.sim_name)
        if self._last_obs is None or self._last_stamp != expected:
            self._last_obs = _LAZY_CAMERA_DATA[self.target_datatype](
                lambda: self._render(expected), (self._width, self._height))
            self._last_stamp = expected
        return self._last_obs


class RoarPyRosLiDARSensor(RosSensorMixin, rpi.RoarPyLiDARSensor):
    def __init__(self, vehicle, name, sim_name, spec: dict, rate):
        rpi.RoarPyLiDARSensor.__init__(self, name, 1.0 / rate)
        from sensor_msgs.msg import PointCloud2

        self._spec = dict(spec)

        def convert(msg):
            points = conversions.lidar_points(msg)
            angle = float(math.atan2(points[-1, 1], points[-1, 0])) if len(points) else 0.0
            return data.RoarPyLiDARSensorData(self.num_lasers, angle, points)

        self._setup(vehicle, sim_name, f"/{vehicle.ros_name}/lidar/{sim_name}/points", PointCloud2, convert)

    @property
    def num_lasers(self) -> int:
        return self._spec["num_lasers"]

    @property
    def max_distance(self) -> float:
        return self._spec["max_distance"]

    @property
    def min_distance(self) -> float:
        return 0.0

    @property
    def points_per_second(self) -> float:
        return self._spec["points_per_second"]

    @property
    def rotation_frequency(self) -> float:
        return self._spec["rotation_frequency"]

    @property
    def upper_fov(self) -> float:
        return self._spec["upper_fov"]

    @property
    def lower_fov(self) -> float:
        return self._spec["lower_fov"]

    @property
    def horizontal_fov(self) -> float:
        return self._spec["horizontal_fov"]


class RoarPyRosGNSSSensor(RosSensorMixin, rpi.RoarPyGNSSSensor):
    """roar_sim's GNSS (its noise) with CARLA's constant biases added, in degrees and metres."""

    def __init__(self, vehicle, name, sim_name, rate, bias: typing.Tuple[float, float, float] = (0.0, 0.0, 0.0)):
        rpi.RoarPyGNSSSensor.__init__(self, name, 1.0 / rate)
        from sensor_msgs.msg import NavSatFix

        altitude_bias, latitude_bias, longitude_bias = bias
        self._setup(vehicle, sim_name, f"/{vehicle.ros_name}/{sim_name}", NavSatFix,
                    lambda m: data.RoarPyGNSSSensorData(m.altitude + altitude_bias, m.latitude + latitude_bias,
                                                        m.longitude + longitude_bias))


class RoarPyRosRadarSensor(RosSensorMixin, rpi.RoarPyRadarSensor):
    """roar_sim's radar: each sweep's detections in CARLA's column order (velocity, azimuth, altitude, depth)."""

    def __init__(self, vehicle, name, sim_name, spec: dict, rate):
        rpi.RoarPyRadarSensor.__init__(self, name, 1.0 / rate)
        from sensor_msgs.msg import PointCloud2

        self._spec = dict(spec)
        self._setup(vehicle, sim_name, f"/{vehicle.ros_name}/radar/{sim_name}/detections", PointCloud2,
                    lambda m: data.RoarPyRadarSensorData(conversions.radar_detections(m)))

    @property
    def horizontal_fov(self) -> float:
        return self._spec["horizontal_fov"]

    @property
    def vertical_fov(self) -> float:
        return self._spec["vertical_fov"]

    @property
    def points_per_second(self) -> float:
        return self._spec["points_per_second"]

    @property
    def max_distance(self) -> float:
        return self._spec["max_distance"]


class _StateSensor(_VehicleSensor):
    """A sensor that reads the car's state (ROAR_PY's CARLA backend reads the actor the same way)."""

    def __init__(self, vehicle, read):
        self._own(vehicle, None)
        self._read = read

    async def receive_observation(self):
        self._check_open()
        self._last_obs = self._read(self._vehicle)
        return self._last_obs


def _state_sensor(base, read, doc: str):
    class Sensor(_StateSensor, base):
        __doc__ = doc

        def __init__(self, vehicle, name):
            base.__init__(self, name, 0.0)
            _StateSensor.__init__(self, vehicle, read)

    Sensor.__name__ = "RoarPyRos" + base.__name__[len("RoarPy"):]
    Sensor.__qualname__ = Sensor.__name__
    return Sensor


def _location(vehicle):
    x, y, z = vehicle.get_3d_location()
    return data.RoarPyLocationInWorldSensorData(float(x), float(y), float(z))


def _local_velocity(vehicle):
    quaternion = rpi.transforms.euler2quat(*vehicle.get_roll_pitch_yaw())
    return data.RoarPyVelocimeterSensorData(
        rpi.transforms.rotate_vector(vehicle.get_linear_3d_velocity(), rpi.transforms.qinverse(quaternion)))


RoarPyRosLocationInWorldSensor = _state_sensor(rpi.RoarPyLocationInWorldSensor, _location, "The car's location (m).")
RoarPyRosVelocimeterSensor = _state_sensor(
    rpi.RoarPyVelocimeterSensor, lambda v: data.RoarPyVelocimeterSensorData(v.get_linear_3d_velocity()),
    "The car's velocity in the world frame (m/s).")
RoarPyRosLocalVelocimeterSensor = _state_sensor(
    rpi.RoarPyVelocimeterSensor, _local_velocity, "The car's velocity in its own frame (m/s): x forward, y left.")
RoarPyRosLocalVelocimeterSensor.__name__ = RoarPyRosLocalVelocimeterSensor.__qualname__ = "RoarPyRosLocalVelocimeterSensor"
RoarPyRosRollPitchYawSensor = _state_sensor(
    rpi.RoarPyRollPitchYawSensor, lambda v: data.RoarPyRollPitchYawSensorData(v.get_roll_pitch_yaw()),
    "The car's roll, pitch and yaw (rad).")
RoarPyRosAccelerometerSensor = _state_sensor(
    rpi.RoarPyAccelerometerSensor, lambda v: data.RoarPyAccelerometerSensorData(v.get_acceleration()),
    "The car's acceleration in the world frame without gravity (m/s^2): its velocity's change over the last tick.")
RoarPyRosGyroscopeSensor = _state_sensor(
    rpi.RoarPyGyroscopeSensor, lambda v: data.RoarPyGyroscopeSensorData(v.get_angular_velocity()),
    "The car's angular velocity in the world frame (rad/s).")


class RoarPyRosOccupancyMapSensor(_VehicleSensor, rpi.RoarPyOccupancyMapSensor):
    """ROAR_PY's CARLA occupancy map: the road drawn from the map's waypoints around the car, forward up,
    drawn when the program first reads it, from the car's place at its observation (most entries never
    look: test_roar_py_ros test_an_occupancy_map_is_drawn_when_first_read_from_the_observations_place)."""

    def __init__(self, vehicle, producer: rpi.RoarPyOccupancyMapProducer, name: str):
        rpi.RoarPyOccupancyMapSensor.__init__(self, name)
        self._own(vehicle, None)
        self.producer = producer

    def get_gym_observation_spec(self):
        return data.RoarPyOccupancyMapSensorData.gym_observation_space(self.producer.width, self.producer.height)

    async def receive_observation(self):
        self._check_open()
        location = self._vehicle.get_3d_location()[:2]
        yaw = self._vehicle.get_roll_pitch_yaw()[2]
        producer = self.producer
        self._last_obs = _LAZY_OCCUPANCY_DATA(
            lambda: data.RoarPyOccupancyMapSensorData.from_image(producer.plot_occupancy_map(location, yaw)),
            (producer.width, producer.height))
        return self._last_obs



class RoarPyRosCollisionSensor(_VehicleSensor, rpi.RoarPyCollisionSensor):
    """The car's latest collision event since the last observation, then zero, as ROAR_PY's CARLA backend
    keeps the last event its sensor heard (conversions.latest_collision): impulse N s (world frame),
    other_actor the car of this world it hit (None for barriers and cars not of this world, as CARLA's
    backend gives None for actors it does not know)."""

    def __init__(self, vehicle, name):
        rpi.RoarPyCollisionSensor.__init__(self, name, 0.0)
        self._own(vehicle, None)

    async def receive_observation(self):
        self._check_open()
        event = conversions.latest_collision(self._vehicle._take_collisions(self))
        impulse = np.zeros(3) if event is None else conversions.vec3(event.impulse)
        other = None if event is None else self._vehicle._world._actor_named(event.other)
        self._last_obs = data.RoarPyCollisionSensorData(self._vehicle, other, impulse)
        return self._last_obs
