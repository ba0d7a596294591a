"""ROAR_PY's remote wire format, written without pyserde (Debian has none) and byte-compatible with it.

Every message is one MessagePack map: pyserde's ``to_msgpack`` of a dataclass, its fields by name,
``Optional`` fields as nil, ``Dict[int, ...]`` as maps with integer keys, NumPy arrays as nested lists
(``use_bin_type``). Readings travel as text: base64 of the reading's ``to_data(MSGPACK_COMPRESSED)``.
Observation and action spaces travel as text too: base64 of zlib of a pickle, as ROAR_PY sends them;
``unpack_space`` unpickles only spaces, and only small ones (roar_py_interface.space_pickle), so a hostile
server can neither run code in a client nor exhaust it (test_roar_py_remote
test_a_pickle_that_is_no_space_is_refused, test_a_hostile_server_cannot_run_code_or_exhaust_a_client).
"""
import base64
import binascii
import pickle
import typing
import zlib

import msgpack

from roar_py_interface import space_pickle, spaces
from roar_py_interface.base import SerialisedDataError, from_plain, to_plain

_T = typing.TypeVar("_T")


class WireFormatError(SerialisedDataError, ConnectionError):
    """A message that is no message of its type; says which field. A ConnectionError too: what a peer sent
    is refused as the connection's fault."""


def to_msgpack(message) -> bytes:
    return msgpack.packb(to_plain(message), use_bin_type=True)


def _unpack_failure(error: Exception) -> str:
    """msgpack's reason; its stack and format errors come without one."""
    if isinstance(error, msgpack.StackError):
        return "nested deeper than the decoder allows"
    if isinstance(error, msgpack.FormatError):
        return "a byte that starts no MessagePack value"
    return str(error) or type(error).__name__


def from_msgpack(cls: typing.Type[_T], data: bytes) -> _T:
    """A message of type cls from its bytes; WireFormatError names the first field that does not fit."""
    if not isinstance(data, (bytes, bytearray)):
        raise WireFormatError(f"{cls.__name__}: a message is binary, got {type(data).__name__}")
    try:
        plain = msgpack.unpackb(data, raw=False, use_list=False, strict_map_key=False)
    except (ValueError, msgpack.ExtraData, msgpack.FormatError, msgpack.StackError) as error:
        raise WireFormatError(f"{cls.__name__}: not MessagePack ({_unpack_failure(error)})") from None
    try:
        return from_plain(cls, plain)
    except WireFormatError:
        raise
    except SerialisedDataError as error:
        raise WireFormatError(str(error)) from None


def pack_space(space: spaces.Space) -> str:
    return base64.b64encode(zlib.compress(pickle.dumps(space, protocol=pickle.DEFAULT_PROTOCOL))).decode("ascii")


def unpack_space(text: str, what: str = "space") -> spaces.Space:
    """The space packed in text; refuses any pickle that builds something other than a space, or a large one
    (roar_py_interface.space_pickle)."""
    try:
        data = base64.b64decode(text, validate=True)
    except (binascii.Error, ValueError, TypeError) as error:
        raise WireFormatError(f"{what}: not base64 ({error})") from None
    try:
        return space_pickle.loads_space(data, what, compressed=True)
    except space_pickle.SpacePickleError as error:
        raise WireFormatError(str(error)) from None
