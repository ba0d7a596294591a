"""ROAR_PY's base: the sensor every backend implements, and sensor data that crosses to other machines.

``RoarPyRemoteSupportedSensorData.to_data``/``from_data`` serialise a reading in the schemes of ROAR_PY
(pyserde's dict, JSON, YAML, TOML and MessagePack, each optionally zlib-compressed): a dataclass's fields
by name, NumPy arrays as nested lists, as pyserde writes them; readings with a ``to_data`` of their own
(camera images and occupancy maps as JPEG) override it. ROAR_PY's remote protocol sends readings as
``MSGPACK_COMPRESSED`` (test_roar_py_remote.py).
"""
import collections.abc
import dataclasses
import enum
import json
import typing
import zlib

import numpy as np

from .. import spaces

_ObsT = typing.TypeVar("_ObsT")


class RoarPyRemoteSupportedSensorSerializationScheme(enum.Enum):
    DICT = 1
    JSON = 2
    YAML = 4
    TOML = 8
    MSGPACK = 16
    INTERNAL_COMPRESSED = 64
    JSON_COMPRESSED = 2 | 64
    YAML_COMPRESSED = 4 | 64
    TOML_COMPRESSED = 8 | 64
    MSGPACK_COMPRESSED = 16 | 64


_Scheme = RoarPyRemoteSupportedSensorSerializationScheme


def to_plain(value):
    """pyserde's to_dict of a value: dataclasses as dicts of their fields, arrays and tuples as lists."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: to_plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, (list, tuple)):
        return [to_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: to_plain(v) for k, v in value.items()}
    return value


class SerialisedDataError(ValueError):
    """Serialised data that does not fit its type; the message names the field (``Class.field[key]``)."""


MAX_INFLATED_BYTES = 64 << 20  # a compressed reading, inflated: a 4K RGB frame is 25 MB


def inflate(data: bytes, what: str, limit: int = MAX_INFLATED_BYTES) -> bytes:
    """zlib data inflated, refused past `limit` bytes before they are made (a zlib bomb from a peer)."""
    try:
        inflater = zlib.decompressobj()
        out = inflater.decompress(data, limit)
    except (zlib.error, TypeError) as error:
        raise SerialisedDataError(f"{what}: not zlib data ({error})") from None
    if inflater.unconsumed_tail:
        raise SerialisedDataError(f"{what}: inflates to more than {limit >> 20} MiB")
    return out


def from_plain(cls, data, where: typing.Optional[str] = None):
    """A value of type ``cls`` from its to_plain form, as pyserde's from_dict reads it: dataclasses from
    mappings of their fields (unknown keys ignored, missing ones refused), ``Optional``, ``List``, ``Dict``,
    ``np.ndarray`` from nested lists of numbers, and numbers, strings and booleans checked."""
    return _from_plain(cls, data, where or getattr(cls, "__name__", str(cls)))


def _from_plain(hint, value, where: str):
    if hint is typing.Any or isinstance(hint, typing.TypeVar):
        return value
    origin = typing.get_origin(hint)
    if origin is typing.Union:
        return _from_union(typing.get_args(hint), value, where)
    if origin in (list, typing.List, collections.abc.Sequence, collections.abc.Iterable):
        return [_from_plain(_arg(hint, 0), v, f"{where}[{i}]") for i, v in enumerate(_sequence(value, where))]
    if origin in (dict, typing.Dict, collections.abc.Mapping):
        key_hint, value_hint = _arg(hint, 0), _arg(hint, 1)
        return {_from_plain(key_hint, k, f"{where} key {k!r}"): _from_plain(value_hint, v, f"{where}[{k!r}]")
                for k, v in _mapping(value, where).items()}
    if origin is tuple:
        return tuple(_from_plain(_arg(hint, 0), v, f"{where}[{i}]") for i, v in enumerate(_sequence(value, where)))
    if dataclasses.is_dataclass(hint):
        return _from_dataclass(hint, value, where)
    return _from_scalar(hint, value, where)


def _arg(hint, index: int):
    args = typing.get_args(hint)
    return args[index] if len(args) > index else typing.Any


def _from_union(members, value, where: str):
    if value is None and type(None) in members:
        return None
    errors = []
    for member in (m for m in members if m is not type(None)):
        try:
            return _from_plain(member, value, where)
        except SerialisedDataError as error:
            errors.append(str(error))
    raise SerialisedDataError(errors[0] if len(errors) == 1 else f"{where}: {value!r} fits none of {members}")


def _sequence(value, where: str):
    if not isinstance(value, (list, tuple)):
        raise SerialisedDataError(f"{where}: expected a list, got {type(value).__name__}")
    return value


def _mapping(value, where: str):
    if not isinstance(value, dict):
        raise SerialisedDataError(f"{where}: expected a mapping, got {type(value).__name__}")
    return value


def _from_dataclass(cls, value, where: str):
    fields = _mapping(value, where)
    hints = typing.get_type_hints(cls)
    values = {}
    for f in dataclasses.fields(cls):
        if f.name not in fields:
            if f.default is not dataclasses.MISSING or f.default_factory is not dataclasses.MISSING:
                continue
            raise SerialisedDataError(f"{where}: no field '{f.name}'")
        values[f.name] = _from_plain(hints.get(f.name, typing.Any), fields[f.name], f"{where}.{f.name}")
    return cls(**values)


def _from_scalar(hint, value, where: str):
    if hint is np.ndarray:
        try:
            array = np.array(value)
        except (ValueError, TypeError) as error:
            raise SerialisedDataError(f"{where}: expected nested lists of numbers ({error})") from None
        if array.dtype.kind not in "biuf":
            raise SerialisedDataError(f"{where}: expected nested lists of numbers, got {array.dtype} values")
        return array
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SerialisedDataError(f"{where}: expected a number, got {type(value).__name__}")
        return float(value)
    if hint is int or hint is bool or hint is str or hint is bytes:
        if type(value) is not hint:
            raise SerialisedDataError(f"{where}: expected {hint.__name__}, got {type(value).__name__}")
        return value
    if isinstance(hint, type) and issubclass(hint, enum.Enum):
        try:
            return hint(value)
        except ValueError:
            raise SerialisedDataError(f"{where}: {value!r} is no {hint.__name__}") from None
    return value


def _encode(plain, scheme: _Scheme) -> bytes:
    kind = scheme.value & ~_Scheme.INTERNAL_COMPRESSED.value
    if kind == _Scheme.JSON.value:
        return json.dumps(plain).encode("utf-8")
    if kind == _Scheme.YAML.value:
        import yaml

        return yaml.safe_dump(plain).encode("utf-8")
    if kind == _Scheme.TOML.value:
        import toml

        return toml.dumps(plain).encode("utf-8")
    if kind == _Scheme.MSGPACK.value:
        import msgpack

        return msgpack.packb(plain, use_bin_type=True)
    raise NotImplementedError(f"serialisation scheme {scheme.name}")


def _decode(data: bytes, scheme: _Scheme):
    kind = scheme.value & ~_Scheme.INTERNAL_COMPRESSED.value
    if kind == _Scheme.JSON.value:
        return json.loads(data.decode("utf-8"))
    if kind == _Scheme.YAML.value:
        import yaml

        return yaml.safe_load(data.decode("utf-8"))
    if kind == _Scheme.TOML.value:
        import toml

        return toml.loads(data.decode("utf-8"))
    if kind == _Scheme.MSGPACK.value:
        import msgpack

        return msgpack.unpackb(data, raw=False, strict_map_key=False)
    raise NotImplementedError(f"serialisation scheme {scheme.name}")


class RoarPyRemoteSupportedSensorData:
    """Sensor data that serialises for ROAR_PY's remote protocol; registered by class name."""

    _supported_data_types: typing.Dict[str, typing.Type["RoarPyRemoteSupportedSensorData"]] = {}

    def to_data(self, scheme: RoarPyRemoteSupportedSensorSerializationScheme) -> typing.Any:
        plain = to_plain(self)
        if scheme == _Scheme.DICT:
            return plain
        data = _encode(plain, scheme)
        if scheme.value & _Scheme.INTERNAL_COMPRESSED.value:
            data = zlib.compress(data)
        return data

    @classmethod
    def from_data(cls, data: typing.Any,
                  scheme: RoarPyRemoteSupportedSensorSerializationScheme) -> "RoarPyRemoteSupportedSensorData":
        if hasattr(cls, "from_data_custom"):
            return cls.from_data_custom(data, scheme)
        if scheme == _Scheme.DICT:
            return from_plain(cls, data)
        if scheme.value & _Scheme.INTERNAL_COMPRESSED.value:
            data = inflate(data, f"{cls.__name__}: compressed reading")
        return from_plain(cls, _decode(data, scheme))

    def get_gym_observation_spec(self) -> spaces.Space:
        raise NotImplementedError()

    def convert_obs_to_gym_obs(self):
        raise NotImplementedError()


