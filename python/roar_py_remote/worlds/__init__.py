"""Worlds over ROAR_PY's remote protocol.

On the server, one world (roar_py_ros's, or any ROAR_PY world) is shared by a
``RoarPyRemoteServerWorldManager``: each client gets a ``RoarPyRemoteMaskedWorld``, a view that shows the
actors and sensors spawned through it and steps with the shared world. A synchronous manager steps the
shared world when every client that has been answered has asked for its next step, or when
``sync_wait_time_max`` has passed (so a stalled client slows the others, never stops them); an
asynchronous one steps it on and on. On the client, ``RoarPyRemoteClientWorld`` is the world as the
server last sent it.
"""
from .remote_worlds import (RoarPyRemoteWorldInitInfo, RoarPyRemoteWorldObsInfo, RoarPyRemoteWorldObsInfoRequest,
                            RoarPyRemoteClientWorld)  # noqa: F401
from .server_worlds import (RoarPyRemoteMaskedWorld, RoarPyRemoteServerWorldManager,
                            RoarPyRemoteServerWorldWrapper)  # noqa: F401

__all__ = ["RoarPyRemoteMaskedWorld", "RoarPyRemoteServerWorldManager", "RoarPyRemoteWorldInitInfo",
           "RoarPyRemoteWorldObsInfo", "RoarPyRemoteWorldObsInfoRequest", "RoarPyRemoteServerWorldWrapper",
           "RoarPyRemoteClientWorld"]
