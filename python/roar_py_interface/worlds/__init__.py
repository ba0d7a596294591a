"""ROAR_PY's world: the world a backend implements, its waypoints and the occupancy map drawn from them."""
from .occupancy_map import RoarPyOccupancyMapProducer  # noqa: F401
from .waypoint import RoarPyWaypoint, RoarPyWaypointsProjection, RoarPyWaypointsTracker  # noqa: F401
from .world import RoarPyWorld, RoarPyWorldResettable  # noqa: F401
