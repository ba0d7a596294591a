"""Actors over ROAR_PY's remote protocol: the server sends an actor's sensors and (until the client has it)
its action space; the client sends its next action flattened in that space, and may close the actor."""
from .remote_actors import (RoarPyRemoteSharedActor, RoarPyRemoteActorObsInfo, RoarPyRemoteActorObsInfoRequest,
                            RoarPyRemoteClientActor)  # noqa: F401
from .remote_actor_wrappers import (RoarPyRemoteSharedActorWrapper, RoarPyRemoteServerActorWrapper)  # noqa: F401

__all__ = ["RoarPyRemoteSharedActor", "RoarPyRemoteActorObsInfo", "RoarPyRemoteActorObsInfoRequest",
           "RoarPyRemoteClientActor", "RoarPyRemoteSharedActorWrapper", "RoarPyRemoteServerActorWrapper"]
