import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`
import asyncio

async def main():
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world
    carla_world.set_asynchronous(True)          # or False for synchronous mode
    carla_world.set_control_steps(0.0, 0.005)   # timestep, substep
    await carla_world.step()
    roar_py_instance.clean_actors_not_registered()
    try:
        pass
    finally:
        roar_py_instance.close()

if __name__ == '__main__':
    asyncio.run(main())
