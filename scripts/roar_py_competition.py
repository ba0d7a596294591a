#!/usr/bin/python3
"""A ROAR competition run, written against ROAR_PY's interface: a vehicle.tesla.model3 on the first
waypoint with a camera, location, velocimeter, roll-pitch-yaw, occupancy-map and collision sensors,
driven by ROAR_PY's documented waypoint-following agent; a collision over 100 N s puts the car back on the
last waypoint it passed (as the competition's rules do); the run ends after --laps laps.

    rosrun roar_ros roar_py_competition.py --map monza --laps 3

Without a running roar_sim it starts its own (roar_py_ros). Prints a line per lap and a summary; --output
writes the laps as YAML."""
import argparse
import asyncio
import sys
import time

import numpy as np
import yaml

import roar_py_interface
import roar_py_ros

RESPAWN_IMPULSE = 100.0  # N s


def filter_waypoints(location: np.ndarray, current_idx: int, waypoints: list) -> int:
    def dist_to_waypoint(waypoint):
        return np.linalg.norm(location[:2] - waypoint.location[:2])
    for i in range(current_idx, len(waypoints) + current_idx):
        if dist_to_waypoint(waypoints[i % len(waypoints)]) < 3:
            return i % len(waypoints)
    return current_idx


class WaypointFollowingAgent:
    """ROAR_PY's documented example controller (examples.md, section 10)."""

    def __init__(self, waypoints, target_speed: float = 20.0):
        self.waypoints = waypoints
        self.current_waypoint_idx = 0
        self.target_speed = target_speed

    def control(self, location, rotation, velocity):
        waypoints = self.waypoints
        self.current_waypoint_idx = filter_waypoints(location, self.current_waypoint_idx, waypoints)
        target_waypoint = waypoints[(self.current_waypoint_idx + 3) % len(waypoints)]
        vector_to_waypoint = (target_waypoint.location - location)[:2]
        heading_to_waypoint = np.arctan2(vector_to_waypoint[1], vector_to_waypoint[0])
        delta_heading = roar_py_interface.normalize_rad(heading_to_waypoint - rotation[2])
        speed = np.linalg.norm(velocity)
        steer_control = -8.0 / np.sqrt(speed) * delta_heading / np.pi if speed > 1e-2 else -np.sign(delta_heading)
        steer_control = np.clip(steer_control, -1.0, 1.0)
        throttle_control = 0.05 * (self.target_speed - speed)
        return {
            "throttle": np.clip(throttle_control, 0.0, 1.0),
            "steer": steer_control,
            "brake": np.clip(-throttle_control, 0.0, 1.0),
            "hand_brake": 0.0,
            "reverse": 0,
        }


async def run(map_name: str = "monza", laps: int = 3, max_sim_time: float = 3600.0, log=print) -> dict:
    instance = roar_py_ros.RoarPyRosInstance(map_name=map_name)
    try:
        world = instance.world
        world.set_asynchronous(False)
        world.set_control_steps(0.05, 0.005)
        waypoints = world.maneuverable_waypoints
        first = waypoints[0]
        vehicle = world.spawn_vehicle("vehicle.tesla.model3", first.location + np.array([0, 0, 0.5]),
                                      first.roll_pitch_yaw, name="competition")
        vehicle.attach_camera_sensor(roar_py_interface.RoarPyCameraSensorDataRGB, np.array([0.6, 0.0, 1.5]),
                                     np.zeros(3), image_width=160, image_height=120, name="camera")
        vehicle.attach_location_in_world_sensor(name="location")
        vehicle.attach_velocimeter_sensor(name="velocimeter")
        vehicle.attach_roll_pitch_yaw_sensor(name="rpy")
        vehicle.attach_occupancy_map_sensor(50, 50, 2.0, 2.0, name="occupancy_map")
        collision_sensor = vehicle.attach_collision_sensor(name="collision")
        agent = WaypointFollowingAgent(waypoints)
        start = world.last_tick_elapsed_seconds
        lap_start, passed_half = start, False
        lap_times, respawns = [], 0
        wall = time.time()
        await world.step()
        while len(lap_times) < laps:
            obs = await vehicle.receive_observation()
            location = obs["location"].convert_obs_to_gym_obs()
            action = agent.control(location, obs["rpy"].roll_pitch_yaw, obs["velocimeter"].velocity)
            if np.linalg.norm(obs["collision"].impulse_normal) > RESPAWN_IMPULSE:
                respawns += 1
                back = waypoints[agent.current_waypoint_idx]
                log(f"collision with {obs['collision'].other_actor} at t = {world.last_tick_elapsed_seconds:.2f} s: "
                    f"back to waypoint {agent.current_waypoint_idx}")
                vehicle.set_transform(back.location, back.roll_pitch_yaw)
            await vehicle.apply_action(action)
            await world.step()
            index = agent.current_waypoint_idx
            if index > len(waypoints) // 2:
                passed_half = True
            elif passed_half and index < len(waypoints) // 10:
                now = world.last_tick_elapsed_seconds
                lap_times.append(now - lap_start)
                log(f"lap {len(lap_times)}: {lap_times[-1]:.2f} s")
                lap_start, passed_half = now, False
            if world.last_tick_elapsed_seconds - start > max_sim_time:
                break
        sim_time = world.last_tick_elapsed_seconds - start
        wall = time.time() - wall
        result = {"map": world.map_name, "laps": [round(t, 2) for t in lap_times], "finished": len(lap_times) >= laps,
                  "respawns": respawns, "sim_time_s": round(sim_time, 2), "wall_time_s": round(wall, 2),
                  "real_time_factor": round(sim_time / wall, 1), "sensors": [s.name for s in vehicle.get_sensors()],
                  "collision_sensor": collision_sensor.name}
        log(f"{world.map_name}: {len(lap_times)}/{laps} laps {', '.join(f'{t:.2f}' for t in lap_times)} s; "
            f"{respawns} respawn(s); {sim_time:.0f} s simulated in {wall:.0f} s ({sim_time / wall:.1f}x real time)")
        return result
    finally:
        instance.close()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default="monza", help="a map in maps/ or a map folder (default monza)")
    parser.add_argument("--laps", type=int, default=3)
    parser.add_argument("--max-sim-time", type=float, default=3600.0, help="simulated seconds before giving up")
    parser.add_argument("--output", help="write the result as YAML here")
    args = parser.parse_args([a for a in (argv if argv is not None else sys.argv[1:]) if ":=" not in a])
    if args.laps < 1:
        parser.error(f"--laps must be at least 1, got {args.laps}")
    result = asyncio.run(run(args.map, args.laps, args.max_sim_time))
    if args.output:
        with open(args.output, "w") as f:
            yaml.safe_dump(result, f, sort_keys=False)
    return 0 if result["finished"] else 1


if __name__ == "__main__":
    sys.exit(main())
