"""A car in roar_sim as ROAR_PY's vehicle: its state, its actions and its sensors, with ROAR_PY's CARLA
backend's methods, arguments and default names."""
import dataclasses
import itertools
import typing

import numpy as np
import rospy

import roar_py_interface as rpi

from . import connection, conversions, sensors
from .sensor_host import SensorHost, _finite_vector


@dataclasses.dataclass
class RoarPyRosBoundingBox:
    """ROAR_PY's CARLA bounding box: half the body's size (m), its centre in the car's frame (m) and its
    rotation (rad)."""

    extent: np.ndarray
    location: np.ndarray
    rotation: np.ndarray


# Actor ids, as CARLA numbers every actor it spawns (a car's carla_id).
_ACTOR_IDS = itertools.count(1)
# CARLA 0.9.12-0.9.14's semantic tag of vehicles (sensors.camera_sensor.CARLA_SEMANTIC_LABEL_COLOR_MAP: "Car").
CARLA_VEHICLE_TAG = 10

class RoarPyRosVehicle(SensorHost, rpi.RoarPyBaseVehicle, rpi.RoarPyResettableActor):
    def __init__(self, world, ros_name: str, blueprint_id: str, auto_gear: bool, name: str, info):
        rpi.RoarPyActor.__init__(self, name=name, control_timestep=world.control_timestep)
        self._world = world
        self.ros_name = ros_name
        self.blueprint_id = blueprint_id
        self.model = info.model
        self.auto_gear = auto_gear
        self.num_gears = max(1, info.gears)
        extent = conversions.vec3(info.extent)
        self.bounding_box = RoarPyRosBoundingBox(extent, np.array([0.0, 0.0, extent[2]]), np.zeros(3))
        self._actions = conversions.ActionReader(f"vehicle '{name}'", auto_gear, self.num_gears)
        self._closed = False
        self._init_sensors()
        self._odom = None
        self._odom_stamp = -1.0
        self._acceleration = np.zeros(3)
        self._pending_collisions: typing.Dict[int, list] = {}
        self.control = None  # roar_sim's VehicleControl of the last action
        self.carla_id = next(_ACTOR_IDS)
        from nav_msgs.msg import Odometry
        from roar_ros.msg import CollisionEvent, QueueDepths, VehicleControl

        with connection.ros_threads():
            self._odom_sub = rospy.Subscriber(f"/{ros_name}/odom", Odometry, self._on_odom, queue_size=2,
                                              tcp_nodelay=True)
            self._collision_sub = rospy.Subscriber(f"/{ros_name}/collision", CollisionEvent, self._on_collision,
                                                   queue_size=100, tcp_nodelay=True)
            # As deep as the C++ drivers' (msg/QueueDepths.msg): a recorder whose link lags loses no control.
            self._control_pub = rospy.Publisher(f"/{ros_name}/control", VehicleControl,
                                                queue_size=QueueDepths.PER_TICK, tcp_nodelay=True)

    def __repr__(self):
        return f"RoarPyRosVehicle(name={self.name!r}, blueprint={self.blueprint_id!r}, roar_sim name={self.ros_name!r})"

    # ---- state ----------------------------------------------------------------------------------------------
    def _on_odom(self, msg):
        self._take_odometry(msg)

    def _take_odometry(self, msg):
        """The newest odometry; the acceleration is the velocity's change since the one before (CARLA's actor
        acceleration is its velocity's change over the last tick too)."""
        with self._lock:
            stamp = msg.header.stamp.to_sec()
            if stamp < self._odom_stamp:
                return
            if self._odom is not None and stamp > self._odom_stamp:
                self._acceleration = (self._world_velocity(msg) - self._world_velocity(self._odom)) / \
                    (stamp - self._odom_stamp)
            self._odom, self._odom_stamp = msg, stamp

    @staticmethod
    def _world_velocity(odom) -> np.ndarray:
        return conversions.rotation_matrix(odom.pose.pose.orientation) @ conversions.vec3(odom.twist.twist.linear)

    def _on_collision(self, msg):
        if self._world.is_asynchronous:
            self._add_collisions([msg])

    def _add_collisions(self, events):
        with self._lock:
            for pending in self._pending_collisions.values():
                pending.extend(events)

    def _on_snapshot(self, snapshot):
        self._take_odometry(snapshot.odometry)
        if snapshot.collisions:
            self._add_collisions(list(snapshot.collisions))
        self._take_sensor_stamps(snapshot)

    def _take_collisions(self, sensor) -> list:
        """The contacts since sensor last read them."""
        with self._lock:
            events = self._pending_collisions.get(id(sensor), [])
            self._pending_collisions[id(sensor)] = []
            return events

    def _odometry(self):
        self._check_open()
        if self._odom is None:
            self._world._observe([self])
        return self._odom

    # Locations, velocities and accelerations are float32, as ROAR_PY's CARLA backend converts CARLA's.
    def get_3d_location(self) -> np.ndarray:
        p = self._odometry().pose.pose.position
        return np.array([p.x, p.y, p.z], dtype=np.float32)

    def get_roll_pitch_yaw(self) -> np.ndarray:
        return conversions.quaternion_to_rpy(self._odometry().pose.pose.orientation)

    def get_linear_3d_velocity(self) -> np.ndarray:
        return self._world_velocity(self._odometry()).astype(np.float32)

    def get_angular_velocity(self) -> np.ndarray:
        odom = self._odometry()
        return conversions.rotation_matrix(odom.pose.pose.orientation) @ conversions.vec3(odom.twist.twist.angular)

    def get_acceleration(self) -> np.ndarray:
        """m/s^2 in the world frame, without gravity: the velocity's change over the last tick."""
        self._odometry()
        with self._lock:
            return self._acceleration.astype(np.float32)

    def set_transform(self, new_location: np.ndarray, new_rotation: np.ndarray) -> None:
        """Teleports the car to the location and rotation as given (above the road it falls onto it), its
        velocity kept, as CARLA's set_transform does."""
        self._check_open()
        location = _finite_vector(new_location, "set_transform: new_location")
        rotation = _finite_vector(new_rotation, "set_transform: new_rotation")
        linear, angular = self.get_linear_3d_velocity(), self.get_angular_velocity()
        self._world._reset_vehicle(self, location, rotation)
        if np.any(linear != 0.0) or np.any(angular != 0.0):
            self._world._set_velocity(self, linear, angular)

    def set_3d_location(self, new_location: np.ndarray) -> None:
        self.set_transform(new_location, self.get_roll_pitch_yaw())

    def set_roll_pitch_yaw(self, new_rotation_rpy: np.ndarray) -> None:
        self.set_transform(self.get_3d_location(), new_rotation_rpy)

    def set_linear_3d_velocity(self, target_linear_velocity: np.ndarray) -> None:
        self._check_open()
        self._world._set_velocity(self, _finite_vector(target_linear_velocity, "set_linear_3d_velocity: velocity"),
                                  self.get_angular_velocity())

    def set_angular_velocity(self, target_angular_velocity: np.ndarray) -> None:
        self._check_open()
        self._world._set_velocity(self, self.get_linear_3d_velocity(),
                                  _finite_vector(target_angular_velocity, "set_angular_velocity: velocity"))

    @property
    def carla_blueprint_type_id(self) -> str:
        return self.blueprint_id

    # ---- CARLA's actor members (roar_py_carla's RoarPyCarlaBase) ------------------------------------------
    @property
    def parent(self):
        """None: a car rides on nothing."""
        return None

    @property
    def carla_attributes(self) -> typing.Dict[str, str]:
        return {"role_name": self.name, "number_of_wheels": "4"}

    @property
    def carla_is_alive(self) -> bool:
        return not self._closed

    @property
    def semantic_labels(self) -> typing.List[int]:
        return [CARLA_VEHICLE_TAG]

    def set_enable_gravity(self, enable: bool = True) -> None:
        self._not_modelled("set_enable_gravity", enable)

    def set_simulate_physics(self, enable: bool = True) -> None:
        self._not_modelled("set_simulate_physics", enable)

    def _not_modelled(self, what: str, enable: bool) -> None:
        # CARLA takes both; roar_sim always simulates the car, so turning either off is said once and ignored.
        self._check_open()
        if not enable:
            self._actions.warnings.warn(what, f"{what}(False) is not modelled: roar_sim always simulates the car "
                                        "with gravity (said once)", stacklevel=3)

    # ---- actions --------------------------------------------------------------------------------------------
    def get_action_spec(self):
        # Built once: a control loop asks for it every step.
        if getattr(self, "_action_spec", None) is None:
            self._action_spec = rpi.vehicle_action_spec(self.auto_gear, self.num_gears)
        return self._action_spec

    async def _apply_action(self, action: typing.Any) -> bool:
        self._check_open()
        control = conversions.to_vehicle_control(self._actions.read(action), self.auto_gear)
        self.control = control
        if self._world.is_asynchronous:
            control.header.stamp = rospy.Time.now()
            self._control_pub.publish(control)
        return True

    async def _reset(self) -> None:
        self._check_open()
        self._world._reset_vehicle(self, None, None)

    # ---- sensors --------------------------------------------------------------------------------------------
    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_radar_sensor(self, location: np.ndarray, roll_pitch_yaw: np.ndarray, horizontal_fov: float = 30.0,
                            vertical_fov: float = 30.0, points_per_second: int = 1500, max_distance: float = 100.0,
                            control_timestep: float = 0.0, attachment_type=None,
                            name: str = "carla_radar_sensor") -> rpi.RoarPyRadarSensor:
        """CARLA's radar (sensor.other.radar, its defaults): detections of the road, barriers and cars in a
        cone, each with its velocity along the line of sight."""
        rate = self._rate(control_timestep, "attach_radar_sensor")
        sim_name = self._sim_sensor_name(name)
        radar = {"horizontal_fov": float(horizontal_fov), "vertical_fov": float(vertical_fov),
                 "points_per_second": float(points_per_second), "max_distance": float(max_distance)}
        spec = {"name": sim_name, "type": "radar", **self._mount(location, roll_pitch_yaw, "attach_radar_sensor"),
                "rate": rate, **radar}
        return self._attach(spec, lambda: sensors.RoarPyRosRadarSensor(self, name, sim_name, radar, rate))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_collision_sensor(self, location: np.ndarray = None, roll_pitch_yaw: np.ndarray = None,
                                attachment_type=None, name: str = "carla_collision_sensor") -> rpi.RoarPyCollisionSensor:
        sensor = self._keep(sensors.RoarPyRosCollisionSensor(self, name))
        with self._lock:
            self._pending_collisions[id(sensor)] = []
        return sensor

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_accelerometer_sensor(self, name: str = "carla_accelerometer_sensor"):
        return self._keep(sensors.RoarPyRosAccelerometerSensor(self, name))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_gyroscope_sensor(self, name: str = "carla_gyroscope_sensor"):
        return self._keep(sensors.RoarPyRosGyroscopeSensor(self, name))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_velocimeter_sensor(self, name: str = "carla_velocimeter_sensor"):
        return self._keep(sensors.RoarPyRosVelocimeterSensor(self, name))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_local_velocimeter_sensor(self, name: str = "carla_local_velocimeter_sensor"):
        return self._keep(sensors.RoarPyRosLocalVelocimeterSensor(self, name))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_roll_pitch_yaw_sensor(self, name: str = "carla_rpy_sensor"):
        return self._keep(sensors.RoarPyRosRollPitchYawSensor(self, name))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_framequat_sensor(self, name: str = "carla_framequat_sensor"):
        # As ROAR_PY's CARLA backend makes it: a quaternion read from a roll-pitch-yaw sensor of its own.
        return self._keep(rpi.RoarPyFrameQuatSensorFromRollPitchYaw(
            sensors.RoarPyRosRollPitchYawSensor(self, "carla_rpy_sensor"), name=name))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_location_in_world_sensor(self, name: str = "carla_location_in_world_sensor"):
        return self._keep(sensors.RoarPyRosLocationInWorldSensor(self, name))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_gnss_sensor(self, noise_altitude_bias: float = 0.0, noise_altitude_std: float = 0.0,
                           noise_latitude_bias: float = 0.0, noise_latitude_std: float = 0.0,
                           noise_longitude_bias: float = 0.0, noise_longitude_std: float = 0.0, noise_seed: int = 0,
                           control_timestep: float = 0.0, name: str = "carla_gnss_sensor"):
        """CARLA's GNSS: standard deviations and biases of latitude and longitude in degrees, of altitude in
        metres (roar_sim's noise is in metres: one degree of latitude is 111,320 m)."""
        metres_per_degree = 111_320.0
        bias = tuple(_finite_vector([noise_altitude_bias, noise_latitude_bias, noise_longitude_bias],
                                    "attach_gnss_sensor: noise_*_bias"))
        spec = {"horizontal_noise_std": float(max(noise_latitude_std, noise_longitude_std) * metres_per_degree),
                "vertical_noise_std": float(noise_altitude_std), "seed": int(noise_seed)}
        rate = self._rate(control_timestep, "attach_gnss_sensor")
        sim_name = self._sim_sensor_name(name)
        return self._attach({"name": sim_name, "type": "gnss", "rate": rate, **spec},
                            lambda: sensors.RoarPyRosGNSSSensor(self, name, sim_name, rate, bias))

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_occupancy_map_sensor(self, width: int, height: int, width_in_world: float, height_in_world: float,
                                    name: str = "carla_occupancy_map_sensor"):
        """ROAR_PY's occupancy map: the road drawn from the map's waypoints on a width x height image covering
        width_in_world x height_in_world metres around the car, its forward up (road 255, else 0)."""
        for value, what in ((width, "width"), (height, "height")):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value <= 0:
                raise ValueError(f"attach_occupancy_map_sensor: {what} must be a positive int, got {value!r}")
        for value, what in ((width_in_world, "width_in_world"), (height_in_world, "height_in_world")):
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"attach_occupancy_map_sensor: {what} must be positive metres, got {value!r}")
        producer = rpi.RoarPyOccupancyMapProducer(self._world.maneuverable_waypoints, int(width), int(height),
                                                  float(width_in_world), float(height_in_world))
        return self._keep(sensors.RoarPyRosOccupancyMapSensor(self, producer, name))

    @rpi.roar_py_remove_item
    @rpi.roar_py_thread_sync
    def remove_sensor(self, sensor: rpi.RoarPySensor):
        if sensor not in self._sensors:
            raise RuntimeError(f"Sensor {sensor.name!r} not found on '{self.name}'")
        sensor.close()

    def _sensor_closed(self, sensor):
        with self._lock:
            self._pending_collisions.pop(id(sensor), None)
        SensorHost._sensor_closed(self, sensor)

    # ---- life -----------------------------------------------------------------------------------------------
    def _check_open(self):
        if getattr(self, "_closed", True):
            raise RuntimeError(f"vehicle '{getattr(self, 'name', '?')}' is closed")
        self._world._check_open()

    def _release(self):
        """Closes the car on this side: its sensors and topics. Closed first, so that the sensors do not
        detach one by one from a car about to go (or already gone with its map)."""
        self._closed = True
        for sensor in list(self._sensors):
            sensor.close()
        for handle in (self._odom_sub, self._collision_sub, self._control_pub):
            handle.unregister()

    def close(self):
        if getattr(self, "_closed", True):
            return
        self._release()
        self._world._vehicle_closed(self)

    def is_closed(self) -> bool:
        return getattr(self, "_closed", True)
