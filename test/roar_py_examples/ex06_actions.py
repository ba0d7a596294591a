import asyncio
import numpy as np
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def main():  # roar_ros: the fragment's surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    vehicle = carla_world.spawn_vehicle("vehicle.tesla.model3", *carla_world.spawn_points[0])

    control = {
        "throttle": np.array([0.5]),   # 0..1
        "steer": np.array([0.0]),      # -1..1, positive right
        "brake": np.array([0.0]),      # 0..1
        "hand_brake": np.array([0]),   # 0 or 1
        "reverse": np.array([0])       # 0 or 1
    }
    # manual-gear vehicles (auto_gear=False) also take control["target_gear"]
    await vehicle.apply_action(control)
    action_spec = vehicle.get_action_spec()   # Dict space: throttle, steer, brake, hand_brake, reverse (+ target_gear)
    print(action_spec)
    roar_py_instance.close()

asyncio.run(main())
