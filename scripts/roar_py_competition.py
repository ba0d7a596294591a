#!/usr/bin/python3
"""A ROAR competition run against roar_sim, written here in the shape of ROAR's official runner
(augcog/ROAR_Competition competition_code): the same calls in the same order. A vehicle.tesla.model3
spawned a metre above Monza's first waypoint with the runner's sensors (a 1024x768 chase camera,
location, velocimeter, roll-pitch-yaw, a 50x50 occupancy map of 2 m, collision); 20 ticks to settle;
laps counted as the runner counts them (every waypoint of the three laps passed in order); a collision
over 100 N s puts the car back where it started and restarts the count, as the runner does.

    rosrun roar_ros roar_py_competition.py --entry competition --laps 3

Entries: `competition`, a controller of the kind ROAR's entries are (tuned to CARLA's car: corners at
2.2 g, braking at 12 m/s^2 and pure pursuit on the waypoints); `cautious`, the same at 1.6 g and 9 m/s^2;
`example`, ROAR_PY's documented waypoint follower at 20 m/s. Without a running roar_sim it starts its own (roar_py_ros). Prints a line per
lap and a summary; --output writes the result as YAML."""
import argparse
import asyncio
import math
import sys
import time
import typing

import numpy as np
import yaml

import roar_py_interface
import roar_py_ros

RESPAWN_IMPULSE = 100.0  # N s: the runner's major collision


class RoarCompetitionRule:
    """The official runner's rule: progress along three laps' waypoints, and respawn at the start."""

    def __init__(self, waypoints, vehicle, world):
        self.waypoints = waypoints
        self.vehicle = vehicle
        self.world = world
        self._last_vehicle_location = vehicle.get_3d_location()
        self._respawn_location = None
        self._respawn_rpy = None
        self.furthest_waypoints_index = 0

    def initialize_race(self):
        self._last_vehicle_location = self.vehicle.get_3d_location()
        distances = [np.linalg.norm(self._last_vehicle_location - w.location) for w in self.waypoints]
        closest = int(np.argmin(distances))
        self.waypoints = self.waypoints[closest + 1:] + self.waypoints[:closest + 1]
        self.furthest_waypoints_index = 0
        self._respawn_location = self._last_vehicle_location.copy()
        self._respawn_rpy = self.vehicle.get_roll_pitch_yaw().copy()

    def lap_finished(self, check_step: int = 5) -> bool:
        return self.furthest_waypoints_index + check_step >= len(self.waypoints)

    async def tick(self, check_step: int = 15):
        current = self.vehicle.get_3d_location()
        delta = current - self._last_vehicle_location
        norm = np.linalg.norm(delta)
        unit = delta / norm if norm >= 1e-5 else np.zeros(3)
        start = self.furthest_waypoints_index
        best, best_index = np.inf, 0
        for i, waypoint in enumerate(self.waypoints[start:min(start + check_step, len(self.waypoints))]):
            projection = np.clip(np.dot(waypoint.location - current, unit), 0, norm)
            distance = np.linalg.norm(waypoint.location - (current + projection * unit))
            if distance < best:
                best, best_index = distance, i
        self.furthest_waypoints_index += best_index
        self._last_vehicle_location = current

    async def respawn(self):
        self.vehicle.set_transform(self._respawn_location, self._respawn_rpy)
        self.vehicle.set_linear_3d_velocity(np.zeros(3))
        self.vehicle.set_angular_velocity(np.zeros(3))
        for _ in range(20):
            await self.world.step()
        self._last_vehicle_location = self.vehicle.get_3d_location()
        self.furthest_waypoints_index = 0


def filter_waypoints(location: np.ndarray, current_idx: int, waypoints: list) -> int:
    for i in range(current_idx, len(waypoints) + current_idx):
        if np.linalg.norm(location[:2] - waypoints[i % len(waypoints)].location[:2]) < 3:
            return i % len(waypoints)
    return current_idx


