"""ROAR_PY's base classes: the sensor and the data a remote peer can be sent, with their serialisation."""
from .sensor import (MAX_INFLATED_BYTES, RoarPyRemoteSupportedSensorData,  # noqa: F401
                     RoarPyRemoteSupportedSensorSerializationScheme, RoarPySensor, SerialisedDataError, from_plain,
                     inflate, remote_support_sensor_data_register, to_plain)
