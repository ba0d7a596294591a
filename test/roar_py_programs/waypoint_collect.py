# ROAR_PY's examples/waypoint_collect.py as a program of this project: the same calls in the same order.
# roar_ros: roar_py_ros's instance where ROAR_PY's makes a CARLA client and instance; the viewer is
# manual_control's, returning the keys held as ROAR_PY's copy of it does.
import asyncio
from typing import List

import numpy as np
import pygame

import manual_control
import roar_py_interface
import roar_py_ros  # roar_ros

WAYPOINT_DISTANCE = 2.0
WAYPOINT_LANE_WIDTH = 12.0


class ManualControlViewer(manual_control.ManualControlViewer):
    def render(self, image, occupancy_map=None):
        control = super().render(image, occupancy_map)
        return None if control is None else (control, pygame.key.get_pressed())


async def main():
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros

    carla_world = roar_py_instance.world
    carla_world.set_asynchronous(True)
    carla_world.set_control_steps(0.0, 0.005)
    await carla_world.step()
    roar_py_instance.clean_actors_not_registered()

    spawn_point, spawn_rpy = carla_world.spawn_points[0]
    print("Spawning vehicle at", spawn_point, spawn_rpy)
    vehicle = carla_world.spawn_vehicle("vehicle.tesla.model3", spawn_point + np.array([0, 0, 2.0]), spawn_rpy)
    camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB,
        np.array([-2.0 * vehicle.bounding_box.extent[0], 0.0, 3.0 * vehicle.bounding_box.extent[2]]),
        np.array([0, 10 / 180.0 * np.pi, 0]),
    )

    viewer = ManualControlViewer()
    waypoints: List[roar_py_interface.RoarPyWaypoint] = []
    waypoints.append(roar_py_interface.RoarPyWaypoint(spawn_point, spawn_rpy, WAYPOINT_LANE_WIDTH))
    is_collecting = False
    try:
        while True:
            last_waypoint = waypoints[-1]
            await carla_world.step()

            current_location = vehicle.get_3d_location()
            dist_to_last_waypoint = np.linalg.norm(current_location[:2] - last_waypoint.location[:2])
            if dist_to_last_waypoint > WAYPOINT_DISTANCE:
                to_add = None
                if is_collecting:
                    to_add = roar_py_interface.RoarPyWaypoint(
                        current_location - vehicle.bounding_box.extent[2] * np.array([0, 0, 1]),
                        vehicle.get_roll_pitch_yaw(), WAYPOINT_LANE_WIDTH)
                else:
                    waypoint_locations = np.asarray([waypoint.location for waypoint in carla_world.maneuverable_waypoints])
                    waypoint_2d_locations = waypoint_locations[:, :2]
                    dist_to_waypoints = np.linalg.norm(waypoint_2d_locations - current_location[:2], axis=1)
                    closest_waypoint_idx = np.argmin(dist_to_waypoints)
                    print("Closest waypoint idx", closest_waypoint_idx)
                    closest_waypoint = carla_world.maneuverable_waypoints[closest_waypoint_idx]
                    if closest_waypoint not in waypoints:
                        to_add = closest_waypoint
                if to_add is not None:
                    print("Adding waypoint", to_add)
                    waypoints.append(to_add)
                dist_to_first_waypoint = np.linalg.norm(current_location[:2] - waypoints[0].location[:2])
                if dist_to_first_waypoint < 100:
                    print("Distance to first waypoint", dist_to_first_waypoint)

            img: roar_py_interface.RoarPyCameraSensorDataRGB = await camera.receive_observation()
            control, keys = viewer.render(img)
            if keys[pygame.K_SPACE]:
                if not is_collecting:
                    print("Start collecting waypoints")
                is_collecting = True
            else:
                if is_collecting:
                    print("Stop collecting waypoints")
                is_collecting = False
            if control is None:
                break
            await vehicle.apply_action(control)
    finally:
        roar_py_instance.close()
        np.savez_compressed("waypoints.npz", **roar_py_interface.RoarPyWaypoint.save_waypoint_list(waypoints))


if __name__ == '__main__':
    asyncio.run(main())
