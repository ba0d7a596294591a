"""roar_py_ros: ROAR_PY's backend over roar_sim (as roar_py_carla is over CARLA)."""
from .connection import RoarSimError  # noqa: F401
from .conversions import RoarPyCompatibilityWarning  # noqa: F401
from .instance import RoarPyRosInstance  # noqa: F401
from .sensors import (RoarPyRosAccelerometerSensor, RoarPyRosCameraSensor, RoarPyRosCollisionSensor,  # noqa: F401
                      RoarPyRosGNSSSensor, RoarPyRosGyroscopeSensor, RoarPyRosLiDARSensor,
                      RoarPyRosLocalVelocimeterSensor, RoarPyRosLocationInWorldSensor, RoarPyRosOccupancyMapSensor,
                      RoarPyRosRadarSensor, RoarPyRosRollPitchYawSensor, RoarPyRosVelocimeterSensor)
from .vehicle import RoarPyRosBoundingBox, RoarPyRosVehicle  # noqa: F401
from .world import RoarPyRosWorld  # noqa: F401
