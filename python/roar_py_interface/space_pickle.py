"""Spaces from pickles a peer sent: ROAR_PY's remote protocol ships observation and action spaces (and a
custom lambda sensor's readings carry theirs) as pickles, which a hostile peer could make run code or build
unbounded objects. ``loads_space`` unpickles only gymnasium's space classes and the NumPy values inside
them, refuses an array or dtype too large before NumPy builds it, and checks the whole space's size before
anything allocates by it: every refusal a ``SpacePickleError`` naming what was sent (test_roar_py_remote
test_a_hostile_server_cannot_run_code_or_exhaust_a_client)."""
import importlib
import io
import math
import pickle
import zlib

import numpy as np

from . import spaces

# A 4K RGB camera's space is the largest a CARLA sensor has: 24.9 Mi values, 100 MB pickled (low, high and
# where each is bounded, every one an array of its shape).
MAX_PICKLE_BYTES = 128 << 20  # a space's pickle, unpacked
MAX_ELEMENTS = 1 << 25       # values in all of a space's arrays together
MAX_DEPTH = 16               # spaces nested in Tuples and Dicts
MAX_SUBSPACES = 10000


class SpacePickleError(ValueError, ConnectionError):
    """A pickled space that is not one, or too large; names what was sent and why. A ConnectionError too:
    what a peer sent is refused as the connection's fault."""


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
_NUMERIC_KINDS = "biuf"


class _SpaceUnpickler(pickle._Unpickler):  # the Python unpickler: its BUILD can be checked before it runs
    def find_class(self, module: str, name: str):
        if module.startswith("numpy._core"):
            module = "numpy.core" + module[len("numpy._core"):]
        if (module, name) in _NUMPY_GLOBALS:
            return super().find_class(module, name)
        if module in _SPACE_MODULES:
            found = getattr(importlib.import_module(module), name, None)
            if isinstance(found, type) and issubclass(found, spaces.Space):
                return found
            raise SpacePickleError(f"a pickled space may hold spaces, not {module}.{name}")
        raise SpacePickleError(f"a pickled space may hold spaces and NumPy values, not {module}.{name}")

    def _load_build(self):
        target, state = self.stack[-2], self.stack[-1]
        if isinstance(target, np.ndarray):
            _check_array_state(state)
        elif isinstance(target, np.dtype):
            _check_dtype_state(state)
        pickle._Unpickler.dispatch[pickle.BUILD[0]](self)

    dispatch = dict(pickle._Unpickler.dispatch)
    dispatch[pickle.BUILD[0]] = _load_build


def _check_array_state(state):
    """An ndarray's pickled state (version, shape, dtype, fortran, data): numeric, and small."""
    if not isinstance(state, tuple) or len(state) != 5 or not isinstance(state[1], tuple):
        raise SpacePickleError("an array's pickled state is not NumPy's")
    shape, dtype = state[1], state[2]
    if not all(isinstance(d, int) and 0 <= d for d in shape) or math.prod(shape) > MAX_ELEMENTS:
        raise SpacePickleError(f"an array of shape {shape[:8]} is more than {MAX_ELEMENTS} values")
    if not isinstance(dtype, np.dtype) or dtype.kind not in _NUMERIC_KINDS or dtype.itemsize == 0:
        raise SpacePickleError(f"an array of {dtype!r}: a space's arrays are numbers")


def _check_dtype_state(state):
    """A dtype's pickled state (version, byte order, subarray, names, fields, item size, ...): a plain number."""
    if not isinstance(state, tuple) or len(state) < 8 or state[2] is not None or state[3] is not None:
        raise SpacePickleError("a dtype in a space is a plain number, not a structure")
    if state[5] not in (-1,) and not (isinstance(state[5], int) and 0 < state[5] <= 16):
        raise SpacePickleError(f"a dtype of item size {state[5]!r}: a space's numbers are at most 16 bytes")


