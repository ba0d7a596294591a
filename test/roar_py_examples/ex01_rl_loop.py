import roar_py_interface
import numpy as np
import asyncio
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def rl_training_loop():
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    carla_world.set_asynchronous(False)
    carla_world.set_control_steps(0.05, 0.01)

    vehicle = carla_world.spawn_vehicle(
        "vehicle.tesla.model3",
        carla_world.spawn_points[0][0],
        carla_world.spawn_points[0][1]
    )
    camera = vehicle.attach_camera_sensor(
        roar_py_interface.RoarPyCameraSensorDataRGB,
        np.array([-2.0, 0.0, 1.5]),
        np.array([0, 0, 0]),
        image_width=84,
        image_height=84
    )
    action_space = vehicle.get_action_spec()
    observation_space = vehicle.get_gym_observation_spec()
    print(f"Action space: {action_space}")
    print(f"Observation space: {observation_space}")

    for episode in range(100):
        await carla_world.step()
        for step in range(1000):
            obs = await vehicle.receive_observation()
            gym_obs = vehicle.convert_obs_to_gym_obs(obs)
            action = {
                "throttle": np.array([0.5]),
                "steer": np.array([np.random.uniform(-0.3, 0.3)]),
                "brake": np.array([0.0]),
                "hand_brake": np.array([0]),
                "reverse": np.array([0])
            }
            await vehicle.apply_action(action)
            await carla_world.step()
    roar_py_instance.close()

if __name__ == '__main__':
    asyncio.run(rl_training_loop())
