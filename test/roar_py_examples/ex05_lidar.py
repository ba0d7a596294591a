import asyncio
import numpy as np
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def main():  # roar_ros: the fragment's surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    vehicle = carla_world.spawn_vehicle("vehicle.tesla.model3", *carla_world.spawn_points[0])

    lidar = carla_world.attach_lidar_sensor(
        location=np.array([0.0, 0.0, 2.5]), roll_pitch_yaw=np.array([0.0, 0.0, 0.0]),
        num_lasers=32, max_distance=50.0, points_per_second=56000, rotation_frequency=10.0,
        upper_fov=10.0, lower_fov=-30.0, horizontal_fov=360.0, control_timestep=0.0,
        name="lidar_sensor", bind_to=vehicle)
    lidar_data = await lidar.receive_observation()
    points = lidar_data.lidar_points_data          # (N, 4): x, y, z, intensity
    print(f"Number of points: {points.shape[0]}")
    print(f"Channels: {lidar_data.channels}")
    print(f"Horizontal angle: {lidar_data.horizontal_angle}")
    gym_obs = lidar_data.convert_obs_to_gym_obs()
    roar_py_instance.close()

asyncio.run(main())
