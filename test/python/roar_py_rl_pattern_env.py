"""An RL environment of ROAR_PY_RL's pattern (its RoarRLEnv and RoarRLSimEnv, written here) on roar_sim:
a gymnasium.Env over a ROAR_PY actor and world that steps by run_until_complete on the event loop, reads
the location, roll-pitch-yaw, velocimeter and collision sensors, measures progress with
RoarPyWaypointsTracker (trace_point, delta_distance_projection, trace_forward_projection,
get_interpolated_waypoint), rewards distance travelled and ends an episode at a collision; and its training
script's action filter. test_roar_py_rl_pattern steps it; bench/roar_py_bench.py times it."""
import asyncio
import warnings

import numpy as np

import roar_py_interface as rpi

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    import gymnasium as gym

# The training script's observations (ROAR_PY_RL's training/env_util.py keeps these; the camera is not kept).
KEPT = ["gyroscope", "waypoints_information", "local_velocimeter"]


class WaypointRewardEnv(gym.Env):
    """ROAR_PY_RL's RoarRLSimEnv, in outline: its calls, its reward and its termination."""

    metadata = {"render_modes": ["rgb_array"]}

    def __init__(self, actor, waypoints, location, rpy, velocity, collision, world, collision_threshold=30.0,
                 waypoint_information_distances=(0.0, 10.0, 30.0)):
        self.roar_py_actor = actor
        self.roar_py_world = world
        self.location_sensor, self.rpy_sensor, self.velocity_sensor = location, rpy, velocity
        self.collision_sensor = collision
        self.collision_threshold = collision_threshold
        self.distances = waypoint_information_distances
        self.action_space = actor.get_action_spec()
        self.observation_space = gym.spaces.Dict({
            **actor.get_gym_observation_spec().spaces,
            "waypoints_information": gym.spaces.Dict({f"waypoint_{d}": gym.spaces.Box(-np.inf, np.inf, (4,))
                                                      for d in waypoint_information_distances})})
        self.tracker = rpi.RoarPyWaypointsTracker(waypoints)
        self.projection = rpi.RoarPyWaypointsProjection(0, 0.0)
        self.travelled = 0.0
        self.visualizer = rpi.RoarPyVisualizer(actor)

    def _run(self, coroutine):
        return asyncio.get_event_loop().run_until_complete(coroutine)

    def _observe(self):
        # The sensors are the actor's: one read each. (ROAR_PY_RL reads them through the actor and again
        # one by one; a collision sensor read twice, here as over CARLA, gives its event to the first read.)
        self._run(self.roar_py_actor.receive_observation())
        location = self.location_sensor.get_last_gym_observation()
        last = self.projection
        self.projection = self.tracker.trace_point(location, last.waypoint_idx)
        self.travelled = self.tracker.delta_distance_projection(last, self.projection)
        yaw = self.rpy_sensor.get_last_gym_observation()[2]
        info = {}
        for distance in self.distances:
            ahead = self.tracker.get_interpolated_waypoint(self.tracker.trace_forward_projection(self.projection, distance))
            delta = ahead.location[:2] - location[:2]
            info[f"waypoint_{distance}"] = np.array([
                np.cos(yaw) * delta[0] + np.sin(yaw) * delta[1], -np.sin(yaw) * delta[0] + np.cos(yaw) * delta[1],
                rpi.normalize_rad(ahead.roll_pitch_yaw[2] - yaw), ahead.lane_width])
        observation = self.roar_py_actor.get_last_gym_observation().copy()
        observation["waypoints_information"] = info
        return observation

    def step(self, action):
        self._run(self.roar_py_actor.apply_action(action))
        self._run(self.roar_py_world.step())
        observation = self._observe()
        impulse = np.linalg.norm(self.collision_sensor.get_last_gym_observation())
        terminated = bool(impulse >= self.collision_threshold)
        reward = -(impulse - self.collision_threshold) if terminated else self.travelled * 20.0
        return observation, reward, terminated, False, {"world_time": self.roar_py_world.last_tick_elapsed_seconds}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        location, rpy = self.roar_py_world.spawn_points[0]
        self.roar_py_actor.set_transform(location + np.array([0.0, 0.0, 0.5]), rpy)
        self.roar_py_actor.set_linear_3d_velocity(np.zeros(3))
        self.roar_py_actor.set_angular_velocity(np.zeros(3))
        self._run(self.roar_py_world.step())
        observation = self._observe()
        self.travelled = 0.0
        return observation, {"world_time": self.roar_py_world.last_tick_elapsed_seconds}

    def render(self):
        image = self.visualizer.render()
        return None if image is None else np.asarray(image.convert("RGB"))


