# ROAR_PY's examples/run_server.py as a program of this project: the same calls in the same order.
# roar_ros: roar_py_ros's instance where ROAR_PY's makes a CARLA client and instance; the port may be set
# by ROAR_PY_REMOTE_PORT (8080 as ROAR_PY's when unset) so that tests do not collide.
import asyncio
import os

import numpy as np

import roar_py_interface
import roar_py_remote
import roar_py_remote.services.base_stream_services.websocket_service  # noqa: F401
import roar_py_ros  # roar_ros

IS_ASYNC = False
SYNC_WAIT_TIME = 0.5
PORT = int(os.environ.get("ROAR_PY_REMOTE_PORT", "8080"))  # roar_ros


class ServerInst(roar_py_remote.RoarPyWebsocketServerService):
    async def initialize_streamed_world(self, client, world: roar_py_ros.RoarPyRosWorld) -> bool:
        waypoints = world.maneuverable_waypoints
        new_vehicle = None
        while new_vehicle is None:
            spawning_waypoint = waypoints[0]
            new_vehicle = world.spawn_vehicle(
                "vehicle.tesla.model3",
                spawning_waypoint.location + np.array([0, 0, 0.5]),
                spawning_waypoint.roll_pitch_yaw,
                True,
                "roar_py_remote_vehicle"
            )
        new_vehicle.attach_camera_sensor(
            roar_py_interface.RoarPyCameraSensorDataRGB,
            np.array([-2.0 * new_vehicle.bounding_box.extent[0], 0.0, 3.0 * new_vehicle.bounding_box.extent[2]]),
            np.array([0, 10 / 180.0 * np.pi, 0]),
            image_width=600,
            image_height=400
        )
        await world.step()
        return True


async def _main():
    print("Connecting to roar_sim...")  # roar_ros
    roar_py_instance = roar_py_ros.RoarPyRosInstance()  # roar_ros
    roar_py_instance.world.set_asynchronous(True)
    roar_py_instance.world.set_control_steps(0.0, 0.005)
    await roar_py_instance.world.step()
    roar_py_instance.clean_actors_not_registered()

    roar_py_server_manager = roar_py_remote.RoarPyRemoteServerWorldManager(roar_py_instance.world, IS_ASYNC,
                                                                           SYNC_WAIT_TIME, thread_safe=False)
    print("Initializing websocket server...")
    roar_py_websocket_server = ServerInst(roar_py_server_manager)
    print("Initialized, starting websocket server...")
    try:
        await roar_py_websocket_server.run_server(bind_port=PORT)
    finally:
        roar_py_instance.close()


if __name__ == "__main__":
    asyncio.run(_main())
