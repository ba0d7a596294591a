from .base_stream_services import RoarPyStreamingClient, RoarPyStreamingService  # noqa: F401
from .common import RoarPyRemoteClientWorldWithStreamClient  # noqa: F401
from .websocket_service import (RoarPyWebsocketClientService, RoarPyWebsocketClientWorldWithStreamClient,  # noqa: F401
                                RoarPyWebsocketServerService)

__all__ = ["RoarPyStreamingService", "RoarPyStreamingClient", "RoarPyRemoteClientWorldWithStreamClient",
           "RoarPyWebsocketServerService", "RoarPyWebsocketClientWorldWithStreamClient", "RoarPyWebsocketClientService"]
