# ROAR_PY's examples/manual_control_occupancy_map.py as a program of this project: the same calls in the
# same order. roar_ros: roar_py_ros's instance where ROAR_PY's makes a CARLA client and instance.
import asyncio

import numpy as np

import roar_py_interface
import roar_py_ros  # roar_ros
from manual_control import ManualControlViewer


async def main():
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros

    carla_world = roar_py_instance.world
    carla_world.set_asynchronous(True)
    carla_world.set_control_steps(0.0, 0.005)
    await carla_world.step()
    roar_py_instance.clean_actors_not_registered()

    print("Map Name", carla_world.map_name)
    occ_map_producer = roar_py_interface.RoarPyOccupancyMapProducer(carla_world.maneuverable_waypoints, 100, 100, 5, 5)
    spawn_point, spawn_rpy = carla_world.spawn_points[0]
    print("Spawning vehicle at", spawn_point, spawn_rpy)
    vehicle = carla_world.spawn_vehicle("vehicle.tesla.model3", spawn_point + np.array([0, 0, 2.0]), spawn_rpy)
    print(vehicle.bounding_box)

    camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB,
        np.array([-2.0 * vehicle.bounding_box.extent[0], 0.0, 3.0 * vehicle.bounding_box.extent[2]]),
        np.array([0, 10 / 180.0 * np.pi, 0]),
    )
    viewer = ManualControlViewer()
    try:
        while True:
            await carla_world.step()
            img: roar_py_interface.RoarPyCameraSensorDataRGB = await camera.receive_observation()
            occupancy_map = occ_map_producer.plot_occupancy_map(vehicle.get_3d_location()[:2],
                                                                vehicle.get_roll_pitch_yaw()[2])
            control = viewer.render(img, occupancy_map)
            if control is None:
                break
            await vehicle.apply_action(control)
    finally:
        roar_py_instance.close()


if __name__ == '__main__':
    asyncio.run(main())
