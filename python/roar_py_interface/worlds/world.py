"""ROAR_PY's world: the actors and sensors in it, its waypoints and its clock."""
import typing

from ..actors import RoarPyActor
from ..base import RoarPySensor
from .waypoint import RoarPyWaypoint


class RoarPyWorld:
    @property
    def is_asynchronous(self) -> bool:
        raise NotImplementedError()

    def get_actors(self) -> typing.Iterable[RoarPyActor]:
        raise NotImplementedError()

    def get_sensors(self) -> typing.Iterable[RoarPySensor]:
        raise NotImplementedError()

    @property
    def maneuverable_waypoints(self) -> typing.Optional[typing.Iterable[RoarPyWaypoint]]:
        return None

    @property
    def comprehensive_waypoints(self) -> typing.Optional[typing.Dict[typing.Any, typing.List[RoarPyWaypoint]]]:
        return None

    @property
    def last_tick_elapsed_seconds(self) -> float:
        raise NotImplementedError()

    async def step(self) -> float:
        """Steps the world by one step; returns the step's length (s)."""
        raise NotImplementedError()


class RoarPyWorldResettable(RoarPyWorld):
    async def reset(self):
        """Puts the world (with its actors and sensors) back to its initial state."""
        raise NotImplementedError()
