#!/usr/bin/env python3
"""Speed of a ROAR_PY program on roar_sim: a Python loop of world.step(), receive_observation() and
apply_action() in synchronous mode at 20 Hz control, everything (this process, roar_sim it starts) on one
core. Prints steps per second and times real time for the state sensors (location, velocimeter,
roll-pitch-yaw, accelerometer, gyroscope, collision), then with an 84x84 RGB camera added; the reference,
measured in the same run, is the same number of bare /roar_sim/step calls from rospy (no sensors, no
ROAR_PY layer).

    /usr/bin/python3 bench/roar_py_bench.py [--steps N] [--cores 1]
"""
import argparse
import asyncio
import os
import time

import numpy as np

import roar_py_interface as rpi
import roar_py_ros

CONTROL_DT = 0.05
ACTION = {"throttle": np.array([0.6]), "steer": np.array([0.0]), "brake": np.array([0.0]),
          "hand_brake": np.array([0]), "reverse": np.array([0])}


async def loop(world, vehicle, steps: int) -> float:
    started = time.perf_counter()
    for _ in range(steps):
        await world.step()
        obs = await vehicle.receive_observation()
        vehicle.convert_obs_to_gym_obs(obs)
        await vehicle.apply_action(ACTION)
    return time.perf_counter() - started


async def bare_steps(instance, vehicle, steps: int) -> float:
    from roar_ros.srv import Step

    started = time.perf_counter()
    for _ in range(steps):
        instance._services.call("/roar_sim/step", Step, ticks=1, vehicle_names=[vehicle.ros_name],
                                controls=[vehicle.control], observe=[vehicle.ros_name])
    return time.perf_counter() - started


def state_sensors(vehicle):
    vehicle.attach_location_in_world_sensor()
    vehicle.attach_velocimeter_sensor()
    vehicle.attach_roll_pitch_yaw_sensor()
    vehicle.attach_accelerometer_sensor()
    vehicle.attach_gyroscope_sensor()
    vehicle.attach_collision_sensor()


def report(name: str, steps: int, seconds: float, reference: float):
    rate = steps / seconds
    print(f"{name:44s} {rate:8.0f} steps/s  {rate * CONTROL_DT:6.1f}x real time  "
          f"{seconds / reference:5.2f}x the bare step's time")


async def main(steps: int, cores: int):
    os.sched_setaffinity(0, set(range(cores)))  # roar_sim, started from here, inherits it
    instance = roar_py_ros.RoarPyRosInstance(map_name="roar_ring")
    try:
        world = instance.world
        world.set_asynchronous(False)
        world.set_control_steps(CONTROL_DT, 0.005)
        location, rpy = world.spawn_points[0]
        vehicle = world.spawn_vehicle("vehicle.tesla.model3", location, rpy)
        await vehicle.apply_action(ACTION)
        await bare_steps(instance, vehicle, 50)  # warm-up
        reference = await bare_steps(instance, vehicle, steps)
        print(f"one car on Roar Ring, {steps} steps of {CONTROL_DT} s, {cores} core(s), pid {os.getpid()}")
        report("bare /roar_sim/step (reference)", steps, reference, reference)
        state_sensors(vehicle)
        await loop(world, vehicle, 50)
        report("ROAR_PY loop, state sensors", steps, await loop(world, vehicle, steps), reference)
        vehicle.attach_camera_sensor(rpi.RoarPyCameraSensorDataRGB, np.array([0.6, 0.0, 1.5]), np.zeros(3),
                                     image_width=84, image_height=84)
        await loop(world, vehicle, 50)
        report("ROAR_PY loop, state sensors + 84x84 camera", steps, await loop(world, vehicle, steps), reference)
    finally:
        instance.close()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="ROAR_PY loop speed on roar_sim")
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--cores", type=int, default=1)
    args = parser.parse_args()
    asyncio.run(main(args.steps, args.cores))
