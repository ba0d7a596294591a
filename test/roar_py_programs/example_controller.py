# ROAR_PY's examples/example_controller.py as a program of this project: the same calls in the same order.
# roar_ros: roar_py_ros's instance where ROAR_PY's makes a CARLA client and instance.
import asyncio
from typing import List

import numpy as np

import roar_py_interface
import roar_py_ros  # roar_ros
from manual_control import ManualControlViewer


def normalize_rad(rad: float):
    return (rad + np.pi) % (2 * np.pi) - np.pi


def filter_waypoints(location: np.ndarray, current_idx: int, waypoints: List[roar_py_interface.RoarPyWaypoint]) -> int:
    def dist_to_waypoint(waypoint: roar_py_interface.RoarPyWaypoint):
        return np.linalg.norm(location[:2] - waypoint.location[:2])
    for i in range(current_idx, len(waypoints) + current_idx):
        if dist_to_waypoint(waypoints[i % len(waypoints)]) < 3:
            return i % len(waypoints)
    return current_idx


async def main():
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros
    manual_viewer = ManualControlViewer()

    carla_world = roar_py_instance.world
    carla_world.set_asynchronous(True)
    carla_world.set_control_steps(0.0, 0.01)
    await carla_world.step()
    roar_py_instance.clean_actors_not_registered()

    way_points = carla_world.maneuverable_waypoints
    vehicle = carla_world.spawn_vehicle("vehicle.audi.a2", way_points[10].location + np.array([0, 0, 1]),
                                        way_points[10].roll_pitch_yaw)
    current_waypoint_idx = 10
    assert vehicle is not None
    camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB,
        np.array([-2.0 * vehicle.bounding_box.extent[0], 0.0, 3.0 * vehicle.bounding_box.extent[2]]),
        np.array([0, 10 / 180.0 * np.pi, 0]),
        image_width=1024,
        image_height=768
    )
    assert camera is not None

    start_time = carla_world.last_tick_elapsed_seconds
    try:
        while True:
            await carla_world.step()
            vehicle_location = vehicle.get_3d_location()
            vehicle_rotation = vehicle.get_roll_pitch_yaw()
            camera_data = await camera.receive_observation()
            render_ret = manual_viewer.render(camera_data)
            if render_ret is None:
                break
            current_waypoint_idx = filter_waypoints(vehicle_location, current_waypoint_idx, way_points)
            waypoint_to_follow = way_points[(current_waypoint_idx + 3) % len(way_points)]
            vector_to_waypoint = (waypoint_to_follow.location - vehicle_location)[:2]
            heading_to_waypoint = np.arctan2(vector_to_waypoint[1], vector_to_waypoint[0])
            delta_heading = normalize_rad(heading_to_waypoint - vehicle_rotation[2])
            steer_control = (
                -8.0 / np.sqrt(np.linalg.norm(vehicle.get_linear_3d_velocity())) * delta_heading / np.pi
            ) if np.linalg.norm(vehicle.get_linear_3d_velocity()) > 1e-2 else -np.sign(delta_heading)
            steer_control = np.clip(steer_control, -1.0, 1.0)
            throttle_control = 0.05 * (20 - np.linalg.norm(vehicle.get_linear_3d_velocity()))
            control = {
                "throttle": np.clip(throttle_control, 0.0, 1.0),
                "steer": steer_control,
                "brake": np.clip(-throttle_control, 0.0, 1.0),
                "hand_brake": 0.0,
                "reverse": 0,
                "target_gear": 0
            }
            await vehicle.apply_action(control)
    finally:
        roar_py_instance.close()
        end_time = carla_world.last_tick_elapsed_seconds
        delta_time = end_time - start_time
        print(f"Total time: {delta_time} seconds")


if __name__ == '__main__':
    asyncio.run(main())
