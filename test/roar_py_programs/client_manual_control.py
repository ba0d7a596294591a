# ROAR_PY's examples/client_manual_control.py as a program of this project: the same calls in the same
# order (it has no CARLA lines). roar_ros: the server's address may be set by ROAR_PY_REMOTE_URI.
import asyncio
import os

import roar_py_interface
import roar_py_remote
from manual_control import ManualControlViewer

WEBSOCKET_URI = os.environ.get("ROAR_PY_REMOTE_URI", "ws://localhost:8080")  # roar_ros


async def main():
    world = await roar_py_remote.RoarPyWebsocketClientService.connect_to_server(WEBSOCKET_URI)

    vehicle: roar_py_interface.RoarPyActor = world.get_actors()[0]
    camera: roar_py_interface.RoarPySensor = vehicle.get_sensors()[0]

    viewer = ManualControlViewer()

    while True:
        await world.step()
        img: roar_py_interface.RoarPyCameraSensorDataRGB = await camera.receive_observation()
        control = viewer.render(img)
        if control is None:
            break
        await vehicle.apply_action(control)

if __name__ == '__main__':
    asyncio.run(main())
