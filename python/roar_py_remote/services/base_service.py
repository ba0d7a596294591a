"""ROAR_PY's streaming of objects with remote messages, over any transport: the server answers each
client's request (and greets a new client) on its next tick; the client sends a request and reads the
answer. A message that does not decode, or that the server's objects cannot take, ends that client's
connection with the reason logged; other clients go on."""
import asyncio
import logging
import typing

from .. import wire
from ..base import RoarPyObjectWithRemoteMessage

_log = logging.getLogger("roar_py_remote")
_CommT = typing.TypeVar("_CommT")


# Requests a client may send before it has read the answers to the ones before: ROAR_PY's client sends one a
# step and waits for its answer; one that floods is dropped (test_roar_py_remote
# test_a_client_that_never_reads_or_floods_is_dropped_and_the_others_go_on).
MAX_UNANSWERED_REQUESTS = 8


class RoarPyStreamingService(typing.Generic[_CommT]):
    def __init__(self):
        self.client_to_stream_object: typing.Dict[_CommT, RoarPyObjectWithRemoteMessage] = {}
        self.next_update_client: typing.List[_CommT] = []
        self._unanswered: typing.Dict[_CommT, int] = {}

    async def send_message_to_client(self, client: _CommT, message: bytes):
        pass

    async def disconnect_client(self, client: _CommT):
        pass

    async def generate_streamable_object(self, client: _CommT) -> typing.Optional[RoarPyObjectWithRemoteMessage]:
        return None

    async def new_client_connected(self, client: _CommT):
        stream_object = await self.generate_streamable_object(client)
        if stream_object is None:
            await self.disconnect_client(client)
            return
        self.client_to_stream_object[client] = stream_object
        self.next_update_client.append(client)

    async def client_disconnected(self, client: _CommT):
        self._unanswered.pop(client, None)
        stream_object = self.client_to_stream_object.pop(client, None)
        if client in self.next_update_client:
            self.next_update_client.remove(client)
        if stream_object is not None and hasattr(stream_object, "close"):
            stream_object.close()

    async def _drop_client(self, client: _CommT, reason: str):
        _log.warning("client %s: %s; disconnecting it", _describe(client), reason)
        await self.disconnect_client(client)
        await self.client_disconnected(client)

    async def client_message_received(self, client: _CommT, message: bytes):
        stream_object = self.client_to_stream_object.get(client)
        if stream_object is None:
            return
        unanswered = self._unanswered.get(client, 0) + 1
        if unanswered > MAX_UNANSWERED_REQUESTS:
            await self._drop_client(client, f"it sent {unanswered} requests without reading their answers")
            return
        self._unanswered[client] = unanswered
        try:
            stream_object._depack_info(wire.from_msgpack(stream_object._in_msg_type, message))
        except Exception as error:  # noqa: BLE001 - one client's bad message must not stop the server
            await self._drop_client(client, f"{type(error).__name__}: {error}")
            return
        if client not in self.next_update_client:
            self.next_update_client.append(client)

    async def tick(self):
        due = [(c, o) for c, o in list(self.client_to_stream_object.items()) if c in self.next_update_client]
        # Requests that arrive while this tick runs are answered on the next.
        self.next_update_client = [c for c in self.next_update_client if all(c is not d for d, _ in due)]
        for client, _ in due:
            self._unanswered[client] = 0  # answered now; what it sends next is its next request
        results = await asyncio.gather(*(o._tick_remote() for _, o in due), return_exceptions=True)
        messages = []
        for (client, stream_object), result in zip(due, results):
            try:
                if isinstance(result, BaseException):
                    raise result
                messages.append((client, wire.to_msgpack(stream_object._pack_info())))
            except Exception as error:  # noqa: BLE001 - one client's failure must not stop the others
                await self._drop_client(client, f"its tick failed: {type(error).__name__}: {error}")
        await asyncio.gather(*(self.send_message_to_client(c, m) for c, m in messages), return_exceptions=True)


_CommClientT = typing.TypeVar("_CommClientT")


class RoarPyStreamingClient(typing.Generic[_CommClientT]):
    def __init__(self, target_type: typing.Type[RoarPyObjectWithRemoteMessage]) -> None:
        self.target_type = target_type
        self.stream_object: typing.Optional[RoarPyObjectWithRemoteMessage] = None
        self._connection: typing.Optional[_CommClientT] = None

    async def send_message_to_server(self, connection: _CommClientT, message: bytes):
        pass

    async def disconnect_from_server(self, connection: _CommClientT):
        pass

    async def disconnected_from_server(self):
        self._connection = None

    async def connected_to_server(self, connection: _CommClientT):
        self._connection = connection

    async def server_message_received(self, connection: _CommClientT, message: bytes):
        """Decodes the server's message into the streamed object (made from the first message). A
        message that does not decode ends the connection and raises ConnectionError saying why."""
        try:
            data = wire.from_msgpack(self.target_type._in_msg_type, message)
            if self.stream_object is None:
                self._connection = connection
                self.stream_object = self.target_type(data)
            else:
                self.stream_object._depack_info(data)
        except wire.WireFormatError as error:
            await self.disconnect_from_server(connection)
            await self.disconnected_from_server()
            raise ConnectionError(f"the server sent a message this client cannot read: {error}") from None

    async def tick(self):
        if self.stream_object is None or self._connection is None:
            return
        await self.stream_object._tick_remote()
        await self.send_message_to_server(self._connection, wire.to_msgpack(self.stream_object._pack_info()))


def _describe(client) -> str:
    address = getattr(client, "remote_address", None)
    return f"{address[0]}:{address[1]}" if isinstance(address, tuple) and len(address) >= 2 else repr(client)


__all__ = ["RoarPyStreamingService", "RoarPyStreamingClient"]
