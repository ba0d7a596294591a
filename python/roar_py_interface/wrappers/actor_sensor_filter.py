"""ROAR_PY's actor wrapper that leaves some of the actor's sensors out of its observations."""
import typing

from .. import spaces
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

    async def receive_observation(self) -> typing.Dict[str, typing.Any]:
        return await RoarPyActor.receive_observation(self)

    def get_last_observation(self) -> typing.Optional[typing.Dict[str, typing.Any]]:
        return self._last_obs

    def get_last_gym_observation(self) -> typing.Optional[typing.Dict[str, typing.Any]]:
        obs = self.get_last_observation()
        return None if obs is None else self.convert_obs_to_gym_obs(obs)

    def get_gym_observation_spec(self) -> spaces.Space:
        return RoarPyActor.get_gym_observation_spec(self)

    def convert_obs_to_gym_obs(self, observation: typing.Dict[str, typing.Any]) -> typing.Dict[str, typing.Any]:
        return RoarPyActor.convert_obs_to_gym_obs(self, observation)
