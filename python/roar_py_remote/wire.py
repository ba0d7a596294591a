"""ROAR_PY's remote wire format, written without pyserde (Debian has none) and byte-compatible with it.

Every message is one MessagePack map: pyserde's ``to_msgpack`` of a dataclass, its fields by name,
``Optional`` fields as nil, ``Dict[int, ...]`` as maps with integer keys, NumPy arrays as nested lists
(``use_bin_type``). Readings travel as text: base64 of the reading's ``to_data(MSGPACK_COMPRESSED)``.
Observation and action spaces travel as text too: base64 of zlib of a pickle, as ROAR_PY sends them;
``unpack_space`` unpickles only spaces (gymnasium's classes and the NumPy values inside them), so a
hostile server cannot run code in a client (test_roar_py_remote
test_a_pickle_that_is_no_space_is_refused).
"""
import base64
import binascii
import importlib
import io
import pickle
import typing
import zlib

import msgpack

from roar_py_interface import spaces
from roar_py_interface.base import SerialisedDataError, from_plain, to_plain

MAX_SPACE_BYTES = 16 << 20  # a space unpacked from the wire; real ones are a few kB
_T = typing.TypeVar("_T")


class WireFormatError(SerialisedDataError):
    """A message that is no message of its type; says which field."""


def to_msgpack(message) -> bytes:
    return msgpack.packb(to_plain(message), use_bin_type=True)


def from_msgpack(cls: typing.Type[_T], data: bytes) -> _T:
    """A message of type cls from its bytes; WireFormatError names the first field that does not fit."""
    if not isinstance(data, (bytes, bytearray)):
        raise WireFormatError(f"{cls.__name__}: a message is binary, got {type(data).__name__}")
    try:
        plain = msgpack.unpackb(data, raw=False, use_list=False, strict_map_key=False)
    except (ValueError, msgpack.ExtraData, msgpack.FormatError, msgpack.StackError) as error:
        raise WireFormatError(f"{cls.__name__}: not MessagePack ({error})") from None
    try:
        return from_plain(cls, plain)
    except WireFormatError:
        raise
    except SerialisedDataError as error:
        raise WireFormatError(str(error)) from None


def pack_space(space: spaces.Space) -> str:
    return base64.b64encode(zlib.compress(pickle.dumps(space, protocol=pickle.DEFAULT_PROTOCOL))).decode("ascii")


def unpack_space(text: str, what: str = "space") -> spaces.Space:
    """The space packed in text; refuses any pickle that builds something other than a space."""
    try:
        inflater = zlib.decompressobj()
        raw = inflater.decompress(base64.b64decode(text, validate=True), MAX_SPACE_BYTES)
    except (binascii.Error, ValueError, zlib.error) as error:
        raise WireFormatError(f"{what}: not base64 of zlib data ({error})") from None
    if inflater.unconsumed_tail:
        raise WireFormatError(f"{what}: unpacks to more than {MAX_SPACE_BYTES >> 20} MiB")
    try:
        space = _SpaceUnpickler(io.BytesIO(raw)).load()
    except WireFormatError:
        raise
    except Exception as error:  # noqa: BLE001 - any broken pickle is the sender's fault
        raise WireFormatError(f"{what}: not a pickled space ({type(error).__name__}: {error})") from None
    if not isinstance(space, spaces.Space):
        raise WireFormatError(f"{what}: the pickle holds a {type(space).__name__}, not a space")
    return space


# What a pickled gymnasium space is built from. NumPy 2 writes numpy._core where NumPy 1 has numpy.core.
_NUMPY_GLOBALS = {
    ("numpy.core.multiarray", "_reconstruct"), ("numpy.core.multiarray", "scalar"), ("numpy", "ndarray"),
    ("numpy", "dtype"), ("numpy.random._pickle", "__generator_ctor"),
    ("numpy.random._pickle", "__bit_generator_ctor"), ("numpy.random._pickle", "__randomstate_ctor"),
    ("collections", "OrderedDict"),
}
_SPACE_MODULES = {"gymnasium.spaces.space", "gymnasium.spaces.box", "gymnasium.spaces.discrete",
                  "gymnasium.spaces.multi_binary", "gymnasium.spaces.multi_discrete", "gymnasium.spaces.tuple",
                  "gymnasium.spaces.dict", "gymnasium.spaces.text", "gymnasium.spaces.sequence"}


class _SpaceUnpickler(pickle.Unpickler):
    def find_class(self, module: str, name: str):
        if module.startswith("numpy._core"):
            module = "numpy.core" + module[len("numpy._core"):]
        if (module, name) in _NUMPY_GLOBALS:
            return super().find_class(module, name)
        if module in _SPACE_MODULES:
            found = getattr(importlib.import_module(module), name, None)
            if isinstance(found, type) and issubclass(found, spaces.Space):
                return found
            raise WireFormatError(f"a pickled space may hold spaces, not {module}.{name}")
        raise WireFormatError(f"a pickled space may hold spaces and NumPy values, not {module}.{name}")
