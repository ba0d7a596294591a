import asyncio
import numpy as np
import roar_py_interface
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def main():  # roar_ros: the fragments' surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    spawn_points = carla_world.spawn_points

    vehicle = carla_world.spawn_vehicle(
        "vehicle.audi.a2", spawn_points[0][0] + np.array([0, 0, 1]), spawn_points[0][1], name="custom_vehicle")
    front_camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB, np.array([2.5, 0.0, 1.0]), np.array([0, 0, 0]),
        image_width=800, image_height=600, name="front_cam")
    rear_camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB, np.array([-2.5, 0.0, 1.0]), np.array([0, 0, np.pi]),
        image_width=800, image_height=600, name="rear_cam")
    collision_sensor = vehicle.attach_collision_sensor(name="collision_detector")
    accel_sensor = vehicle.attach_accelerometer_sensor(name="accelerometer")
    gyro_sensor = vehicle.attach_gyroscope_sensor(name="gyroscope")
    all_sensors = list(vehicle.get_sensors())
    print(f"Total sensors: {len(all_sensors)}")
    observations = await vehicle.receive_observation()
    front_image = observations["front_cam"]
    rear_image = observations["rear_cam"]
    collision_data = observations["collision_detector"]
    accel_data = observations["accelerometer"]
    gyro_data = observations["gyroscope"]

    camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB, np.array([-2.0, 0.0, 1.5]), np.array([0, 0, 0]))
    collision_sensor = vehicle.attach_collision_sensor(name="collision")
    location_sensor = vehicle.attach_location_in_world_sensor(name="gps")
    velocimeter = vehicle.attach_velocimeter_sensor(name="speed")
    await carla_world.step()
    observations = await vehicle.receive_observation()
    camera_obs = observations["camera"]
    collision_obs = observations["collision"]
    location_obs = observations["gps"]
    velocity_obs = observations["speed"]
    obs_spec = vehicle.get_gym_observation_spec()   # a Dict space of every sensor's space

    camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB,
        np.array([-2.0 * vehicle.bounding_box.extent[0], 0.0, 3.0 * vehicle.bounding_box.extent[2]]),
        np.array([0, 10/180.0*np.pi, 0]),
        fov=90.0, image_width=1024, image_height=768)
    await carla_world.step()
    camera_data = await camera.receive_observation()
    pil_image = camera_data.get_image()     # PIL image
    numpy_array = camera_data.to_gym()      # (H, W, 3)
    image_size = camera_data.get_size()     # (width, height)
    pil_image.save("capture.png")
    roar_py_instance.close()

asyncio.run(main())
