"""ROAR_PY's interface (roar_py_interface), written for roar_ros: the names, arguments and behaviour of
ROAR_PY's public classes at ROAR_PY's head, with roar_py_ros as the backend over roar_sim and
roar_py_remote streaming them to other machines. Without gymnasium installed, importing this package
provides ``gymnasium`` (see gymnasium_fallback), and on shapely 1.8 shapely 2's top-level names
(shapely_names)."""
from . import spaces  # noqa: F401
from . import gymnasium_fallback, shapely_names

gymnasium_fallback.install()
shapely_names.install()

from . import transforms  # noqa: E402,F401
from .actors import (RoarPyActor, RoarPyBaseVehicle, RoarPyResettableActor, RoarPyVehicleAutoGearActor,  # noqa: E402,F401
                     RoarPyVehicleManualGearActor, observation_keys, propose_name_and_modify_dict,
                     propose_name_and_modify_list, vehicle_action_spec)
from .base import (RoarPyRemoteSupportedSensorData, RoarPyRemoteSupportedSensorSerializationScheme,  # noqa: E402,F401
                   RoarPySensor, remote_support_sensor_data_register)
from .sensors import (CARLA_SEMANTIC_LABEL_COLOR_MAP, RoarPyAccelerometerSensor,  # noqa: E402,F401
                      RoarPyAccelerometerSensorData, RoarPyCameraSensor, RoarPyCameraSensorData,
                      RoarPyCameraSensorDataDepth, RoarPyCameraSensorDataGreyscale, RoarPyCameraSensorDataRGB,
                      RoarPyCameraSensorDataSemanticSegmentation, RoarPyCollisionSensor, RoarPyCollisionSensorData,
                      RoarPyCustomLambdaSensor, RoarPyCustomLambdaSensorData, RoarPyFrameQuatSensor,
                      RoarPyFrameQuatSensorData, RoarPyFrameQuatSensorFromRollPitchYaw, RoarPyGNSSSensor,
                      RoarPyGNSSSensorData, RoarPyGyroscopeSensor, RoarPyGyroscopeSensorData, RoarPyLiDARSensor,
                      RoarPyLiDARSensorData, RoarPyLocationInWorldSensor, RoarPyLocationInWorldSensorData,
                      RoarPyOccupancyMapSensor, RoarPyOccupancyMapSensorData, RoarPyOccupancyMapSensorImpl,
                      RoarPyRadarSensor, RoarPyRadarSensorData, RoarPyRollPitchYawSensor, RoarPyRollPitchYawSensorData,
                      RoarPyRollPitchYawSensorFromFrameQuat, RoarPyVelocimeterSensor, RoarPyVelocimeterSensorData)
from .transforms import euler2mat, normalize_rad  # noqa: E402,F401
from .visualizations import RoarPyVisualizer  # noqa: E402,F401
from .worlds import (RoarPyOccupancyMapProducer, RoarPyWaypoint, RoarPyWaypointsProjection,  # noqa: E402,F401
                     RoarPyWaypointsTracker, RoarPyWorld, RoarPyWorldResettable)
from .wrappers import (RoarPyActorSensorFilterWrapper, RoarPyActorWrapper, RoarPyAddItemWrapper,  # noqa: E402,F401
                       RoarPySensorWrapper, RoarPyThreadSafeWrapper, RoarPyWorldWrapper, RoarPyWrapper,
                       roar_py_append_item, roar_py_remove_item, roar_py_thread_sync)
