"""Gymnasium's spaces, or classes of the same names, attributes and behaviour when gymnasium is not installed.

Debian packages no gymnasium; code written for ``gymnasium.spaces`` (Box, Discrete with ``start``,
MultiBinary, Dict, Tuple: ``sample``, ``contains``, ``seed``, ``shape``, ``dtype``, ``low``/``high``;
``flatten``, ``unflatten``, ``flatdim``, ``flatten_space``) works with either. ``USING_GYMNASIUM`` says which
one is in use.

The fallback classes keep gymnasium's attribute names (``_shape``, ``low_repr``, ``bounded_below``, ...)
and its module names (``gymnasium.spaces.box`` ...), so a space pickled here unpickles as a gymnasium
space on a machine that has gymnasium, and the reverse: ROAR_PY's remote protocol ships spaces as pickles
(``test_roar_py_remote.py`` pins the pickle's layout).
"""
import collections.abc
import typing

import numpy as np

try:  # pragma: no cover - depends on the machine
    from gymnasium.spaces import Box, Dict, Discrete, MultiBinary, Space, Tuple  # noqa: F401
    from gymnasium.spaces.utils import flatdim, flatten, flatten_space, unflatten  # noqa: F401

    USING_GYMNASIUM = True
except ImportError:
    USING_GYMNASIUM = False

    class Space:
        """A set of values with a random generator: ``sample`` draws from it, ``contains`` tests it."""

        def __init__(self, shape=None, dtype=None, seed=None):
            self._shape = None if shape is None else tuple(int(d) for d in shape)
            self.dtype = None if dtype is None else np.dtype(dtype)
            self._np_random = None
            if seed is not None:
                self.seed(seed)

        @property
        def shape(self):
            return self._shape

        @property
        def np_random(self) -> np.random.Generator:
            if self._np_random is None:
                self.seed()
            return self._np_random

        @property
        def is_np_flattenable(self) -> bool:
            return False

        def seed(self, seed=None):
            seed_seq = np.random.SeedSequence(seed)
            self._np_random = np.random.Generator(np.random.PCG64(seed_seq))
            return [seed_seq.entropy if seed is None else seed]

        def sample(self, mask=None):
            raise NotImplementedError

        def contains(self, x) -> bool:
            raise NotImplementedError

        def __contains__(self, x) -> bool:
            return self.contains(x)

        def __setstate__(self, state):
            state = dict(state)
            if "shape" in state:
                state["_shape"] = state.pop("shape")
            if "np_random" in state:
                state["_np_random"] = state.pop("np_random")
            self.__dict__.update(state)

    def _short_repr(arr: np.ndarray) -> str:
        if arr.size != 0 and np.min(arr) == np.max(arr):
            return str(np.min(arr))
        return str(arr)

    class Box(Space):
        """A box in R^n (or a box of integers): ``low <= x <= high`` elementwise."""

        def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
            dtype = np.dtype(dtype)
            if shape is None:
                shape = np.shape(low) if np.ndim(low) > 0 else np.shape(high)
            shape = tuple(int(d) for d in shape)
            low = np.full(shape, low, dtype=np.float64) if np.ndim(low) == 0 else np.asarray(low, np.float64)
            high = np.full(shape, high, dtype=np.float64) if np.ndim(high) == 0 else np.asarray(high, np.float64)
            if low.shape != shape or high.shape != shape:
                raise ValueError(f"Box: low {low.shape} and high {high.shape} must have the shape {shape}")
            if np.any(low > high):
                raise ValueError("Box: low must not be above high")
            self.dtype = dtype
            self.low = low.astype(dtype)
            self.high = high.astype(dtype)
            self.low_repr = _short_repr(self.low)
            self.high_repr = _short_repr(self.high)
            self.bounded_below = -np.inf < low
            self.bounded_above = np.inf > high
            super().__init__(shape, dtype, seed)
            self._sampling = None

        def _sampling_bounds(self):
            """low, high (one above for integers) and whether bounded, as sample() uses them: made once, since
            sampling is in every random-action loop."""
            if getattr(self, "_sampling", None) is None:  # absent in a Box unpickled from gymnasium
                integer = self.dtype.kind in "iu"
                low, high = self.low.astype(np.float64), self.high.astype(np.float64)
                top = high + 1.0 if integer else high
                self._sampling = (low, high, top, top - low, integer, self.is_bounded())
            return self._sampling

        @property
        def is_np_flattenable(self) -> bool:
            return True

        def is_bounded(self, manner="both") -> bool:
            below = bool(np.all(self.bounded_below))
            above = bool(np.all(self.bounded_above))
            return {"both": below and above, "below": below, "above": above}[manner]

        def sample(self, mask=None):
            rng = self.np_random
            low, high, top, span, integer, bounded = self._sampling_bounds()
            if bounded:
                out = low + span * rng.random(size=self.shape)  # numpy's uniform(low, top), to the bit
            else:
                out = self._sample_unbounded(rng, low, top)
            if integer:
                return np.clip(np.floor(out), low, high).astype(self.dtype)
            return out.astype(self.dtype)  # uniform draws from [low, high): no clip needed

        def _sample_unbounded(self, rng, low, high):
            out = np.empty(self.shape, dtype=np.float64)
            below, above = self.bounded_below, self.bounded_above
            both, only_low = below & above, below & ~above
            only_high, neither = ~below & above, ~below & ~above
            out[both] = rng.uniform(low[both], high[both])
            out[only_low] = low[only_low] + rng.exponential(size=only_low.sum())
            out[only_high] = high[only_high] - rng.exponential(size=only_high.sum())
            out[neither] = rng.normal(size=neither.sum())
            return out

        def contains(self, x) -> bool:
            if not isinstance(x, np.ndarray):
                try:
                    x = np.asarray(x, dtype=self.dtype)
                except (ValueError, TypeError):
                    return False
            if not np.can_cast(x.dtype, self.dtype):
                return False
            return bool(x.shape == self.shape and np.all(x >= self.low) and np.all(x <= self.high))

        def __repr__(self):
            return f"Box({self.low_repr}, {self.high_repr}, {self.shape}, {self.dtype})"

        def __eq__(self, other):
            return (isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype
                    and np.allclose(self.low, other.low) and np.allclose(self.high, other.high))

    class Discrete(Space):
        """The integers ``start, start + 1, ..., start + n - 1``."""

        def __init__(self, n, seed=None, start=0):
            if int(n) <= 0:
                raise ValueError(f"Discrete: n must be positive, got {n}")
            self.n = np.int64(n)
            self.start = np.int64(start)
            super().__init__((), np.int64, seed)

        @property
        def is_np_flattenable(self) -> bool:
            return True

        def sample(self, mask=None):
            return np.int64(self.start + self.np_random.integers(self.n))

        def contains(self, x) -> bool:
            if isinstance(x, int):
                value = np.int64(x)
            elif isinstance(x, (np.generic, np.ndarray)) and x.dtype.kind in "iu" and x.shape == ():
                value = np.int64(x)
            else:
                return False
            return bool(self.start <= value < self.start + self.n)

        def __repr__(self):
            return f"Discrete({self.n}, start={self.start})" if self.start != 0 else f"Discrete({self.n})"

        def __eq__(self, other):
            return isinstance(other, Discrete) and self.n == other.n and self.start == other.start

    class MultiBinary(Space):
        """Arrays of 0 and 1 of a shape (``n`` an int or a shape)."""

        def __init__(self, n, seed=None):
            self.n = n
            shape = (int(n),) if np.ndim(n) == 0 else tuple(int(d) for d in n)
            super().__init__(shape, np.int8, seed)

        @property
        def is_np_flattenable(self) -> bool:
            return True

        def sample(self, mask=None):
            return self.np_random.integers(0, 2, size=self.shape, dtype=np.int8)

        def contains(self, x) -> bool:
            if isinstance(x, (list, tuple)):
                x = np.asarray(x)
            return bool(isinstance(x, np.ndarray) and x.shape == self.shape and x.dtype.kind in "iub"
                        and np.all((x == 0) | (x == 1)))

        def __repr__(self):
            return f"MultiBinary({self.n})"

        def __eq__(self, other):
            return isinstance(other, MultiBinary) and self.shape == other.shape

    class Tuple(Space, collections.abc.Sequence):
        """A tuple of spaces."""

        def __init__(self, spaces, seed=None):
            self.spaces = tuple(spaces)
            for i, space in enumerate(self.spaces):
                if not isinstance(space, Space):
                    raise TypeError(f"Tuple: element {i} is not a space: {space!r}")
            super().__init__(None, None, seed)

        @property
        def is_np_flattenable(self) -> bool:
            return all(s.is_np_flattenable for s in self.spaces)

        def seed(self, seed=None):
            seeds = super().seed(seed)
            for i, space in enumerate(self.spaces):
                seeds += space.seed(None if seed is None else int(seed) + i + 1)
            return seeds

        def sample(self, mask=None):
            return tuple(space.sample() for space in self.spaces)

        def contains(self, x) -> bool:
            if isinstance(x, (list, np.ndarray)):
                x = tuple(x)
            return (isinstance(x, tuple) and len(x) == len(self.spaces)
                    and all(space.contains(part) for space, part in zip(self.spaces, x)))

        def __getitem__(self, index):
            return self.spaces[index]

        def __len__(self):
            return len(self.spaces)

        def __repr__(self):
            return "Tuple(" + ", ".join(str(s) for s in self.spaces) + ")"

        def __eq__(self, other):
            return isinstance(other, Tuple) and self.spaces == other.spaces

    class Dict(Space, collections.abc.Mapping):
        """A dictionary of spaces; a plain dict's keys are sorted, as gymnasium does."""

        def __init__(self, spaces=None, seed=None, **spaces_kwargs):
            if spaces is None:
                spaces = spaces_kwargs
            if isinstance(spaces, collections.abc.Mapping) and not isinstance(spaces, collections.OrderedDict):
                try:
                    spaces = dict(sorted(spaces.items()))
                except TypeError:
                    spaces = dict(spaces.items())
            elif isinstance(spaces, collections.abc.Sequence):
                spaces = dict(spaces)
            self.spaces: typing.Dict[str, Space] = dict(spaces)
            for key, space in self.spaces.items():
                if not isinstance(space, Space):
                    raise TypeError(f"Dict: the value of '{key}' is not a space: {space!r}")
            super().__init__(None, None, None)
            if seed is not None:
                self.seed(seed)

        @property
        def is_np_flattenable(self) -> bool:
            return all(s.is_np_flattenable for s in self.spaces.values())

        def seed(self, seed=None):
            seeds = super().seed(seed)
            for i, space in enumerate(self.spaces.values()):
                seeds += space.seed(None if seed is None else int(seed) + i + 1)
            return seeds

        def sample(self, mask=None):
            return {key: space.sample() for key, space in self.spaces.items()}

        def contains(self, x) -> bool:
            return (isinstance(x, collections.abc.Mapping) and set(x.keys()) == set(self.spaces.keys())
                    and all(space.contains(x[key]) for key, space in self.spaces.items()))

        def __getitem__(self, key):
            return self.spaces[key]

        def __setitem__(self, key, space):
            if not isinstance(space, Space):
                raise TypeError(f"Dict: the value of '{key}' is not a space: {space!r}")
            self.spaces[key] = space

        def __iter__(self):
            return iter(self.spaces)

        def __len__(self):
            return len(self.spaces)

        def __repr__(self):
            return "Dict(" + ", ".join(f"{k!r}: {s}" for k, s in self.spaces.items()) + ")"

        def __eq__(self, other):
            return isinstance(other, Dict) and self.spaces == other.spaces

    def flatdim(space: Space) -> int:
        """The length of flatten(space, x)."""
        if isinstance(space, Box):
            return int(np.prod(space.shape, dtype=np.int64))
        if isinstance(space, Discrete):
            return int(space.n)
        if isinstance(space, MultiBinary):
            return int(np.prod(space.shape, dtype=np.int64))
        if isinstance(space, Tuple):
            return sum(flatdim(s) for s in space.spaces)
        if isinstance(space, Dict):
            return sum(flatdim(s) for s in space.spaces.values())
        raise NotImplementedError(f"flatdim: {type(space).__name__} is not flattenable")

    def flatten(space: Space, x) -> np.ndarray:
        """x of the space as one 1-D array (a Discrete as a one-hot vector), gymnasium's layout."""
        if isinstance(space, Box):
            return np.asarray(x, dtype=space.dtype).flatten()
        if isinstance(space, Discrete):
            onehot = np.zeros(int(space.n), dtype=space.dtype)
            onehot[int(x) - int(space.start)] = 1
            return onehot
        if isinstance(space, MultiBinary):
            return np.asarray(x, dtype=space.dtype).flatten()
        if isinstance(space, Tuple):
            return np.concatenate([np.array(flatten(s, part)) for s, part in zip(space.spaces, x)])
        if isinstance(space, Dict):
            return np.concatenate([np.array(flatten(s, x[key])) for key, s in space.spaces.items()])
        raise NotImplementedError(f"flatten: {type(space).__name__} is not flattenable")

    def unflatten(space: Space, x: np.ndarray):
        """The inverse of flatten."""
        if isinstance(space, Box):
            return np.asarray(x, dtype=space.dtype).reshape(space.shape)
        if isinstance(space, Discrete):
            nonzero = np.nonzero(x)[0]
            if len(nonzero) == 0:
                raise ValueError(f"unflatten: {x} is no one-hot vector of {space}")
            return space.start + np.int64(nonzero[0])
        if isinstance(space, MultiBinary):
            return np.asarray(x, dtype=space.dtype).reshape(space.shape)
        if isinstance(space, Tuple):
            parts = _split(space.spaces, x)
            return tuple(unflatten(s, part) for s, part in zip(space.spaces, parts))
        if isinstance(space, Dict):
            parts = _split(list(space.spaces.values()), x)
            return {key: unflatten(s, part) for (key, s), part in zip(space.spaces.items(), parts)}
        raise NotImplementedError(f"unflatten: {type(space).__name__} is not flattenable")

    def _split(spaces_list, x):
        sizes = np.cumsum([flatdim(s) for s in spaces_list])[:-1]
        return np.split(np.asarray(x), sizes)

    def flatten_space(space: Space) -> Box:
        """The Box that flatten's results lie in."""
        if isinstance(space, Box):
            return Box(space.low.flatten(), space.high.flatten(), dtype=space.dtype)
        if isinstance(space, Discrete):
            return Box(low=0, high=1, shape=(int(space.n),), dtype=space.dtype)
        if isinstance(space, MultiBinary):
            return Box(low=0, high=1, shape=(flatdim(space),), dtype=space.dtype)
        if isinstance(space, (Tuple, Dict)):
            parts = [flatten_space(s) for s in (space.spaces if isinstance(space, Tuple) else space.spaces.values())]
            return Box(low=np.concatenate([p.low for p in parts]), high=np.concatenate([p.high for p in parts]),
                       dtype=np.result_type(*[p.dtype for p in parts]))
        raise NotImplementedError(f"flatten_space: {type(space).__name__} is not flattenable")

    # gymnasium's module of each class, so that pickles name the same classes on either side.
    for _cls, _module in ((Space, "space"), (Box, "box"), (Discrete, "discrete"), (MultiBinary, "multi_binary"),
                          (Tuple, "tuple"), (Dict, "dict")):
        _cls.__module__ = f"gymnasium.spaces.{_module}"
