import asyncio
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def main():  # roar_ros: the fragment's surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    # Synchronous mode with a fixed timestep
    carla_world.set_asynchronous(False)
    carla_world.set_control_steps(control_timestep=0.05, control_substimestep=0.01)
    # Variable timestep (asynchronous mode)
    carla_world.set_asynchronous(True)
    carla_world.set_control_steps(0.0, 0.005)
    dt = await carla_world.step()
    print(f"Time delta: {dt} seconds")
    print(f"Total elapsed: {carla_world.last_tick_elapsed_seconds} seconds")
    is_async = carla_world.is_asynchronous
    timestep = carla_world.control_timestep
    roar_py_instance.close()

asyncio.run(main())
