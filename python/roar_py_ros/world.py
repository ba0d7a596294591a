"""roar_sim's world as ROAR_PY's: its map's waypoints and spawn points, its clock and stepping, its cars."""
import asyncio
import fnmatch
import math
import threading
import time
import typing
import warnings

import numpy as np
import rospy

import roar_py_interface as rpi

from . import connection, conversions
from .connection import RoarSimError
from .sensor_host import WorldSensors, _finite_vector, ros_safe
from .vehicle import RoarPyRosVehicle

WAIT_TIMEOUT = 30.0  # wall seconds
ASYNC_POLL = 0.002  # wall seconds between looks at the clock in asynchronous mode
# The longest physics substep (s): CARLA's tyre friction is too stiff for roar_sim's explicit step beyond
# it (physics_test ASpunUpWheelLandsWithoutThrowingTheCarBack); CARLA's own substeps are at most as long as
# asked, so shorter ones are what a program asked for.
MAX_SUBSTEP = 0.005


class RoarPyRosWorld(rpi.RoarPyWorld):
    def __init__(self, instance):
        from geometry_msgs.msg import PoseArray
        from roar_ros.msg import MapInfo, WaypointArray

        self._instance = instance
        self._services = instance._services
        self._vehicles: typing.Dict[str, RoarPyRosVehicle] = {}
        self._world_sensors = WorldSensors(self)
        self._cond = threading.Condition()
        self._waypoints_msg = None
        self._waypoints_count = 0
        self._spawn_msg = None
        self._spawn_count = 0
        self._map_info = None
        self._clock = 0.0
        self._waypoint_cache = None
        self._last_step_time = None
        with connection.ros_threads():
            self._subs = [
                rospy.Subscriber("/waypoints", WaypointArray, self._on_waypoints, queue_size=1),
                rospy.Subscriber("/spawn_points", PoseArray, self._on_spawn_points, queue_size=1),
                rospy.Subscriber("/roar_sim/map", MapInfo, self._on_map, queue_size=1),
            ]
        self._clock_sub = None
        self._refresh_settings()
        self._wait(lambda: self._waypoints_msg is not None and self._spawn_msg is not None,
                   "waypoint_server's /waypoints and /spawn_points")

    # ---- subscriptions -------------------------------------------------------------------------------------
    def _on_waypoints(self, msg):
        with self._cond:
            self._waypoints_msg, self._waypoint_cache = msg, None
            self._waypoints_count += 1
            self._cond.notify_all()

    def _on_spawn_points(self, msg):
        with self._cond:
            self._spawn_msg = msg
            self._spawn_count += 1
            self._cond.notify_all()

    def _on_map(self, msg):
        with self._cond:
            self._map_info = msg
            self._cond.notify_all()

    def _on_clock(self, msg):
        with self._cond:
            self._clock = msg.clock.to_sec()
            self._cond.notify_all()

    def _wait(self, ready, what: str, timeout: float = WAIT_TIMEOUT):
        deadline = time.time() + timeout
        with self._cond:
            while not ready():
                if not self._instance._sim_alive():
                    raise RoarSimError(f"roar_sim has gone away while waiting for {what}")
                if time.time() > deadline:
                    raise RoarSimError(f"no {what} within {timeout:.0f} s")
                self._cond.wait(0.2)

    def _check_open(self):
        self._instance._check_open()

    # ---- settings -----------------------------------------------------------------------------------------
    def _refresh_settings(self):
        from roar_ros.srv import GetWorldInfo

        info = self._services.call("/roar_sim/get_world_info", GetWorldInfo)
        self._mode, self._control_dt, self._physics_dt = info.mode, info.control_dt, info.physics_dt
        self._sim_time = info.stamp.to_sec()
        self._follow_clock()
        return info

    def _follow_clock(self):
        """/clock is followed in asynchronous mode only: a synchronous step's answer carries its time, and a
        message a tick would cost every step a wake-up of this process (bench/roar_py_bench.py)."""
        from rosgraph_msgs.msg import Clock

        if self.is_asynchronous and self._clock_sub is None:
            with connection.ros_threads():
                self._clock_sub = rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=1, tcp_nodelay=True)
        elif not self.is_asynchronous and self._clock_sub is not None:
            self._clock_sub.unregister()
            self._clock_sub = None

    def _set_stepping(self, **fields):
        """Changes roar_sim's stepping; fields not given are kept (the pace too: 0 there is flat out)."""
        from roar_ros.srv import SetStepping

        fields.setdefault("real_time_factor", -1.0)
        response = self._services.call("/roar_sim/set_stepping", SetStepping, check=False, **fields)
        if not response.success:
            raise ValueError(f"roar_sim refused the stepping settings: {response.message}")
        self._mode, self._control_dt, self._physics_dt = response.mode, response.control_dt, response.physics_dt
        self._follow_clock()

    def set_asynchronous(self, asynchronous: bool):
        """Asynchronous: roar_sim runs on by itself at wall-clock time, as CARLA's server does; synchronous:
        one control step per step(). Either order with set_control_steps gives the same."""
        self._check_open()
        self._set_stepping(mode="async" if asynchronous else "step", real_time_factor=1.0 if asynchronous else -1.0)

    @property
    def is_asynchronous(self) -> bool:
        return self._mode == "async"

    def set_control_steps(self, control_timestep: float, control_substimestep: float):
        """The control step and the longest physics substep (s), as CARLA's fixed_delta_seconds and
        max_substep_delta_time; the pace is left alone. A control step of 0 (CARLA's variable step, for
        asynchronous mode) keeps roar_sim's: its control step is always fixed. Substeps are at most
        MAX_SUBSTEP long, and divide the control step evenly."""
        self._check_open()
        for value, what in ((control_timestep, "control_timestep"), (control_substimestep, "control_substimestep")):
            if not np.isfinite(value) or value < 0:
                raise ValueError(f"set_control_steps: {what} must be >= 0 s, got {value}")
        values = {}
        if control_timestep > 0:
            values["control_dt"] = float(control_timestep)
        if control_substimestep > 0:
            control_dt = values.get("control_dt", self._control_dt)
            whole = control_dt / control_substimestep
            if abs(whole - round(whole)) > 1e-6 or whole < 1 - 1e-9:
                # ROAR_PY's CARLA backend asserts the same.
                raise ValueError(f"set_control_steps: the control step ({control_dt} s) must be a whole multiple of "
                                 f"control_substimestep ({control_substimestep} s)")
            substeps = math.ceil(control_dt / min(control_substimestep, MAX_SUBSTEP) - 1e-9)
            values["physics_dt"] = control_dt / substeps
        self._set_stepping(**values)
        for vehicle in self._vehicles.values():
            vehicle.control_timestep = self._control_dt

    @property
    def control_timestep(self) -> float:
        return self._control_dt

    @control_timestep.setter
    def control_timestep(self, control_timestep: float):
        """As ROAR_PY's: the same number of substeps in the new control step."""
        substeps = max(1, round(self._control_dt / self._physics_dt))
        self.set_control_steps(control_timestep, control_timestep / substeps)

    @property
    def contorl_subtimestep(self) -> float:
        """ROAR_PY's spelling."""
        return self._physics_dt

    @contorl_subtimestep.setter
    def contorl_subtimestep(self, contorl_subtimestep: float):
        self.set_control_steps(self._control_dt, contorl_subtimestep)

    control_subtimestep = contorl_subtimestep

    @property
    def last_tick_elapsed_seconds(self) -> float:
        """Simulated seconds since roar_sim started, at the last step."""
        return self._sim_time

    # ---- stepping -----------------------------------------------------------------------------------------
    async def step(self) -> float:
        """Synchronous: simulates one control step (every car's last action held) and returns its length.
        Asynchronous: waits for roar_sim's next tick and returns the simulated time since the last step."""
        self._check_open()
        # Yields to the event loop once a step, as CARLA's backend does: a Ctrl-C (asyncio cancels the main
        # task) and the program's other tasks get their turn (test_roar_py_lifecycle
        # test_ctrl_c_ends_a_program_whose_steps_never_wait).
        await asyncio.sleep(0)
        before = self._sim_time
        if self.is_asynchronous:
            await self._next_tick(before)
            with self._cond:
                self._sim_time = self._clock
            return self._sim_time - before
        from roar_ros.srv import Step

        vehicles = [v for v in self._vehicles.values() if not v.is_closed()]
        driven = [v for v in vehicles if v.control is not None]
        response = self._services.call("/roar_sim/step", Step, check=False, ticks=1,
                                       vehicle_names=[v.ros_name for v in driven],
                                       controls=[v.control for v in driven], observe=self._observed(vehicles))
        if not response.success:
            if "only served in mode" in response.message:
                self._refresh_settings()
            raise RoarSimError(f"roar_sim refused the step: {response.message}")
        self._take_snapshots(response.vehicles)
        self._sim_time = response.stamp.to_sec()
        return self._sim_time - before

    async def _next_tick(self, after: float):
        """Until roar_sim's clock passes after, letting the program's other tasks run meanwhile."""
        start = time.time()
        next_alive_check = start + 0.5
        while True:
            with self._cond:
                if self._clock > after + 1e-9:
                    return
            now = time.time()
            if now > next_alive_check:
                next_alive_check = now + 0.5
                if not self._instance._sim_alive():
                    raise RoarSimError("roar_sim has gone away while waiting for a tick of roar_sim")
            if now > start + WAIT_TIMEOUT:
                raise RoarSimError(f"no tick of roar_sim within {WAIT_TIMEOUT:.0f} s")
            await asyncio.sleep(ASYNC_POLL)

    def _observed(self, vehicles) -> typing.List[str]:
        """What a step's reply should tell of: the cars, and the world's own sensors when it has some."""
        return [v.ros_name for v in vehicles] + ([self._world_sensors.ros_name] if self._world_sensors.get_sensors() else [])

    def _take_snapshots(self, snapshots):
        by_name = {v.ros_name: v for v in self._vehicles.values()}
        for snapshot in snapshots:
            if snapshot.name in by_name:
                by_name[snapshot.name]._on_snapshot(snapshot)
            elif snapshot.name == self._world_sensors.ros_name:
                self._world_sensors._take_sensor_stamps(snapshot)

    def _observe(self, vehicles):
        from roar_ros.srv import Step

        response = self._services.call("/roar_sim/step", Step, ticks=0, observe=[v.ros_name for v in vehicles])
        self._take_snapshots(response.vehicles)

    # ---- the map -----------------------------------------------------------------------------------------
    @property
    def map_name(self) -> str:
        return self._waypoints_msg.map_name

    @property
    def maneuverable_waypoints(self) -> typing.List[rpi.RoarPyWaypoint]:
        with self._cond:
            if self._waypoint_cache is None:
                self._waypoint_cache = [
                    rpi.RoarPyWaypoint(np.array([w.location.x, w.location.y, w.location.z]),
                                       np.array([w.roll, w.pitch, w.yaw]), w.lane_width)
                    for w in self._waypoints_msg.waypoints]
            return list(self._waypoint_cache)

    @property
    def comprehensive_waypoints(self) -> typing.Dict[int, typing.List[rpi.RoarPyWaypoint]]:
        """Two lanes, each its two edges per waypoint (edge, edge, edge, edge, ...): lane 0 from the left
        edge to the centre line, lane 1 from the centre line to the right edge."""
        lanes: typing.Dict[int, typing.List[rpi.RoarPyWaypoint]] = {0: [], 1: []}
        for w in self.maneuverable_waypoints:
            left, right = w.line_representation
            half = w.lane_width / 2.0
            lanes[0] += [rpi.RoarPyWaypoint(left, w.roll_pitch_yaw, half), rpi.RoarPyWaypoint(w.location, w.roll_pitch_yaw, half)]
            lanes[1] += [rpi.RoarPyWaypoint(w.location, w.roll_pitch_yaw, half), rpi.RoarPyWaypoint(right, w.roll_pitch_yaw, half)]
        return lanes

    @property
    def spawn_points(self) -> typing.List[typing.Tuple[np.ndarray, np.ndarray]]:
        """The start grid: (location, roll_pitch_yaw) of each slot, pole first."""
        return [(np.array([p.position.x, p.position.y, p.position.z]), conversions.quaternion_to_rpy(p.orientation))
                for p in self._spawn_msg.poses]

    def get_geolocation(self, location: np.ndarray) -> np.ndarray:
        """[latitude deg, longitude deg, altitude m] of a location (or an N x 3 array of them)."""
        self._check_open()
        from geometry_msgs.msg import Point
        from roar_ros.srv import GetGeolocation

        points = np.asarray(location, dtype=np.float64)
        single = points.ndim == 1
        points = points.reshape(-1, 3) if points.size % 3 == 0 else None
        if points is None or not np.all(np.isfinite(points)):
            raise ValueError(f"get_geolocation: location must be [x, y, z] (or N x 3) finite metres, got {location!r}")
        response = self._services.call("/roar_sim/get_geolocation", GetGeolocation,
                                        points=[Point(*p) for p in points])
        out = np.stack([response.latitude, response.longitude, response.altitude], axis=1)
        return out[0] if single else out

    # ---- actors ---------------------------------------------------------------------------------------------
    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def spawn_vehicle(self, blueprint_id: str, location: np.ndarray, roll_pitch_yaw: np.ndarray,
                      auto_gear: bool = True, name: str = "carla_vehicle", rgba: typing.Optional[np.ndarray] = None
                      ) -> typing.Optional[RoarPyRosVehicle]:
        """A car of a blueprint (those of /roar_sim/get_world_info; an unknown one is refused, naming them) at
        location and roll_pitch_yaw as given, as CARLA spawns it: above the road it falls onto it (never below it). rgba: 0..255. None where another car stands
        or there is no ground, as CARLA's try_spawn_actor (with a warning)."""
        self._check_open()
        from geometry_msgs.msg import Pose
        from roar_ros.srv import GetWorldInfo, SpawnVehicle
        from std_msgs.msg import ColorRGBA

        loc = _finite_vector(location, "spawn_vehicle: location")
        rpy = _finite_vector(roll_pitch_yaw, "spawn_vehicle: roll_pitch_yaw")
        colour = ColorRGBA()
        if rgba is not None:
            c = _finite_vector(rgba, "spawn_vehicle: rgba", 4)
            if np.any(c < 0) or np.any(c > 255):
                raise ValueError(f"spawn_vehicle: rgba channels must be in [0, 255], got {rgba!r}")
            colour = ColorRGBA(*(c[:3] / 255.0), 1.0)
        taken = {v.ros_name for v in self._vehicles.values()} | {self._world_sensors.ros_name}
        taken |= {v.name for v in self._services.call("/roar_sim/get_world_info", GetWorldInfo).vehicles}
        base = ros_safe(name)
        ros_name, n = base, 2
        while ros_name in taken:
            ros_name, n = f"{base}_{n}", n + 1
        if ros_name != name:
            # CARLA lets actors share a role name; ROS names are unique, so this car's topics say which it is.
            warnings.warn(f"spawn_vehicle: '{name}' is {'taken' if base in taken else 'no ROS name'}: this car is "
                          f"'{ros_name}' on ROS (/{ros_name}/odom, ...), '{name}' here", conversions.RoarPyCompatibilityWarning,
                          stacklevel=4)
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = loc
        q = conversions.rpy_to_quaternion(rpy)
        pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q
        response = self._services.call("/roar_sim/spawn_vehicle", SpawnVehicle, check=False, name=ros_name,
                                       model=str(blueprint_id), spawn_point=-1, pose=pose, as_given=True,
                                       colour=colour)
        if not response.success and "cannot place" in response.message:
            # CARLA's try_spawn_actor gives None where the place is taken, and programs check for it.
            warnings.warn(f"spawn_vehicle('{blueprint_id}'): {response.message}: None, as CARLA returns",
                          conversions.RoarPyCompatibilityWarning, stacklevel=4)
            return None
        if not response.success:
            raise ValueError(f"spawn_vehicle('{blueprint_id}'): {response.message}")
        info = next(v for v in self._services.call("/roar_sim/get_world_info", GetWorldInfo).vehicles
                    if v.name == ros_name)
        vehicle = RoarPyRosVehicle(self, ros_name, str(blueprint_id), bool(auto_gear), name, info)
        self._vehicles[ros_name] = vehicle
        self._observe([vehicle])
        return vehicle

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_camera_sensor(self, target_datatype, location, roll_pitch_yaw, fov=90.0, image_width=800,
                             image_height=600, control_timestep=0.0, attachment_type=None, name="carla_camera",
                             bind_to: typing.Optional[RoarPyRosVehicle] = None):
        return self._host(bind_to, "attach_camera_sensor").attach_camera_sensor(
            target_datatype, location, roll_pitch_yaw, fov, image_width, image_height, control_timestep,
            attachment_type, name)

    @rpi.roar_py_append_item
    @rpi.roar_py_thread_sync
    def attach_lidar_sensor(self, location, roll_pitch_yaw, num_lasers=32, max_distance=10.0, points_per_second=56000,
                            rotation_frequency=10.0, upper_fov=10.0, lower_fov=-30.0, horizontal_fov=360.0,
                            atmosphere_attenuation_rate=0.004, dropoff_general_rate=0.45,
                            dropoff_intensity_limit_below=0.8, control_timestep=0.0, noise_std=0.0,
                            attachment_type=None, name="carla_lidar_sensor",
                            bind_to: typing.Optional[RoarPyRosVehicle] = None):
        return self._host(bind_to, "attach_lidar_sensor").attach_lidar_sensor(
            location, roll_pitch_yaw, num_lasers, max_distance, points_per_second, rotation_frequency, upper_fov,
            lower_fov, horizontal_fov, atmosphere_attenuation_rate, dropoff_general_rate,
            dropoff_intensity_limit_below, control_timestep, noise_std, attachment_type, name)

    def _host(self, bind_to, what: str):
        """A sensor's host: the car bound to, or with bind_to None the world (the sensor fixed in it)."""
        if bind_to is None:
            return self._world_sensors
        if not isinstance(bind_to, RoarPyRosVehicle) or bind_to not in self._vehicles.values():
            raise ValueError(f"{what}: bind_to must be a vehicle of this world or None, got {bind_to!r}")
        return bind_to

    def _actor_named(self, ros_name: typing.Optional[str]) -> typing.Optional[RoarPyRosVehicle]:
        """This world's car of a roar_sim name, or None (barriers, the ground, cars of other programs)."""
        vehicle = self._vehicles.get(ros_name) if ros_name else None
        return None if vehicle is None or vehicle.is_closed() else vehicle

    def get_actors(self) -> typing.List[RoarPyRosVehicle]:
        return [v for v in self._vehicles.values() if not v.is_closed()]

    def get_sensors(self) -> typing.List[rpi.RoarPySensor]:
        """The sensors on no car (attached with bind_to None), as ROAR_PY's CARLA world lists them."""
        return list(self._world_sensors.get_sensors())

    def get_all_sensors(self) -> typing.List[rpi.RoarPySensor]:
        return [s for v in self.get_actors() for s in v.get_sensors()] + self.get_sensors()

    @rpi.roar_py_remove_item
    @rpi.roar_py_thread_sync
    def remove_actor(self, actor: RoarPyRosVehicle):
        if actor not in self._vehicles.values():
            raise ValueError(f"remove_actor: {actor!r} is not an actor of this world")
        actor.close()

    @rpi.roar_py_remove_item
    @rpi.roar_py_thread_sync
    def remove_sensor(self, sensor: rpi.RoarPySensor):
        for vehicle in self.get_actors():
            if sensor in vehicle._sensors:
                return vehicle.remove_sensor(sensor)
        if sensor in self._world_sensors._sensors:
            return sensor.close()
        raise ValueError(f"remove_sensor: {sensor.name!r} is not a sensor in this world")

    def _vehicle_closed(self, vehicle: RoarPyRosVehicle):
        self._vehicles.pop(vehicle.ros_name, None)
        if self._instance._sim_alive():
            from roar_ros.srv import DestroyVehicle

            self._services.call("/roar_sim/destroy_vehicle", DestroyVehicle, check=False, name=vehicle.ros_name)

    def _forget_vehicles(self):
        """After a map load: roar_sim's cars are gone."""
        for vehicle in list(self._vehicles.values()):
            vehicle._release()
        self._vehicles.clear()
        self._world_sensors._release()

    def _reset_vehicle(self, vehicle, location, roll_pitch_yaw):
        from geometry_msgs.msg import Pose
        from roar_ros.srv import ResetVehicle

        if location is None:
            self._services.call("/roar_sim/reset_vehicle", ResetVehicle, name=vehicle.ros_name, spawn_point=0)
        else:
            pose = Pose()
            pose.position.x, pose.position.y, pose.position.z = location
            q = conversions.rpy_to_quaternion(roll_pitch_yaw)
            pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q
            self._services.call("/roar_sim/reset_vehicle", ResetVehicle, name=vehicle.ros_name, spawn_point=-1, pose=pose,
                                as_given=True)
        self._observe([vehicle])

    def _set_velocity(self, vehicle, linear, angular):
        from geometry_msgs.msg import Vector3
        from roar_ros.srv import SetVehicleVelocity

        self._services.call("/roar_sim/set_vehicle_velocity", SetVehicleVelocity, name=vehicle.ros_name,
                            linear=Vector3(*linear), angular=Vector3(*angular))
        self._observe([vehicle])

    def clean_actors_not_registered(self, typeid_wildcard: typing.Sequence[str] = ("vehicle.*", "sensor.*")):
        """As ROAR_PY's: destroys the actors in roar_sim this world did not spawn whose type id (a car's
        blueprint id) matches one of the wildcards; a car's sensors go with it."""
        from roar_ros.srv import DestroyVehicle, GetWorldInfo

        if isinstance(typeid_wildcard, str):
            typeid_wildcard = [typeid_wildcard]
        mine = {v.ros_name for v in self._vehicles.values()}
        for info in self._services.call("/roar_sim/get_world_info", GetWorldInfo).vehicles:
            if info.name not in mine and any(fnmatch.fnmatchcase(info.blueprint, w) for w in typeid_wildcard):
                self._services.call("/roar_sim/destroy_vehicle", DestroyVehicle, name=info.name)

    # ---- debug drawing (CARLA's world.debug, drawn in rviz on /roar_sim/debug_markers) ---------------------
    def _shape(self, kind, points, color, size=0.0, arrow_size=0.0, text="", life_time=-1.0):
        from geometry_msgs.msg import Point
        from roar_ros.msg import DebugShape
        from std_msgs.msg import ColorRGBA

        c = _finite_vector(color, f"draw_{kind}: color (0..255)", 3 if len(color) == 3 else 4) / 255.0
        return DebugShape(kind=kind, points=[Point(*_finite_vector(p, f"draw_{kind}: point")) for p in points],
                          color=ColorRGBA(c[0], c[1], c[2], c[3] if c.size == 4 else 1.0), size=float(size),
                          arrow_size=float(arrow_size), text=str(text), life_time=float(life_time))

    def _send(self, shapes):
        from roar_ros.srv import DrawDebug

        self._check_open()
        response = self._services.call("/roar_sim/draw_debug", DrawDebug, check=False, shapes=shapes)
        if not response.success:
            raise ValueError(f"draw: {response.message}")

    def _draw(self, *args, **kwargs):
        self._send([self._shape(*args, **kwargs)])

    def draw_point(self, location, size=0.1, color=(255, 0, 0), life_time=-1.0):
        self._draw("point", [location], color, size, life_time=life_time)

    def draw_line(self, begin, end, thickness=0.1, color=(255, 0, 0), life_time=-1.0):
        self._draw("line", [begin, end], color, thickness, life_time=life_time)

    def draw_arrow(self, begin, end, thickness=0.1, arrow_size=0.1, color=(255, 0, 0), life_time=-1.0):
        self._draw("arrow", [begin, end], color, thickness, arrow_size, life_time=life_time)

    def draw_string(self, location, text, color=(255, 255, 255), size=1.0, life_time=-1.0):
        self._draw("text", [location], color, size, text=text, life_time=life_time)

    def draw_waypoints(self, waypoints: typing.Sequence[rpi.RoarPyWaypoint], length=0.5, color=(0, 255, 0)):
        """Each waypoint as an arrow along its heading: what ROAR_PY users draw with CARLA's debug."""
        shapes = []
        for w in waypoints:
            tip = w.location + rpi.euler2mat(*w.roll_pitch_yaw) @ np.array([length, 0.0, 0.0])
            shapes.append(self._shape("arrow", [w.location, tip], color, 0.1, 0.1))
        self._send(shapes)

    def clear_debug(self):
        from roar_ros.srv import DrawDebug

        self._services.call("/roar_sim/draw_debug", DrawDebug, check=False, clear=True)

    def close(self):
        for sub in self._subs + ([self._clock_sub] if self._clock_sub is not None else []):
            sub.unregister()
        self._subs, self._clock_sub = [], None
