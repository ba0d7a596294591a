#!/usr/bin/env python3
"""Speed of ROAR's competition set-up on roar_sim: the official runner's car and sensors (a
vehicle.tesla.model3 with a 1024x768 chase camera, location, velocimeter, roll-pitch-yaw, a 50x50
occupancy map and collision) driven by a loop of the runner's shape (world.step(), receive_observation(),
an action) in synchronous mode at 20 Hz control on Monza, this process and the roar_sim it starts on one
core. Prints steps per second and times real time for an entry that reads only location, velocity and
rotation (the camera's frames never read, so never rendered), then for one that reads the camera's
pixels every tick, then for ROAR_PY_RL's training environment (test/python/roar_py_rl_pattern_env.py: its
sensors with a 400x200 camera it filters out, its 14 waypoint distances, its action filter and
FilterObservation, stepped under nest_asyncio); the reference, measured in the same run, is the same
number of bare /roar_sim/step calls from rospy (no sensors, no ROAR_PY layer). Each loop runs --rounds
times, interleaved with the bare step's, and its median is printed with the range: this machine's speed drifts from run to run by a quarter.

    /usr/bin/python3 bench/roar_py_bench.py [--steps N] [--rounds 5] [--cores 1] [--camera 1024x768]
"""
import argparse
import asyncio
import os
import sys
import time

import numpy as np

import roar_py_interface as rpi
import roar_py_ros

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test", "python"))
import roar_py_rl_pattern_env as rl_pattern  # noqa: E402  (ROAR_PY_RL's environment, one home: beside its test)

CONTROL_DT = 0.05
ACTION = {"throttle": 0.5, "steer": 0.0, "brake": 0.0, "hand_brake": 0.0, "reverse": 0, "target_gear": 0}


def runner_sensors(vehicle, camera_size):
    """The official runner's sensors, with its arguments."""
    extent = vehicle.bounding_box.extent
    camera = vehicle.attach_camera_sensor(rpi.RoarPyCameraSensorDataRGB, np.array([-2.0 * extent[0], 0.0, 3.0 * extent[2]]),
                                          np.array([0, 10 / 180.0 * np.pi, 0]), image_width=camera_size[0],
                                          image_height=camera_size[1])
    sensors = {"camera": camera, "location": vehicle.attach_location_in_world_sensor(),
               "velocity": vehicle.attach_velocimeter_sensor(), "rpy": vehicle.attach_roll_pitch_yaw_sensor(),
               "occupancy": vehicle.attach_occupancy_map_sensor(50, 50, 2.0, 2.0),
               "collision": vehicle.attach_collision_sensor(np.zeros(3), np.zeros(3))}
    return sensors


async def loop(world, vehicle, sensors, steps: int, read_camera: bool) -> float:
    started = time.perf_counter()
    for _ in range(steps):
        await vehicle.receive_observation()
        location = sensors["location"].get_last_gym_observation()
        velocity = sensors["velocity"].get_last_gym_observation()
        rotation = sensors["rpy"].get_last_gym_observation()
        if read_camera:
            sensors["camera"].get_last_observation().get_image()
        steer = float(np.clip(0.01 * rotation[2] + 0.0 * location[0], -1, 1))
        await vehicle.apply_action({**ACTION, "throttle": 0.5 if np.linalg.norm(velocity) < 20 else 0.0,
                                    "steer": steer})
        await world.step()
    return time.perf_counter() - started


def rl_steps(env, steps: int) -> float:
    """ROAR_PY_RL's training loop: a steady action through its wrappers, a new episode when one ends."""
    steady = {"throttle": np.array([0.3], dtype=np.float32), "steer": np.array([0.0], dtype=np.float32)}
    started = time.perf_counter()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(steady)
        if terminated or truncated:
            env.reset()
    return time.perf_counter() - started