def check_space(space, what: str = "space") -> None:
    """Refuses a space too large or not a space's shape before anything allocates by it."""
    budget = {"elements": 0, "subspaces": 0}

    def count(n: int, where: str):
        budget["elements"] += n
        if budget["elements"] > MAX_ELEMENTS:
            raise SpacePickleError(f"{what}: {where} takes it over {MAX_ELEMENTS} values")

    def shape_of(s, where):
        shape = getattr(s, "shape", None)
        if shape is not None and (not isinstance(shape, tuple) or
                                  not all(isinstance(d, (int, np.integer)) and 0 <= d for d in shape)):
            raise SpacePickleError(f"{what}: {where}'s shape is {shape!r}")
        return shape

    def visit(s, where: str, depth: int):
        budget["subspaces"] += 1
        if depth > MAX_DEPTH or budget["subspaces"] > MAX_SUBSPACES:
            raise SpacePickleError(f"{what}: nested deeper than {MAX_DEPTH} or more than {MAX_SUBSPACES} spaces")
        if not isinstance(s, spaces.Space):
            raise SpacePickleError(f"{what}: {where} is a {type(s).__name__}, not a space")
        shape = shape_of(s, where)
        kind = type(s).__name__
        if kind == "Box":
            count(math.prod(shape), where)
            for bound in ("low", "high"):
                value = getattr(s, bound, None)
                if not isinstance(value, np.ndarray) or value.shape != shape or value.dtype.kind not in _NUMERIC_KINDS:
                    raise SpacePickleError(f"{what}: {where}.{bound} is no array of numbers of shape {shape}")
        elif kind == "Discrete":
            n = getattr(s, "n", None)
            if not isinstance(n, (int, np.integer)) or not 0 < int(n) < 2 ** 63:
                raise SpacePickleError(f"{what}: {where}.n is {n!r}")
            count(1, where)
        elif kind in ("MultiBinary", "MultiDiscrete"):
            count(math.prod(shape) if shape is not None else MAX_ELEMENTS + 1, where)
        elif kind == "Tuple":
            for i, sub in enumerate(getattr(s, "spaces", ())):
                visit(sub, f"{where}[{i}]", depth + 1)
        elif kind == "Dict":
            subs = getattr(s, "spaces", {})
            if not hasattr(subs, "items"):
                raise SpacePickleError(f"{what}: {where}.spaces is no mapping")
            for key, sub in subs.items():
                visit(sub, f"{where}[{key!r}]", depth + 1)
        elif kind == "Text":
            count(int(getattr(s, "max_length", MAX_ELEMENTS + 1)), where)
        elif kind == "Sequence":
            visit(getattr(s, "feature_space", None), f"{where}.feature_space", depth + 1)
        else:
            raise SpacePickleError(f"{what}: {where} is a {kind}, which a space sent is not")

    if not isinstance(space, spaces.Space):
        raise SpacePickleError(f"{what}: the pickle holds a {type(space).__name__}, not a space")
    visit(space, "the space", 0)


def loads_space(data: bytes, what: str = "space", compressed: bool = False):
    """The space pickled in data (zlib-compressed when `compressed`), checked whole; SpacePickleError if not."""
    raw = data
    if compressed:
        try:
            inflater = zlib.decompressobj()
            raw = inflater.decompress(data, MAX_PICKLE_BYTES)
        except zlib.error as error:
            raise SpacePickleError(f"{what}: not zlib data ({error})") from None
        if inflater.unconsumed_tail:
            raise SpacePickleError(f"{what}: unpacks to more than {MAX_PICKLE_BYTES >> 20} MiB")
    if len(raw) > MAX_PICKLE_BYTES:
        raise SpacePickleError(f"{what}: a pickle of more than {MAX_PICKLE_BYTES >> 20} MiB")
    try:
        space = _SpaceUnpickler(io.BytesIO(raw)).load()
    except SpacePickleError as error:
        raise SpacePickleError(f"{what}: {error}") from None
    except Exception as error:  # noqa: BLE001 - any broken pickle is the sender's fault
        raise SpacePickleError(f"{what}: not a pickled space ({type(error).__name__}: {error})") from None
    check_space(space, what)
    return space
