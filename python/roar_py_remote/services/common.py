"""A client's world with the stream it comes over: step() sends the request and takes the answer."""
import roar_py_interface as rpi

from ..worlds import RoarPyRemoteClientWorld
from .base_stream_services import RoarPyStreamingClient


class RoarPyRemoteClientWorldWithStreamClient(rpi.RoarPyWorldWrapper):
    def __init__(self, stream_service: RoarPyStreamingClient):
        if not isinstance(stream_service.stream_object, RoarPyRemoteClientWorld):
            raise TypeError("RoarPyRemoteClientWorldWithStreamClient: the stream carries no world yet")
        rpi.RoarPyWorldWrapper.__init__(self, stream_service.stream_object, "RoarPyRemoteClientWorldWithStreamClient")
        self._stream_service = stream_service

    async def try_receive_and_feed_service(self) -> None:
        raise NotImplementedError()

    async def step(self) -> float:
        await self._stream_service.tick()  # the actions for the next step go out
        await self.try_receive_and_feed_service()
        return await self._wrapped_object.step()