async def bare_steps(instance, vehicle, steps: int) -> float:
    from roar_ros.srv import Step

    started = time.perf_counter()
    for _ in range(steps):
        instance._services.call("/roar_sim/step", Step, ticks=1, vehicle_names=[vehicle.ros_name],
                                controls=[vehicle.control], observe=[vehicle.ros_name])
    return time.perf_counter() - started


def report(name: str, steps: int, seconds, reference):
    """Median steps/s over the rounds (and their range), and the median of each round's time over the bare
    step's in the same round."""
    rates = np.array([steps / t for t in seconds])
    ratio = np.median([t / r for t, r in zip(seconds, reference)])
    rate = np.median(rates)
    print(f"{name:52s} {rate:8.0f} steps/s ({rates.min():.0f}-{rates.max():.0f})  {rate * CONTROL_DT:6.1f}x real "
          f"time  {ratio:5.2f}x the bare step's time", flush=True)


async def main(steps: int, rounds: int, cores: int, camera_size):
    os.sched_setaffinity(0, set(range(cores)))  # roar_sim, started from here, inherits it
    instance = roar_py_ros.RoarPyRosInstance(map_name="monza")
    try:
        world = instance.world
        world.set_control_steps(CONTROL_DT, 0.005)
        world.set_asynchronous(False)
        waypoints = world.maneuverable_waypoints
        vehicle = world.spawn_vehicle("vehicle.tesla.model3", waypoints[0].location + np.array([0, 0, 1]),
                                      waypoints[0].roll_pitch_yaw, True)
        await vehicle.apply_action(ACTION)
        await bare_steps(instance, vehicle, 50)  # warm-up
        print(f"the official runner's set-up on Monza, {steps} steps of {CONTROL_DT} s, {rounds} rounds, {cores} "
              f"core(s), camera {camera_size[0]}x{camera_size[1]}")
        bare = [await bare_steps(instance, vehicle, steps)]
        report("bare /roar_sim/step (reference)", steps, bare, bare)
        sensors = runner_sensors(vehicle, camera_size)
        await loop(world, vehicle, sensors, 50, False)
        reference, reading = [], []
        for _ in range(rounds):
            reference.append(await bare_steps(instance, vehicle, steps))
            reading.append(await loop(world, vehicle, sensors, steps, False))
        report("bare /roar_sim/step, between the runner's rounds", steps, reference, reference)
        report("runner's sensors, entry reads location/velocity/rpy", steps, reading, reference)
        camera_steps = max(10, steps // 10)  # a frame a step is slow: a tenth of the steps
        camera, camera_reference = [], []
        for _ in range(rounds):
            camera_reference.append(await bare_steps(instance, vehicle, camera_steps))
            camera.append(await loop(world, vehicle, sensors, camera_steps, True))
        report("runner's sensors, entry reads the camera every tick", camera_steps, camera, camera_reference)
        vehicle.close()
        import nest_asyncio  # ROAR_PY_RL's training steps its env synchronously inside a running loop

        nest_asyncio.apply()
        env = rl_pattern.training_env(rl_pattern.make_env(instance, (400, 200), rl_pattern.TRAINING_DISTANCES),
                                      max_episode_steps=10 * steps)
        env.reset()
        rl_steps(env, 50)  # warm-up, and the car's first control for the bare steps
        rl, rl_reference = [], []
        for _ in range(rounds):
            rl_reference.append(await bare_steps(instance, env.unwrapped.roar_py_actor, steps))
            rl.append(rl_steps(env, steps))
        report("ROAR_PY_RL's environment, its observations (no camera)", steps, rl, rl_reference)
    finally:
        instance.close()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="ROAR's competition set-up: loop speed on roar_sim")
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--cores", type=int, default=1)
    parser.add_argument("--camera", default="1024x768")
    args = parser.parse_args()
    asyncio.run(main(args.steps, args.rounds, args.cores, tuple(int(v) for v in args.camera.split("x"))))