# The waypoints ahead (and behind) its training script observes, m.
TRAINING_DISTANCES = (-10.0, 0.0, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 40.0, 50.0, 100.0)


def make_env(instance, camera_size=(96, 48), distances=(0.0, 10.0, 30.0)) -> WaypointRewardEnv:
    """ROAR_PY_RL's sensor set on a vehicle.tesla.model3 at the map's first spawn point, synchronous at 20 Hz
    (its training script's camera is 400 x 200, its distances TRAINING_DISTANCES)."""
    world = instance.world
    world.set_control_steps(0.05, 0.005)
    world.set_asynchronous(False)
    asyncio.set_event_loop(asyncio.new_event_loop())
    location, rpy = world.spawn_points[0]
    vehicle = world.spawn_vehicle("vehicle.tesla.model3", location + np.array([0.0, 0.0, 2.0]), rpy, True, "vehicle")
    collision = vehicle.attach_collision_sensor(np.zeros(3), np.zeros(3), name="collision_sensor")
    velocimeter = vehicle.attach_velocimeter_sensor("velocimeter")
    vehicle.attach_local_velocimeter_sensor("local_velocimeter")
    location_sensor = vehicle.attach_location_in_world_sensor("location")
    rpy_sensor = vehicle.attach_roll_pitch_yaw_sensor("roll_pitch_yaw")
    vehicle.attach_gyroscope_sensor("gyroscope")
    vehicle.attach_camera_sensor(rpi.RoarPyCameraSensorDataRGB, np.array([-2.0 * vehicle.bounding_box.extent[0], 0.0,
                                 3.0 * vehicle.bounding_box.extent[2]]), np.array([0, 10 / 180.0 * np.pi, 0]),
                                 image_width=camera_size[0], image_height=camera_size[1])
    return WaypointRewardEnv(vehicle, world.maneuverable_waypoints, location_sensor, rpy_sensor, velocimeter,
                             collision, world, waypoint_information_distances=distances)


class SimplifiedActions(gym.ActionWrapper):
    """ROAR_PY_RL's SimplifyCarlaActionFilter, in outline: throttle and brake on one axis, steer on another; it
    sets its space through gymnasium's private attribute, as ROAR_PY_RL does."""

    def __init__(self, env):
        super().__init__(env)
        self._action_space = gym.spaces.Dict({"throttle": gym.spaces.Box(-1.0, 1.0, (1,), np.float32),
                                              "steer": gym.spaces.Box(-1.0, 1.0, (1,), np.float32)})

    def action(self, action):
        return {"throttle": np.clip(action["throttle"], 0.0, 1.0), "brake": np.clip(-action["throttle"], 0.0, 1.0),
                "steer": action["steer"], "hand_brake": 0.0, "reverse": 0.0}


def training_env(env, max_episode_steps: int = 30):
    """The training script's wrapping: its action filter, FilterObservation keeping KEPT, a time limit and
    episode statistics."""
    return gym.wrappers.RecordEpisodeStatistics(gym.wrappers.TimeLimit(
        gym.wrappers.FilterObservation(SimplifiedActions(env), KEPT), max_episode_steps=max_episode_steps))
