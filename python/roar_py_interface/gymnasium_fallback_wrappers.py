"""``gymnasium.wrappers`` for ROAR programs on a machine without gymnasium: the wrappers ROAR_PY_RL and
ROAR's training scripts use, with gymnasium's semantics (test_roar_py_interface
test_gymnasiums_wrappers_behave_as_gymnasiums; test_roar_py_rl_pattern drives ROAR_PY_RL's pattern)."""
import collections
import time
import typing

import numpy as np

from . import spaces
from .gymnasium_fallback import ObservationWrapper, Wrapper


class FilterObservation(ObservationWrapper):
    """Keeps the listed keys of a Dict observation (all when None), in the wrapped space's order."""

    def __init__(self, env, filter_keys: typing.Optional[typing.Sequence[str]] = None):
        super().__init__(env)
        wrapped = env.observation_space
        if not isinstance(wrapped, spaces.Dict):
            raise ValueError(f"FilterObservation: the observation space is a {type(wrapped).__name__}, not a Dict")
        keys = list(wrapped.spaces) if filter_keys is None else list(filter_keys)
        missing = [k for k in keys if k not in wrapped.spaces]
        if missing:
            raise ValueError(f"FilterObservation: {missing} are not keys of the observation space "
                             f"({list(wrapped.spaces)})")
        self._filter_keys = tuple(keys)
        self.observation_space = spaces.Dict([(k, s) for k, s in wrapped.spaces.items() if k in self._filter_keys])

    def observation(self, observation):
        # By key: a value not kept is never read (nor converted).
        return type(observation)((k, observation[k]) for k in observation.keys() if k in self._filter_keys)


class FlattenObservation(ObservationWrapper):
    """The observation as one flat array in the wrapped space's flattened layout."""

    def __init__(self, env):
        super().__init__(env)
        self.observation_space = spaces.flatten_space(env.observation_space)

    def observation(self, observation):
        return spaces.flatten(self.env.observation_space, observation)


class TimeLimit(Wrapper):
    """Truncates an episode after max_episode_steps steps."""

    def __init__(self, env, max_episode_steps: int):
        super().__init__(env)
        if max_episode_steps is None or int(max_episode_steps) < 1:
            raise ValueError(f"TimeLimit: max_episode_steps must be a positive integer, got {max_episode_steps!r}")
        self._max_episode_steps = int(max_episode_steps)
        self._elapsed_steps: typing.Optional[int] = None

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        self._elapsed_steps += 1
        if self._elapsed_steps >= self._max_episode_steps:
            truncated = True
        return obs, reward, terminated, truncated, info

    def reset(self, **kwargs):
        self._elapsed_steps = 0
        return self.env.reset(**kwargs)


class RecordEpisodeStatistics(Wrapper):
    """At each episode's end, info["episode"] holds its return "r", length "l" and wall time "t"; the last
    deque_size episodes' returns and lengths are in return_queue and length_queue."""

    def __init__(self, env, deque_size: int = 100):
        super().__init__(env)
        self.episode_count = 0
        self.episode_start_time = time.perf_counter()
        self.episode_returns = 0.0
        self.episode_lengths = 0
        self.return_queue: collections.deque = collections.deque(maxlen=deque_size)
        self.length_queue: collections.deque = collections.deque(maxlen=deque_size)

    def reset(self, **kwargs):
        self.episode_start_time = time.perf_counter()
        self.episode_returns = 0.0
        self.episode_lengths = 0
        return self.env.reset(**kwargs)

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        self.episode_returns += float(reward)
        self.episode_lengths += 1
        if terminated or truncated:
            if "episode" in info:
                raise ValueError("RecordEpisodeStatistics: the info already holds an 'episode' key")
            info = dict(info)
            info["episode"] = {"r": np.array(self.episode_returns), "l": np.array(self.episode_lengths),
                               "t": np.array(round(time.perf_counter() - self.episode_start_time, 6))}
            self.return_queue.append(self.episode_returns)
            self.length_queue.append(self.episode_lengths)
            self.episode_count += 1
            self.episode_returns, self.episode_lengths = 0.0, 0
            self.episode_start_time = time.perf_counter()
        return obs, reward, terminated, truncated, info


class RunningMeanStd:
    """Mean and variance of every value seen, updated a batch at a time (Chan et al.'s parallel algorithm)."""

    def __init__(self, epsilon: float = 1e-4, shape: typing.Tuple[int, ...] = ()):
        self.mean = np.zeros(shape, np.float64)
        self.var = np.ones(shape, np.float64)
        self.count = epsilon

    def update(self, batch: np.ndarray):
        batch_mean, batch_var, batch_count = np.mean(batch, axis=0), np.var(batch, axis=0), batch.shape[0]
        delta = batch_mean - self.mean
        total = self.count + batch_count
        self.mean = self.mean + delta * batch_count / total
        m2 = self.var * self.count + batch_var * batch_count + np.square(delta) * self.count * batch_count / total
        self.var = m2 / total
        self.count = total


class NormalizeObservation(ObservationWrapper):
    """Each observation less the running mean of those seen so far, over their running standard deviation."""

    def __init__(self, env, epsilon: float = 1e-8):
        super().__init__(env)
        self.obs_rms = RunningMeanStd(shape=self.observation_space.shape)
        self.epsilon = epsilon

    def observation(self, observation):
        observation = np.asarray(observation)
        self.obs_rms.update(observation[None])
        return (observation - self.obs_rms.mean) / np.sqrt(self.obs_rms.var + self.epsilon)
