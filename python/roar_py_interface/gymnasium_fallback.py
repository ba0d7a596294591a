"""``import gymnasium`` for ROAR programs on a machine without gymnasium (Debian packages none).

ROAR_PY, its competition starter kit and ROAR_PY_RL all ``import gymnasium as gym`` and use ``gym.Space``,
``gym.spaces.*``, ``gym.spaces.flatten``/``unflatten``, ``gym.Env`` and gymnasium's wrappers
(``gym.Wrapper``, ``ActionWrapper``, ``ObservationWrapper``, ``RewardWrapper``, ``gym.wrappers.*``). When gymnasium is not importable,
importing roar_py_interface registers this module as ``gymnasium`` (with ``gymnasium.spaces`` and its
submodules) so that those programs run unchanged; when gymnasium is installed nothing is registered and
the real one is used. A program that imports gymnasium before roar_py_interface needs the real one.
"""
import sys
import types
import typing

import numpy as np

from . import spaces as _spaces

__version__ = "0.0-roar_py_interface"


class Env:
    """gymnasium.Env's contract: step, reset (seeding np_random), render, close, the spaces and metadata."""

    metadata: typing.Dict[str, typing.Any] = {"render_modes": []}
    render_mode: typing.Optional[str] = None
    reward_range = (-float("inf"), float("inf"))
    spec = None
    action_space: _spaces.Space
    observation_space: _spaces.Space
    _np_random: typing.Optional[np.random.Generator] = None

    def step(self, action):
        raise NotImplementedError

    def reset(self, *, seed: typing.Optional[int] = None, options: typing.Optional[dict] = None):
        if seed is not None:
            self._np_random = np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed)))
        return None

    def render(self):
        raise NotImplementedError

    def close(self):
        pass

    @property
    def np_random(self) -> np.random.Generator:
        if self._np_random is None:
            self._np_random = np.random.Generator(np.random.PCG64(np.random.SeedSequence()))
        return self._np_random

    @np_random.setter
    def np_random(self, value: np.random.Generator):
        self._np_random = value

    @property
    def unwrapped(self) -> "Env":
        return self

    def __enter__(self):
        return self

    def __exit__(self, *args):
        self.close()
        return False

    def __str__(self):
        return f"<{type(self).__name__} instance>"


class Wrapper(Env):
    """gymnasium.Wrapper: forwards to the wrapped environment; its spaces can be set, as gymnasium's wrappers
    set them (then they are this wrapper's own)."""

    def __init__(self, env: Env):
        self.env = env
        self._action_space: typing.Optional[_spaces.Space] = None
        self._observation_space: typing.Optional[_spaces.Space] = None
        self._metadata: typing.Optional[dict] = None

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(f"accessing private attribute '{name}' is prohibited")
        return getattr(self.env, name)

    @property
    def action_space(self):
        return self.env.action_space if self._action_space is None else self._action_space

    @action_space.setter
    def action_space(self, space: _spaces.Space):
        self._action_space = space

    @property
    def observation_space(self):
        return self.env.observation_space if self._observation_space is None else self._observation_space

    @observation_space.setter
    def observation_space(self, space: _spaces.Space):
        self._observation_space = space

    @property
    def metadata(self) -> dict:
        return self.env.metadata if self._metadata is None else self._metadata

    @metadata.setter
    def metadata(self, value: dict):
        self._metadata = value

    @property
    def np_random(self) -> np.random.Generator:
        return self.env.np_random

    @np_random.setter
    def np_random(self, value: np.random.Generator):
        self.env.np_random = value

    @property
    def render_mode(self):
        return self.env.render_mode

    @property
    def spec(self):
        return self.env.spec

    @classmethod
    def class_name(cls) -> str:
        return cls.__name__

    def step(self, action):
        return self.env.step(action)

    def reset(self, **kwargs):
        return self.env.reset(**kwargs)

    def render(self):
        return self.env.render()

    def close(self):
        return self.env.close()

    @property
    def unwrapped(self) -> Env:
        return self.env.unwrapped

    def __str__(self):
        return f"<{type(self).__name__}{self.env}>"


class ObservationWrapper(Wrapper):
    """gymnasium.ObservationWrapper: every observation reset and step give passes through observation()."""

    def reset(self, **kwargs):
        obs, info = self.env.reset(**kwargs)
        return self.observation(obs), info

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        return self.observation(obs), reward, terminated, truncated, info

    def observation(self, observation):
        raise NotImplementedError


class RewardWrapper(Wrapper):
    """gymnasium.RewardWrapper: every reward step gives passes through reward()."""

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        return obs, self.reward(reward), terminated, truncated, info

    def reward(self, reward):
        raise NotImplementedError


class ActionWrapper(Wrapper):
    """gymnasium.ActionWrapper: every action passes through action() before the wrapped step."""

    def step(self, action):
        return self.env.step(self.action(action))

    def action(self, action):
        raise NotImplementedError

    def reverse_action(self, action):
        raise NotImplementedError


Space = _spaces.Space
spaces = None  # gymnasium.spaces once install() has run


def install() -> bool:
    """Registers this module as ``gymnasium`` when no gymnasium is importable; True if it did."""
    if _spaces.USING_GYMNASIUM or "gymnasium" in sys.modules:
        return False
    spaces_module = types.ModuleType("gymnasium.spaces", "gymnasium.spaces (roar_py_interface's fallback)")
    for name in ("Space", "Box", "Discrete", "MultiBinary", "Tuple", "Dict", "flatten", "unflatten", "flatdim",
                 "flatten_space"):
        setattr(spaces_module, name, getattr(_spaces, name))
    utils_module = types.ModuleType("gymnasium.spaces.utils")
    for name in ("flatten", "unflatten", "flatdim", "flatten_space"):
        setattr(utils_module, name, getattr(_spaces, name))
    spaces_module.utils = utils_module
    this = sys.modules[__name__]
    this.spaces = spaces_module
    from . import gymnasium_fallback_wrappers as wrappers_module
    this.wrappers = wrappers_module
    sys.modules["gymnasium"] = this
    sys.modules["gymnasium.wrappers"] = wrappers_module
    sys.modules["gymnasium.spaces"] = spaces_module
    sys.modules["gymnasium.spaces.utils"] = utils_module
    sys.modules["gymnasium.core"] = this
    for cls in (_spaces.Space, _spaces.Box, _spaces.Discrete, _spaces.MultiBinary, _spaces.Tuple, _spaces.Dict):
        sys.modules.setdefault(cls.__module__, spaces_module)
    return True
