import asyncio
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def main():  # roar_ros: the fragment's surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    vehicle = carla_world.spawn_vehicle("vehicle.tesla.model3", *carla_world.spawn_points[0])

    vehicle_location = vehicle.get_3d_location()
    geolocation = carla_world.get_geolocation(vehicle_location)   # [latitude deg, longitude deg, altitude m]
    print(f"GPS: {geolocation[0]:.6f}, {geolocation[1]:.6f}, {geolocation[2]:.2f}m")
    roar_py_instance.close()

asyncio.run(main())
