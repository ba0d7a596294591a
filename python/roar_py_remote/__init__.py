"""ROAR_PY's remote protocol (roar_py_remote), written for roar_ros: a ROAR_PY world streamed over
websockets to programs on other machines, wire-compatible with ROAR_PY's own server and client (see
wire.py), with ROAR_PY's names and module paths."""
from .actors import *  # noqa: F401,F403
from .base import RoarPyObjectWithRemoteMessage, register_object_with_remote_message  # noqa: F401
from .sensors import *  # noqa: F401,F403
from .services import *  # noqa: F401,F403
from .worlds import *  # noqa: F401,F403
