import asyncio
import numpy as np
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


def normalize_rad(rad: float):
    return (rad + np.pi) % (2 * np.pi) - np.pi

def filter_waypoints(location: np.ndarray, current_idx: int, waypoints: list) -> int:
    def dist_to_waypoint(waypoint):
        return np.linalg.norm(location[:2] - waypoint.location[:2])
    for i in range(current_idx, len(waypoints) + current_idx):
        if dist_to_waypoint(waypoints[i % len(waypoints)]) < 3:
            return i % len(waypoints)
    return current_idx


async def main():  # roar_ros: the fragment's surroundings (the set-up of examples 1 and 8)
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    carla_world.set_asynchronous(False)
    carla_world.set_control_steps(0.05, 0.005)
    vehicle = carla_world.spawn_vehicle(
        "vehicle.tesla.model3", carla_world.maneuverable_waypoints[10].location + np.array([0, 0, 1]),
        carla_world.maneuverable_waypoints[10].roll_pitch_yaw)

    current_waypoint_idx = 10
    waypoints = carla_world.maneuverable_waypoints
    while True:
        await carla_world.step()
        vehicle_location = vehicle.get_3d_location()
        vehicle_rotation = vehicle.get_roll_pitch_yaw()
        vehicle_velocity = vehicle.get_linear_3d_velocity()
        current_waypoint_idx = filter_waypoints(vehicle_location, current_waypoint_idx, waypoints)
        target_waypoint = waypoints[(current_waypoint_idx + 3) % len(waypoints)]
        vector_to_waypoint = (target_waypoint.location - vehicle_location)[:2]
        heading_to_waypoint = np.arctan2(vector_to_waypoint[1], vector_to_waypoint[0])
        delta_heading = normalize_rad(heading_to_waypoint - vehicle_rotation[2])
        speed = np.linalg.norm(vehicle_velocity)
        steer_control = -8.0 / np.sqrt(speed) * delta_heading / np.pi if speed > 1e-2 else -np.sign(delta_heading)
        steer_control = np.clip(steer_control, -1.0, 1.0)
        throttle_control = 0.05 * (20 - speed)
        control = {
            "throttle": np.clip(throttle_control, 0.0, 1.0),
            "steer": steer_control,
            "brake": np.clip(-throttle_control, 0.0, 1.0),
            "hand_brake": 0.0,
            "reverse": 0
        }
        await vehicle.apply_action(control)

asyncio.run(main())