class Entry:
    """What every entry gets (the runner's arguments) and does (initialize, then step each tick)."""

    def __init__(self, maneuverable_waypoints, vehicle, camera_sensor=None, location_sensor=None,
                 velocity_sensor=None, rpy_sensor=None, occupancy_map_sensor=None, collision_sensor=None):
        self.maneuverable_waypoints = maneuverable_waypoints
        self.vehicle = vehicle
        self.camera_sensor = camera_sensor
        self.location_sensor = location_sensor
        self.velocity_sensor = velocity_sensor
        self.rpy_sensor = rpy_sensor
        self.occupancy_map_sensor = occupancy_map_sensor
        self.collision_sensor = collision_sensor
        self.current_waypoint_idx = 0

    def state(self):
        return (self.location_sensor.get_last_gym_observation(), self.rpy_sensor.get_last_gym_observation(),
                self.velocity_sensor.get_last_gym_observation())

    async def initialize(self):
        location, _, _ = self.state()
        self.current_waypoint_idx = filter_waypoints(location, 10, self.maneuverable_waypoints)


class ExampleEntry(Entry):
    """ROAR_PY's documented waypoint follower: 3 waypoints ahead, 20 m/s."""

    async def step(self):
        location, rotation, velocity = self.state()
        speed = np.linalg.norm(velocity)
        waypoints = self.maneuverable_waypoints
        self.current_waypoint_idx = filter_waypoints(location, self.current_waypoint_idx, waypoints)
        target = waypoints[(self.current_waypoint_idx + 3) % len(waypoints)]
        delta = roar_py_interface.normalize_rad(
            math.atan2(*(target.location - location)[1::-1]) - rotation[2])
        steer = np.clip(-8.0 / np.sqrt(speed) * delta / np.pi, -1.0, 1.0) if speed > 1e-2 else -np.sign(delta)
        throttle = 0.05 * (20.0 - speed)
        await self.vehicle.apply_action({"throttle": np.clip(throttle, 0.0, 1.0), "steer": steer,
                                         "brake": np.clip(-throttle, 0.0, 1.0), "hand_brake": 0.0, "reverse": 0,
                                         "target_gear": 0})


