"""ROAR_PY's world: the actors and sensors in it, its waypoints and its clock."""
import typing

import numpy as np

from .actors import RoarPyActor
from .sensors import RoarPySensor
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
    def maneuverable_waypoints(self) -> typing.Optional[typing.List[RoarPyWaypoint]]:
        raise NotImplementedError()

    @property
    def comprehensive_waypoints(self) -> typing.Optional[typing.Dict[typing.Any, typing.List[RoarPyWaypoint]]]:
        raise NotImplementedError()

    @property
    def spawn_points(self) -> typing.List[typing.Tuple[np.ndarray, np.ndarray]]:
        raise NotImplementedError()

    async def step(self) -> float:
        raise NotImplementedError()

    @property
    def last_tick_elapsed_seconds(self) -> float:
        raise NotImplementedError()
