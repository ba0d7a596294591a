"""ROAR_PY's interface (roar_py_interface), written for roar_ros: the names and behaviour of ROAR_PY's
public classes, with roar_py_ros as the backend over roar_sim."""
from . import spaces  # noqa: F401
from .actors import (RoarPyActor, RoarPyBaseVehicle, RoarPyResettableActor, observation_keys,  # noqa: F401
                     vehicle_action_spec)
from .sensors import (RoarPyAccelerometerSensor, RoarPyAccelerometerSensorData, RoarPyCameraSensor,  # noqa: F401
                      RoarPyCameraSensorData, RoarPyCameraSensorDataDepth, RoarPyCameraSensorDataGreyscale,
                      RoarPyCameraSensorDataRGB, RoarPyCameraSensorDataSemanticSegmentation, RoarPyCollisionSensor,
                      RoarPyCollisionSensorData, RoarPyGNSSSensor, RoarPyGNSSSensorData, RoarPyGyroscopeSensor,
                      RoarPyGyroscopeSensorData, RoarPyLiDARSensor, RoarPyLiDARSensorData,
                      RoarPyLocationInWorldSensor, RoarPyLocationInWorldSensorData, RoarPyOccupancyMapSensor,
                      RoarPyOccupancyMapSensorData, RoarPyRollPitchYawSensor, RoarPyRollPitchYawSensorData,
                      RoarPySensor, RoarPyVelocimeterSensor, RoarPyVelocimeterSensorData, SEMANTIC_LABEL_COLOR_MAP)
from .waypoint import RoarPyWaypoint, euler2mat, interpolate_waypoints, normalize_rad  # noqa: F401
from .world import RoarPyWorld  # noqa: F401
