"""Gymnasium's space classes, or classes of the same names and behaviour when gymnasium is not installed.

Debian packages no gymnasium; code written for ``gymnasium.spaces`` (Box, Discrete with ``start``,
MultiBinary, Dict: ``sample``, ``contains``, ``seed``, ``shape``, ``dtype``, ``low``/``high``) works with
either. ``USING_GYMNASIUM`` says which one is in use.
"""
import collections.abc
import typing

import numpy as np

try:  # pragma: no cover - depends on the machine
    from gymnasium.spaces import Box, Dict, Discrete, MultiBinary, Space  # noqa: F401

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

        def seed(self, seed=None):
            seed_seq = np.random.SeedSequence(seed)
            self._np_random = np.random.Generator(np.random.PCG64(seed_seq))
            return [seed_seq.entropy if seed is None else seed]

        def sample(self):
            raise NotImplementedError

        def contains(self, x) -> bool:
            raise NotImplementedError

        def __contains__(self, x) -> bool:
            return self.contains(x)

    class Box(Space):
        """A box in R^n (or a box of integers): ``low <= x <= high`` elementwise."""

        def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
            dtype = np.dtype(dtype)
            if shape is None:
                shape = np.shape(low) if np.ndim(low) > 0 else np.shape(high)
            shape = tuple(int(d) for d in shape)
            self.low = np.full(shape, low, dtype=np.float64) if np.ndim(low) == 0 else np.asarray(low, np.float64)
            self.high = np.full(shape, high, dtype=np.float64) if np.ndim(high) == 0 else np.asarray(high, np.float64)
            if self.low.shape != shape or self.high.shape != shape:
                raise ValueError(f"Box: low {self.low.shape} and high {self.high.shape} must have the shape {shape}")
            if np.any(self.low > self.high):
                raise ValueError("Box: low must not be above high")
            self.low = self.low.astype(dtype)
            self.high = self.high.astype(dtype)
            super().__init__(shape, dtype, seed)

        def is_bounded(self, manner="both") -> bool:
            below = bool(np.all(np.isfinite(self.low)))
            above = bool(np.all(np.isfinite(self.high)))
            return {"both": below and above, "below": below, "above": above}[manner]

        def sample(self):
            low = self.low.astype(np.float64)
            high = self.high.astype(np.float64)
            if self.dtype.kind in "iu":
                high = np.where(np.isfinite(high), high + 1, high)
            out = np.empty(self.shape, dtype=np.float64)
            both = np.isfinite(low) & np.isfinite(high)
            only_low = np.isfinite(low) & ~np.isfinite(high)
            only_high = ~np.isfinite(low) & np.isfinite(high)
            neither = ~np.isfinite(low) & ~np.isfinite(high)
            rng = self.np_random
            out[both] = rng.uniform(low[both], high[both])
            out[only_low] = low[only_low] + rng.exponential(size=only_low.sum())
            out[only_high] = high[only_high] - rng.exponential(size=only_high.sum())
            out[neither] = rng.normal(size=neither.sum())
            if self.dtype.kind in "iu":
                out = np.floor(out)
            return np.clip(out, low, self.high.astype(np.float64)).astype(self.dtype)

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
            def bound(b):
                return str(b.flat[0]) if b.size and np.all(b == b.flat[0]) else str(b)

            return f"Box({bound(self.low)}, {bound(self.high)}, {self.shape}, {self.dtype})"

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

        def sample(self):
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

        def sample(self):
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

        def seed(self, seed=None):
            seeds = super().seed(seed)
            for i, space in enumerate(self.spaces.values()):
                seeds += space.seed(None if seed is None else int(seed) + i + 1)
            return seeds

        def sample(self):
            return {key: space.sample() for key, space in self.spaces.items()}

        def contains(self, x) -> bool:
            return (isinstance(x, collections.abc.Mapping) and set(x.keys()) == set(self.spaces.keys())
                    and all(space.contains(x[key]) for key, space in self.spaces.items()))

        def __getitem__(self, key):
            return self.spaces[key]

        def __setitem__(self, key, space):
            self.spaces[key] = space

        def __iter__(self):
            return iter(self.spaces)

        def __len__(self):
            return len(self.spaces)

        def __repr__(self):
            return "Dict(" + ", ".join(f"{k!r}: {s}" for k, s in self.spaces.items()) + ")"

        def __eq__(self, other):
            return isinstance(other, Dict) and self.spaces == other.spaces
