"""ROAR_PY's sensors: the data each one reads and the sensor base classes a backend implements, one module per
kind as ROAR_PY keeps them. Names, fields (and their order), observation spaces and gym conversions are
ROAR_PY's (``roar_py_interface/sensors/*.py`` at ROAR_PY's head); test_roar_py_conformance.py lists them."""
from ._common import MAX_IMAGE_PIXELS  # noqa: F401
from .accelerometer_sensor import RoarPyAccelerometerSensor, RoarPyAccelerometerSensorData  # noqa: F401
from .camera_sensor import (CARLA_SEMANTIC_LABEL_COLOR_MAP, RoarPyCameraSensor, RoarPyCameraSensorData,  # noqa: F401
                            RoarPyCameraSensorDataDepth, RoarPyCameraSensorDataGreyscale, RoarPyCameraSensorDataRGB,
                            RoarPyCameraSensorDataSemanticSegmentation)
from .collision_sensor import RoarPyCollisionSensor, RoarPyCollisionSensorData  # noqa: F401
from .custom_lambda_sensor import RoarPyCustomLambdaSensor, RoarPyCustomLambdaSensorData  # noqa: F401
from .gnss_sensor import RoarPyGNSSSensor, RoarPyGNSSSensorData  # noqa: F401
from .gyroscope_sensor import RoarPyGyroscopeSensor, RoarPyGyroscopeSensorData  # noqa: F401
from .lidar_sensor import RoarPyLiDARSensor, RoarPyLiDARSensorData  # noqa: F401
from .location_in_world_sensor import RoarPyLocationInWorldSensor, RoarPyLocationInWorldSensorData  # noqa: F401
from .occupancy_map_sensor import (RoarPyOccupancyMapSensor, RoarPyOccupancyMapSensorData,  # noqa: F401
                                   RoarPyOccupancyMapSensorImpl)
from .radar_sensor import RoarPyRadarSensor, RoarPyRadarSensorData  # noqa: F401
from .rotation_sensor import (RoarPyFrameQuatSensor, RoarPyFrameQuatSensorData,  # noqa: F401
                              RoarPyFrameQuatSensorFromRollPitchYaw, RoarPyRollPitchYawSensor,
                              RoarPyRollPitchYawSensorData, RoarPyRollPitchYawSensorFromFrameQuat)
from .velocimeter_sensor import RoarPyVelocimeterSensor, RoarPyVelocimeterSensorData  # noqa: F401
