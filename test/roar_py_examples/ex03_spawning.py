import asyncio
import numpy as np
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def main():  # roar_ros: the fragments' surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world

    spawn_points = carla_world.spawn_points
    print(f"Available spawn points: {len(spawn_points)}")
    for i, (location, rotation) in enumerate(spawn_points[:5]):   # (location [x, y, z], rotation [roll, pitch, yaw])
        print(f"Spawn {i}: {location} {rotation}")
    random_idx = np.random.randint(len(spawn_points))
    spawn_loc, spawn_rot = spawn_points[random_idx]
    vehicle = carla_world.spawn_vehicle("vehicle.tesla.model3", spawn_loc + np.array([0, 0, 2.0]), spawn_rot)

    spawn_point, spawn_rpy = carla_world.spawn_points[1]
    vehicle = carla_world.spawn_vehicle(
        "vehicle.tesla.model3",
        spawn_point + np.array([0, 0, 2.0]),
        spawn_rpy,
        auto_gear=True,
        name="my_vehicle",
        rgba=np.array([255, 0, 0, 255])
    )
    bounding_box = vehicle.bounding_box
    print(f"Vehicle extent: {bounding_box.extent}")
    print(f"Vehicle location: {vehicle.get_3d_location()}")
    print(f"Vehicle velocity: {vehicle.get_linear_3d_velocity()}")
    print(f"Vehicle rotation: {vehicle.get_roll_pitch_yaw()}")
    roar_py_instance.close()

asyncio.run(main())
