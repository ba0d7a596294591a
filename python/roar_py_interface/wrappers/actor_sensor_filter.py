"""ROAR_PY's actor wrapper that leaves some of the actor's sensors out of its observations."""
import typing

from ..actors import RoarPyActor
from ..base import RoarPySensor
from .wrapper_base import RoarPyActorWrapper, RoarPyWrapper


class RoarPyActorSensorFilterWrapper(RoarPyActorWrapper):
    """An actor without some of its sensors: its observations and their spaces leave them out."""

    def __init__(self, wrapped_object: typing.Union[RoarPyActor, RoarPyWrapper[RoarPyActor]],
                 exclude_sensors: typing.Sequence[RoarPySensor] = (),
                 wrapper_name: str = "RoarPyActorSensorFilterWrapper"):
        super().__init__(wrapped_object, wrapper_name)
        self.exclude_sensors = list(exclude_sensors)

    def get_sensors(self) -> typing.Iterable[RoarPySensor]:
        return [s for s in self._wrapped_object.get_sensors() if s not in self.exclude_sensors]
