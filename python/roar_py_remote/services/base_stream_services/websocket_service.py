"""ROAR_PY's streaming over websockets: a message is one binary websocket message. The server never waits on
one client: each client's answers go through a short queue of its own, written by a task of its own, so a
client that does not read holds up nobody and is dropped once its queue is full; a client is closed in the
background (test_roar_py_remote test_a_client_that_never_reads_or_floods_is_dropped_and_the_others_go_on)."""
import asyncio
import typing

import websockets

from ..base_service import RoarPyStreamingClient, RoarPyStreamingService

SEND_QUEUE = 4  # answers a client may leave unread before it is dropped


class RoarPyWebsocketStreamingService(RoarPyStreamingService):
    def __init__(self):
        super().__init__()
        self._outboxes: typing.Dict[typing.Any, asyncio.Queue] = {}
        self._writers: typing.Dict[typing.Any, asyncio.Task] = {}

    async def send_message_to_client(self, client, message: bytes):
        outbox = self._outboxes.get(client)
        if outbox is None:
            outbox = self._outboxes[client] = asyncio.Queue(SEND_QUEUE)
            self._writers[client] = asyncio.ensure_future(self._write(client, outbox))
        try:
            outbox.put_nowait(message)
        except asyncio.QueueFull:
            await self._drop_client(client, f"it has left its last {SEND_QUEUE} answers unread")

    @staticmethod
    async def _write(client, outbox: asyncio.Queue):
        try:
            while True:
                await client.send(await outbox.get())
        except websockets.exceptions.ConnectionClosed:
            pass

    async def disconnect_client(self, client):
        asyncio.ensure_future(client.close())  # its closing handshake waits on the client: not on the server

    async def client_disconnected(self, client):
        writer = self._writers.pop(client, None)
        if writer is not None:
            writer.cancel()
        self._outboxes.pop(client, None)
        await super().client_disconnected(client)


class RoarPyWebsocketStreamingClient(RoarPyStreamingClient):
    async def send_message_to_server(self, connection, message: bytes):
        await connection.send(message)

    async def disconnect_from_server(self, connection):
        await connection.close()


__all__ = ["RoarPyWebsocketStreamingService", "RoarPyWebsocketStreamingClient"]
