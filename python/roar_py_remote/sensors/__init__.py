"""Sensors over ROAR_PY's remote protocol: each tick the server sends a sensor's newest reading and, until
the client has it, its observation space; the client asks for the space and may close the sensor."""
from .remote_sensors import (RoarPyRemoteSharedSensor, RoarPyRemoteSensorObsInfo, RoarPyRemoteSensorObsInfoRequest,
                             RoarPyRemoteClientSensor)  # noqa: F401
from .remote_sensor_wrappers import (RoarPyRemoteSharedSensorWrapper, RoarPyRemoteServerSensorWrapper)  # noqa: F401

__all__ = ["RoarPyRemoteSharedSensor", "RoarPyRemoteSensorObsInfo", "RoarPyRemoteSensorObsInfoRequest",
           "RoarPyRemoteClientSensor", "RoarPyRemoteSharedSensorWrapper", "RoarPyRemoteServerSensorWrapper"]