class CompetitionEntry(Entry):
    """A controller of the kind ROAR's entries are, tuned to CARLA's car: a speed profile from the waypoints'
    curvature at 2.2 g, braked into at 12 m/s^2 and read 0.7 s ahead (CARLA's brakes take half a second to
    bite), floored or braking hard as ROAR's entries drive (their telemetry's pedals are 0 or 1), pure
    pursuit on the waypoints with CARLA's 70 degree lock narrowing with speed. It sends target_gear as every
    entry does (ignored on the automatic car)."""

    CORNER_G = 2.2
    BRAKING = 12.0       # m/s^2
    TOP_SPEED = 90.0     # m/s
    PREVIEW = 0.7        # s
    WHEELBASE = 2.875    # m
    LOCK = math.radians(70.0)
    STEERING_CURVE = ((0.0, 1.0), (20 / 3.6, 0.9), (60 / 3.6, 0.8), (120 / 3.6, 0.7))  # CARLA's

    async def initialize(self):
        await super().initialize()
        self.points = np.array([w.location[:2] for w in self.maneuverable_waypoints])
        self.profile = self.speed_profile(self.points)

    def speed_profile(self, points: np.ndarray) -> np.ndarray:
        """The fastest speed at each waypoint: CORNER_G through the tightest bend within 20 m (radius
        through points 6 m either side), braked into at BRAKING."""
        count = len(points)
        span = 3
        a, b, c = np.roll(points, span, axis=0), points, np.roll(points, -span, axis=0)
        ab, bc, ca = (np.linalg.norm(a - b, axis=1), np.linalg.norm(b - c, axis=1), np.linalg.norm(c - a, axis=1))
        cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
        radius = np.where(cross > 1e-6, ab * bc * ca / (2 * np.maximum(cross, 1e-6)), 1e6)
        self.radius = radius
        corner = np.minimum(np.sqrt(self.CORNER_G * 9.81 * radius), self.TOP_SPEED)
        speed = np.min([np.roll(corner, k) for k in range(-10, 11)], axis=0)
        step = np.linalg.norm(np.roll(points, -1, axis=0) - points, axis=1)
        for _ in range(2):  # twice round: the braking zone before the first waypoint wraps
            for i in range(count - 1, -1, -1):
                following = speed[(i + 1) % count]
                speed[i] = min(speed[i], math.sqrt(following ** 2 + 2 * self.BRAKING * step[i]))
        return speed

    def lock_at(self, speed: float) -> float:
        kmh = [v for v, _ in self.STEERING_CURVE]
        return self.LOCK * float(np.interp(speed, kmh, [s for _, s in self.STEERING_CURVE]))

    def nearest_waypoint(self, location: np.ndarray) -> int:
        """The nearest waypoint from a little behind to 100 m ahead of the last one (never lost off-line)."""
        count = len(self.maneuverable_waypoints)
        window = (self.current_waypoint_idx + np.arange(-5, 50)) % count
        distances = np.linalg.norm(self.points[window] - location[:2], axis=1)
        return int(window[np.argmin(distances)])

    async def step(self):
        location, rotation, velocity = self.state()
        speed = float(np.linalg.norm(velocity))
        waypoints = self.maneuverable_waypoints
        self.current_waypoint_idx = self.nearest_waypoint(location)
        lookahead = float(np.clip(0.65 * speed, 10.0, 40.0))
        ahead = (self.current_waypoint_idx + int(round(lookahead / 2.0))) % len(waypoints)
        to_target = waypoints[ahead].location[:2] - location[:2]
        alpha = roar_py_interface.normalize_rad(math.atan2(to_target[1], to_target[0]) - rotation[2])
        wheel_angle = math.atan2(2.0 * self.WHEELBASE * math.sin(alpha), max(np.linalg.norm(to_target), 1.0))
        steer = float(np.clip(-wheel_angle / self.lock_at(speed), -1.0, 1.0))  # ROAR_PY steers right positive
        # The profile read PREVIEW seconds ahead: CARLA's brakes take half a second to bite.
        preview = (self.current_waypoint_idx + int(round(speed * self.PREVIEW / 2.0)) + 1) % len(waypoints)
        error = self.profile[preview] - speed
        # What grip the corner leaves for driving (full throttle is about 0.4 g).
        lateral = speed * speed / self.radius[self.current_waypoint_idx]
        budget = math.sqrt(max(0.0, (1.1 * self.CORNER_G * 9.81) ** 2 - lateral ** 2)) / 9.81
        # Floored or braking hard, as ROAR's entries drive CARLA's car (its telemetry: pedals 0 or 1).
        throttle, brake = (float(np.clip(0.3 + 0.5 * error, 0.0, min(1.0, budget))), 0.0) if error > -0.5 else \
            (0.0, 1.0)
        await self.vehicle.apply_action({"throttle": throttle, "steer": steer, "brake": brake, "hand_brake": 0.0,
                                         "reverse": 0, "target_gear": 0})


class CautiousEntry(CompetitionEntry):
    """The competition entry tuned for safety over pace, as a student's first tuning is: corners at 1.6 g,
    braking at 9 m/s^2."""

    CORNER_G = 1.6
    BRAKING = 9.0


ENTRIES = {"competition": CompetitionEntry, "cautious": CautiousEntry, "example": ExampleEntry}


