"""ROAR_PY's websocket server and client.

The server (``RoarPyWebsocketServerService``) gives each client that connects a view of the shared
world (``initialize_streamed_world`` may spawn its car and sensors there) and answers its requests each
tick. It listens where the program says (``bind_addr=""`` is every interface, ROAR_PY's default), else where
``ROAR_PY_REMOTE_BIND`` says, else on loopback only. ``RoarPyWebsocketClientService.connect_to_server`` returns the client's world.
"""
import asyncio
import logging
import os
import typing

import websockets

import roar_py_interface as rpi

from ..base import RoarPyObjectWithRemoteMessage
from ..worlds import RoarPyRemoteClientWorld, RoarPyRemoteServerWorldManager, RoarPyRemoteServerWorldWrapper
from .base_stream_services import RoarPyStreamingClient
from .base_stream_services import websocket_service
from .base_service import _describe
from .common import RoarPyRemoteClientWorldWithStreamClient

_log = logging.getLogger("roar_py_remote")
LOOPBACK = "127.0.0.1"
BIND_VARIABLE = "ROAR_PY_REMOTE_BIND"  # where a server listens when its program gives no address
MAX_REQUEST_BYTES = 1 << 20   # a client's request: actions and flags, a few hundred bytes
MAX_MESSAGE_BYTES = 32 << 20  # the server's answer: camera frames, and the waypoints once (about 1 MB on Monza)
KEEPALIVE_S = 5.0
SETTLE_S = 1.0  # at most, a new client's set-up waits for a tick


class RoarPyWebsocketServerService(websocket_service.RoarPyWebsocketStreamingService):
    def __init__(self, server_world_manager: RoarPyRemoteServerWorldManager):
        super().__init__()
        self.server_world_manager = server_world_manager
        self._client_to_world_map: typing.Dict[typing.Any, RoarPyRemoteServerWorldWrapper] = {}
        self._ticked: typing.Optional[asyncio.Event] = None  # set after each tick of run_server

    async def initialize_streamed_world(self, client, world: rpi.RoarPyWorld) -> bool:
        """Override: prepare a new client's world (spawn its car, attach its sensors); False turns it away."""
        return True

    async def generate_streamable_object(self, client) -> typing.Optional[RoarPyObjectWithRemoteMessage]:
        await self._let_the_departed_leave()
        masked_world = self.server_world_manager.get_world()
        try:
            accepted = await self.initialize_streamed_world(client, masked_world)
        except Exception:
            masked_world.close()
            raise
        if not accepted:
            masked_world.close()
            return None
        wrapper = RoarPyRemoteServerWorldWrapper(masked_world)
        self._client_to_world_map[client] = wrapper
        return wrapper

    async def client_disconnected(self, client):
        await super().client_disconnected(client)
        self._client_to_world_map.pop(client, None)

    async def _let_the_departed_leave(self):
        """A client that has just said goodbye still has its car until its handler runs: a new client's
        set-up waits for the next tick (where goodbyes arrive) and closes the cars of clients whose
        connections are closing, so that a program spawning where the last one did finds the place free
        (test_roar_py_remote test_back_to_back_clients_find_the_spawn_point_free)."""
        if self._ticked is not None:
            self._ticked.clear()
            try:
                await asyncio.wait_for(self._ticked.wait(), SETTLE_S)
            except asyncio.TimeoutError:
                pass
        for other in list(self._client_to_world_map):
            if not getattr(other, "open", True):
                await self.client_disconnected(other)

    async def _websocket_handler(self, websocket):
        try:
            await self.new_client_connected(websocket)
        except Exception as error:  # noqa: BLE001 - the program's set-up failing for one client
            _log.exception("client %s: setting up its world failed", _describe(websocket))
            await websocket.close(code=1011, reason=f"setting up the world failed: {type(error).__name__}"[:120])
            return
        try:
            async for message in websocket:
                await self.client_message_received(websocket, message)
        except websockets.exceptions.ConnectionClosed:
            pass
        finally:
            await self.client_disconnected(websocket)

    async def run_server(self, bind_addr: typing.Optional[str] = None, bind_port: int = 80):
        """Serves until cancelled (or the world fails): steps the shared world and answers the clients."""
        host = serving_address(bind_addr, bind_port)
        # Pings every 5 s, answered within 10 s: a client gone silent is closed within seconds.
        async with websockets.serve(self._websocket_handler, host, bind_port, max_size=MAX_REQUEST_BYTES,
                                    ping_interval=KEEPALIVE_S, ping_timeout=2 * KEEPALIVE_S):
            _log.info("serving ROAR_PY's remote protocol on ws://%s:%d", host or "0.0.0.0", bind_port)
            self._ticked = asyncio.Event()
            while True:
                await self.server_world_manager._step()
                await self.tick()
                self._ticked.set()


def serving_address(bind_addr: typing.Optional[str], bind_port: int) -> str:
    """Where the server listens: the program's address, else ROAR_PY_REMOTE_BIND's, else loopback only. Said
    in the log either way, so that nobody serves the network unknowingly or wonders why no client reaches
    them (test_roar_py_remote test_other_machines_reach_the_server_only_when_asked)."""
    if bind_addr is None:
        bind_addr = os.environ.get(BIND_VARIABLE)
    if bind_addr is None:
        _log.warning("serving on %s:%d only: clients on other machines cannot connect (%s=0.0.0.0 or "
                     "run_server(bind_addr=\"\") serves every interface, as ROAR_PY does)", LOOPBACK, bind_port,
                     BIND_VARIABLE)
        return LOOPBACK
    if bind_addr in ("", "0.0.0.0", "::"):
        _log.warning("serving on every interface, port %d: anyone who reaches it can drive a car here",
                     bind_port)
    return bind_addr


class RoarPyWebsocketClientWorldWithStreamClient(RoarPyRemoteClientWorldWithStreamClient):
    def __init__(self, stream_service: RoarPyStreamingClient, websocket_client):
        super().__init__(stream_service)
        self._websocket_client = websocket_client

    async def try_receive_and_feed_service(self) -> None:
        try:
            message = await self._websocket_client.recv()
        except websockets.exceptions.ConnectionClosed as closed:
            await self._stream_service.disconnected_from_server()
            raise ConnectionError(f"the server closed the connection ({closed})") from None
        await self._stream_service.server_message_received(self._websocket_client, message)

    async def close(self) -> None:
        """Closes the connection: the server closes this client's car and sensors."""
        await self._websocket_client.close()


class RoarPyWebsocketClientService:
    @staticmethod
    async def connect_to_server(wss_address: str = "ws://localhost:8080") -> RoarPyWebsocketClientWorldWithStreamClient:
        websocket_client = await websockets.connect(wss_address, max_size=MAX_MESSAGE_BYTES)
        base_service = websocket_service.RoarPyWebsocketStreamingClient(RoarPyRemoteClientWorld)
        await base_service.connected_to_server(websocket_client)
        while base_service.stream_object is None:
            try:
                message = await websocket_client.recv()
            except websockets.exceptions.ConnectionClosed as closed:
                raise ConnectionError(f"{wss_address} closed the connection while the client was set up "
                                      f"({closed})") from None
            await base_service.server_message_received(websocket_client, message)
        return RoarPyWebsocketClientWorldWithStreamClient(base_service, websocket_client)


__all__ = ["RoarPyWebsocketServerService", "RoarPyWebsocketClientWorldWithStreamClient",
           "RoarPyWebsocketClientService"]
