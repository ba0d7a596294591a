"""ROAR_PY's wrappers: of actors, sensors and worlds, thread-safe ones, and the actor sensor filter."""
from .actor_sensor_filter import RoarPyActorSensorFilterWrapper  # noqa: F401
from .wrapper_base import (RoarPyActorWrapper, RoarPyAddItemWrapper, RoarPySensorWrapper,  # noqa: F401
                           RoarPyThreadSafeWrapper, RoarPyWorldWrapper, RoarPyWrapper, roar_py_append_item,
                           roar_py_remove_item, roar_py_thread_sync)