async def evaluate_solution(world, solution_constructor, max_seconds: float, laps: int, log,
                            camera_size: typing.Tuple[int, int] = (1024, 768)) -> dict:
    waypoints = world.maneuverable_waypoints
    vehicle = world.spawn_vehicle("vehicle.tesla.model3", waypoints[0].location + np.array([0, 0, 1]),
                                  waypoints[0].roll_pitch_yaw, True)
    camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB,
        np.array([-2.0 * vehicle.bounding_box.extent[0], 0.0, 3.0 * vehicle.bounding_box.extent[2]]),
        np.array([0, 10 / 180.0 * np.pi, 0]), image_width=camera_size[0], image_height=camera_size[1])
    location_sensor = vehicle.attach_location_in_world_sensor()
    velocity_sensor = vehicle.attach_velocimeter_sensor()
    rpy_sensor = vehicle.attach_roll_pitch_yaw_sensor()
    occupancy_map_sensor = vehicle.attach_occupancy_map_sensor(50, 50, 2.0, 2.0)
    collision_sensor = vehicle.attach_collision_sensor(np.zeros(3), np.zeros(3))
    solution = solution_constructor(waypoints, vehicle, camera, location_sensor, velocity_sensor, rpy_sensor,
                                    occupancy_map_sensor, collision_sensor)
    rule = RoarCompetitionRule(waypoints * laps, vehicle, world)
    for _ in range(20):
        await world.step()
    rule.initialize_race()
    start_time = world.last_tick_elapsed_seconds
    lap_length = len(waypoints)
    lap_marks, respawns, wall = [], [], time.time()
    await vehicle.receive_observation()
    await solution.initialize()
    finished = False
    while world.last_tick_elapsed_seconds - start_time <= max_seconds:
        await vehicle.receive_observation()
        await rule.tick()
        impulse = np.linalg.norm(collision_sensor.get_last_observation().impulse_normal)
        if impulse > RESPAWN_IMPULSE:
            where = vehicle.get_3d_location()
            t = world.last_tick_elapsed_seconds - start_time
            respawns.append({"t": round(t, 2), "x": round(float(where[0]), 1), "y": round(float(where[1]), 1)})
            log(f"major collision of {impulse:.0f} N s at t = {t:.2f} s, ({where[0]:.0f}, {where[1]:.0f}): respawn")
            await rule.respawn()
            lap_marks = []
        while len(lap_marks) < laps and rule.furthest_waypoints_index >= (len(lap_marks) + 1) * lap_length - 5:
            lap_marks.append(world.last_tick_elapsed_seconds - start_time)
            previous = lap_marks[-2] if len(lap_marks) > 1 else 0.0
            log(f"lap {len(lap_marks)}: {lap_marks[-1] - previous:.2f} s")
        if rule.lap_finished():
            finished = True
            break
        await solution.step()
        await world.step()
    elapsed = world.last_tick_elapsed_seconds - start_time
    wall = time.time() - wall
    vehicle.close()
    laps_s = [round(b - a, 2) for a, b in zip([0.0] + lap_marks[:-1], lap_marks)]
    return {"finished": finished, "elapsed_time": round(elapsed, 2), "laps": laps_s, "respawns": respawns,
            "wall_time_s": round(wall, 2), "real_time_factor": round(elapsed / max(wall, 1e-9), 2)}


async def run(map_name: str = "monza", laps: int = 3, entry: str = "competition", max_seconds: float = 1200.0,
              log=print, camera_size: typing.Tuple[int, int] = (1024, 768)) -> dict:
    instance = roar_py_ros.RoarPyRosInstance(map_name=map_name)
    try:
        world = instance.world
        world.set_control_steps(0.05, 0.005)
        world.set_asynchronous(False)
        result = await evaluate_solution(world, ENTRIES[entry], max_seconds, laps, log, camera_size)
        result.update({"map": world.map_name, "entry": entry})
        log(f"{world.map_name}, {entry}: {'finished' if result['finished'] else 'did not finish'} "
            f"{len(result['laps'])} lap(s) {', '.join(f'{t:.2f}' for t in result['laps'])} s in "
            f"{result['elapsed_time']:.2f} s; {len(result['respawns'])} respawn(s); "
            f"{result['real_time_factor']:.1f}x real time")
        return result
    finally:
        instance.close()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default="monza", help="a map in maps/ or a map folder (default monza)")
    parser.add_argument("--laps", type=int, default=3)
    parser.add_argument("--entry", choices=sorted(ENTRIES), default="competition")
    parser.add_argument("--max-seconds", type=float, default=1200.0, help="simulated seconds before giving up")
    parser.add_argument("--camera", default="1024x768", help="the chase camera's WIDTHxHEIGHT (the runner's 1024x768)")
    parser.add_argument("--output", help="write the result as YAML here")
    args = parser.parse_args([a for a in (argv if argv is not None else sys.argv[1:]) if ":=" not in a])
    if args.laps < 1:
        parser.error(f"--laps must be at least 1, got {args.laps}")
    try:
        camera = tuple(int(v) for v in args.camera.split("x"))
        assert len(camera) == 2 and min(camera) > 0
    except (ValueError, AssertionError):
        parser.error(f"--camera must be WIDTHxHEIGHT, got {args.camera!r}")
    result = asyncio.run(run(args.map, args.laps, args.entry, args.max_seconds, camera_size=camera))
    if args.output:
        with open(args.output, "w") as f:
            yaml.safe_dump(result, f, sort_keys=False)
    return 0 if result["finished"] else 1


if __name__ == "__main__":
    sys.exit(main())