def remote_support_sensor_data_register(cls):
    RoarPyRemoteSupportedSensorData._supported_data_types[cls.__name__] = cls
    return cls


class RoarPySensor(typing.Generic[_ObsT]):
    """A sensor: ``receive_observation`` waits for its reading of the current step."""

    sensordata_type: typing.Type = object

    def __init__(self, name: str, control_timestep: float):
        self.name = name
        self._control_timestep = control_timestep

    @property
    def control_timestep(self) -> float:
        return self._control_timestep

    @control_timestep.setter
    def control_timestep(self, value: float):
        self._control_timestep = value

    def get_gym_observation_spec(self) -> spaces.Space:
        raise NotImplementedError()

    async def receive_observation(self) -> _ObsT:
        raise NotImplementedError()

    def get_last_observation(self) -> typing.Optional[_ObsT]:
        raise NotImplementedError()

    def convert_obs_to_gym_obs(self, obs: _ObsT):
        return obs.convert_obs_to_gym_obs()

    def get_last_gym_observation(self) -> typing.Optional[typing.Any]:
        obs = self.get_last_observation()
        return None if obs is None else self.convert_obs_to_gym_obs(obs)

    def close(self):
        raise NotImplementedError()

    def is_closed(self) -> bool:
        raise NotImplementedError()

    def __del__(self):
        try:
            if not self.is_closed():
                self.close()
        except Exception:  # noqa: BLE001 - nothing may escape a finaliser
            pass
