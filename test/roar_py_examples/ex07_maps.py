import asyncio
import roar_py_ros  # roar_ros: instead of `import carla` and `import roar_py_carla`


async def main():  # roar_ros: the fragment's surroundings
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros: instead of carla.Client, set_timeout, RoarPyCarlaInstance
    carla_world = roar_py_instance.world

    available_maps = roar_py_instance.get_available_maps()
    roar_py_instance.load_world("roar_speedway", reset_settings=True)   # roar_ros: a roar_sim map instead of CARLA's Town05
    roar_py_instance.reload_world(reset_settings=True)
    map_name = carla_world.map_name
    client_version = roar_py_instance.get_client_version()
    server_version = roar_py_instance.get_server_version()
    print(available_maps, map_name, client_version, server_version)
    roar_py_instance.close()

asyncio.run(main())
