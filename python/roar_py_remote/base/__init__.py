"""ROAR_PY's remote objects: anything that packs its state into a message and takes requests from one."""
from .remote_object import RoarPyObjectWithRemoteMessage, register_object_with_remote_message  # noqa: F401

__all__ = ["RoarPyObjectWithRemoteMessage", "register_object_with_remote_message"]
