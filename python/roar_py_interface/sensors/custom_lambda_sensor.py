"""ROAR_PY's custom lambda sensor: a sensor whose readings a subclass makes, values of a gym space."""
import dataclasses
import typing

import numpy as np

from .. import spaces
from ..base import remote_support_sensor_data_register, RoarPyRemoteSupportedSensorData, RoarPySensor
from ._common import _Scheme


@remote_support_sensor_data_register
@dataclasses.dataclass
class RoarPyCustomLambdaSensorData(RoarPyRemoteSupportedSensorData):
    flattened: np.ndarray
    space: spaces.Space

    @property
    def unflattened(self):
        return spaces.unflatten(self.space, self.flattened)

    def get_gym_observation_spec(self) -> spaces.Space:
        return self.space

    def convert_obs_to_gym_obs(self):
        return spaces.unflatten(self.space, self.flattened)

    def to_data(self, scheme: _Scheme) -> bytes:
        import msgpack
        import pickle
        import zlib

        return msgpack.packb({"flattened": self.flattened.tolist(), "space": zlib.compress(pickle.dumps(self.space))},
                             use_bin_type=True)

    @staticmethod
    def from_data_custom(data: bytes, scheme: _Scheme) -> "RoarPyCustomLambdaSensorData":
        """ROAR_PY's own encoding (a pickled space), unpickled only as a space and checked for size: a reading
        from a peer runs no code (space_pickle)."""
        import msgpack

        from ..space_pickle import SpacePickleError, loads_space

        what = "RoarPyCustomLambdaSensorData"
        try:
            fields = msgpack.unpackb(data, raw=False, strict_map_key=False)
        except (ValueError, msgpack.ExtraData, msgpack.FormatError, msgpack.StackError) as error:
            raise SpacePickleError(f"{what}: not MessagePack ({error})") from None
        if not isinstance(fields, dict) or not isinstance(fields.get("flattened"), (list, tuple)) or \
                not isinstance(fields.get("space"), bytes):
            raise SpacePickleError(f"{what}: serialised data needs 'flattened' (a list) and 'space' (bytes)")
        space = loads_space(fields["space"], f"{what}.space", compressed=True)
        size = spaces.flatdim(space)
        if len(fields["flattened"]) != size:
            raise SpacePickleError(f"{what}.flattened: {len(fields['flattened'])} values for a space of {size}")
        try:
            flattened = np.asarray(fields["flattened"], dtype=np.float64)
        except (TypeError, ValueError):
            raise SpacePickleError(f"{what}.flattened: not a list of numbers") from None
        return RoarPyCustomLambdaSensorData(flattened=flattened, space=space)


class RoarPyCustomLambdaSensor(RoarPySensor[RoarPyCustomLambdaSensorData]):
    """A sensor whose reading is a value of data_space; abstract, as ROAR_PY's: a subclass implements
    receive_observation, and may hand its value to ``observed`` to have it checked against the space,
    flattened and kept as the last observation."""

    sensordata_type = RoarPyCustomLambdaSensorData

    def __init__(self, name: str, control_timestep: float, data_space: spaces.Space):
        super().__init__(name, control_timestep)
        self.data_space = data_space
        self._last_obs: typing.Optional[RoarPyCustomLambdaSensorData] = None
        self._closed = False

    def get_gym_observation_spec(self) -> spaces.Space:
        return self.data_space

    def convert_obs_to_gym_obs(self, obs: RoarPyCustomLambdaSensorData):
        return obs.convert_obs_to_gym_obs()

    def observed(self, value: typing.Any) -> RoarPyCustomLambdaSensorData:
        """A subclass's reading: checked against data_space, flattened and kept as the last observation."""
        if self._closed:
            raise RuntimeError(f"sensor '{self.name}' is closed")
        if not self.data_space.contains(value):
            raise ValueError(f"sensor '{self.name}': {value!r} is not a value of {self.data_space}")
        self._last_obs = RoarPyCustomLambdaSensorData(spaces.flatten(self.data_space, value), self.data_space)
        return self._last_obs

    async def receive_observation(self) -> RoarPyCustomLambdaSensorData:
        raise NotImplementedError(f"sensor '{self.name}': a RoarPyCustomLambdaSensor's subclass implements "
                                  "receive_observation")

    def get_last_observation(self) -> typing.Optional[RoarPyCustomLambdaSensorData]:
        return self._last_obs

    def close(self):
        self._closed = True

    def is_closed(self) -> bool:
        return self._closed
