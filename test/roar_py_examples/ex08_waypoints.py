import asyncio
import numpy as np
import roar_py_interface
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`
from roar_py_interface import RoarPyWaypoint


def generate_spawn_points(waypoints):
    spawn_point_locations = []
    spawn_rotations = []
    for spawn_point in waypoints[::len(waypoints) // 10]:
        spawn_point_locations.append(spawn_point.location)
        spawn_rotations.append(spawn_point.roll_pitch_yaw)
    return np.stack(spawn_point_locations, axis=0), np.stack(spawn_rotations, axis=0)


def generate_waypoints(locations, distance_between_waypoints, lane_width):
    # locations: (N, 3) in ROAR_PY's frame
    waypoint_locations = [locations[0]]
    waypoint_rotations = []
    last_location_idx = 0
    for i in range(1, len(locations)):
        next_location = locations[i]
        if np.linalg.norm(next_location - locations[last_location_idx]) > distance_between_waypoints:
            waypoint_locations.append(next_location)
            waypoint_rotations.append(np.arctan2(next_location[1] - locations[last_location_idx][1],
                                                 next_location[0] - locations[last_location_idx][0]))
            last_location_idx = i
    waypoint_rotations.append(np.arctan2(locations[0][1] - waypoint_locations[-1][1],
                                         locations[0][0] - waypoint_locations[-1][0]))
    return [RoarPyWaypoint(waypoint_locations[i], np.array([0, 0, waypoint_rotations[i]]), lane_width)
            for i in range(len(waypoint_locations))]


async def main():  # roar_ros: the fragments' surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    roar_py_world = carla_world

    waypoints = carla_world.maneuverable_waypoints
    if waypoints is not None:
        print(f"Total waypoints: {len(waypoints)}")
        for i, waypoint in enumerate(waypoints[:10]):
            print(i, waypoint.location, waypoint.roll_pitch_yaw, waypoint.lane_width)
        vehicle = carla_world.spawn_vehicle(
            "vehicle.audi.a2", waypoints[10].location + np.array([0, 0, 1]), waypoints[10].roll_pitch_yaw)

    spawn_point_locations, spawn_rotations = generate_spawn_points(waypoints)
    np.savez_compressed("final_major_map_spawn_points.npz", locations=spawn_point_locations, rotations=spawn_rotations)
    np.savez_compressed("final_major_map_waypoints.npz", **RoarPyWaypoint.save_waypoint_list(waypoints))
    resampled = generate_waypoints(np.stack([w.location for w in waypoints]), 2, 3.5)

    # Two edge points per waypoint in comprehensive_waypoints[lane_id], made into centre waypoints, saved as npz
    waypoint_list = []
    print("LaneIDS: ", roar_py_world.comprehensive_waypoints.keys())
    for lane_id in [0, 1]:
        lane_waypoints = roar_py_world.comprehensive_waypoints[lane_id]
        assert len(lane_waypoints) % 2 == 0
        for i in range(len(lane_waypoints) // 2):
            first_waypoint = lane_waypoints[2 * i]
            second_waypoint = lane_waypoints[2 * i + 1]
            real_waypoint = roar_py_interface.RoarPyWaypoint.from_line_representation(
                first_waypoint.location, second_waypoint.location, first_waypoint.roll_pitch_yaw)
            waypoint_list.append(real_waypoint)
    roar_py_instance.close()
    np.savez_compressed("Monza.npz", **roar_py_interface.RoarPyWaypoint.save_waypoint_list(waypoint_list))

asyncio.run(main())
