from ..base_service import RoarPyStreamingClient, RoarPyStreamingService  # noqa: F401
from .websocket_service import RoarPyWebsocketStreamingClient, RoarPyWebsocketStreamingService  # noqa: F401
