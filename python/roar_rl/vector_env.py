"""Gymnasium's vector API over the C++ VectorEnv (roar_rl_core)."""
import numbers
import os
import typing

import numpy as np

from roar_py_interface import spaces

import roar_core
import roar_rl_core as _core

from roar_paths import layout, package_root

ROOT = package_root()
FOLDERS = layout()


def available_maps() -> typing.List[str]:
    return list(roar_core.list_maps(str(FOLDERS["maps"])))


def available_env_options() -> typing.List[str]:
    return sorted(p.stem for p in FOLDERS["rl"].glob("*.yaml"))


def _map_folder(map_name: str) -> str:
    try:
        return roar_core.resolve_map_folder(str(map_name), str(FOLDERS["maps"]))
    except roar_core.MapError as error:
        raise ValueError(f"VectorEnv: map_name: {error}") from None


def _options_path(env_options: str) -> str:
    if os.path.isfile(env_options):
        return env_options
    path = FOLDERS["rl"] / f"{env_options}.yaml"
    if not path.exists():
        raise ValueError(f"VectorEnv: env_options '{env_options}' is neither a file nor one of {available_env_options()}")
    return str(path)


def _whole(name: str, value) -> int:
    """A count given as a whole number (1.5 environments is an error, not one)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not float(value).is_integer():
        raise ValueError(f"VectorEnv: {name} must be a whole number, got {value!r}")
    return int(value)


def space_of(description: dict) -> spaces.Space:
    """A space from the C++ side's description of it."""
    kind = description["kind"]
    if kind == "Dict":
        return spaces.Dict({k: space_of(v) for k, v in description["spaces"].items()})
    if kind == "Discrete":
        return spaces.Discrete(int(description["n"]), start=int(description["start"]))
    if kind == "MultiBinary":
        return spaces.MultiBinary(int(description["shape"][0]))
    shape = tuple(description["shape"])
    low = np.asarray(description["low"], dtype=np.float64).reshape(shape)
    high = np.asarray(description["high"], dtype=np.float64).reshape(shape)
    return spaces.Box(low=low, high=high, shape=shape, dtype=np.dtype(description["dtype"]))


def batch_space(space: spaces.Space, n: int) -> spaces.Space:
    """gymnasium.vector.utils.batch_space for Box, MultiBinary and Dict (Discrete as an int64 Box)."""
    if isinstance(space, spaces.Dict):
        return spaces.Dict({k: batch_space(s, n) for k, s in space.spaces.items()})
    if isinstance(space, spaces.Discrete):
        return spaces.Box(low=int(space.start), high=int(space.start + space.n - 1), shape=(n,), dtype=np.int64)
    if isinstance(space, spaces.MultiBinary):
        return spaces.MultiBinary((n,) + tuple(space.shape))
    return spaces.Box(low=np.broadcast_to(space.low, (n,) + space.shape), high=np.broadcast_to(space.high, (n,) + space.shape),
                      shape=(n,) + space.shape, dtype=space.dtype)


class VectorEnv:
    """num_envs racing environments of one map, options (a name in config/rl or a YAML path) and car model,
    stepped on num_threads threads (the calling one included) with the GIL released.

    Gymnasium's vector API: reset(seed) -> (observations, infos); step(actions) -> (observations, rewards,
    terminations, truncations, infos). Observations, rewards and infos are NumPy arrays with a leading
    environment axis, written in place: they are overwritten by the next step (copy what you keep). An
    environment whose episode ended starts its next at once (autoreset): its row then holds the new
    episode's first observation, infos["final_observation"] the last one of the ended episode (same layout,
    valid where infos["_final_observation"] is True). Environment i is reset with seed + i.

    With batch_size (EnvPool's asynchronous batching): send(actions, env_ids) queues one action per listed
    environment and recv() returns the first batch_size environments to be done, as (observations, rewards,
    terminations, truncations, infos) of batch_size rows, infos["env_id"] saying whose each row is; send the
    next actions to those ids. No thread waits for the slowest environment. A batch's arrays stay as they
    are until the next recv(), even once its environments are sent again (batches go round a ring of
    buffers, each row written by the thread that stepped its environment). reset() resets every
    environment and returns their first observations by id; step() is send to all then recv (batch_size
    must then be num_envs; rows come in the order the environments were done, see infos["env_id"])."""

    def __init__(self, map_name: str = "roar_sprint", env_options: str = "state", num_envs: int = 4,
                 num_threads: typing.Optional[int] = None, model: str = roar_core.DEFAULT_MODEL, seed: int = 0,
                 batch_size: typing.Optional[int] = None):
        num_envs = _whole("num_envs", num_envs)
        threads = _whole("num_threads", num_threads) if num_threads is not None else min(num_envs, os.cpu_count() or 1)
        where = (_map_folder(map_name), _options_path(env_options), model, str(FOLDERS["urdf"]),
                 str(FOLDERS["vehicles"]), num_envs, threads)
        self.batch_size = None if batch_size is None else _whole("batch_size", batch_size)
        self._core = _core.VectorEnv(*where) if batch_size is None else _core.AsyncVectorEnv(*where, int(batch_size))
        self.num_envs = self._core.num_envs
        self.num_threads = threads
        self.single_action_space = space_of(self._core.action_space())
        self.single_observation_space = space_of(self._core.observation_space())
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._seed = int(seed)
        self._started = False
        self.closed = False

    def _open_core(self):
        if self.closed:
            raise RuntimeError("VectorEnv is closed")
        return self._core

    def reset(self, seed: typing.Optional[int] = None, options: typing.Optional[dict] = None):
        self._open_core()
        if seed is not None:
            self._seed = int(seed)
        observations, infos = self._core.reset(self._seed)
        self._started = True
        return observations, infos

    def step(self, actions):
        self._open_core()
        if not self._started:
            raise RuntimeError("VectorEnv.step before reset")
        if self.batch_size is not None:
            if self.batch_size != self.num_envs:
                raise RuntimeError(f"VectorEnv.step needs batch_size = num_envs ({self.num_envs}), not "
                                   f"{self.batch_size}: use send() and recv()")
            self.send(actions, np.arange(self.num_envs))
            return self.recv()
        observations, rewards, terminations, truncations, infos, final, mask = self._core.step(actions)
        infos["final_observation"] = final  # infos is the module's own dict, filled in place like the arrays
        infos["_final_observation"] = mask
        return observations, rewards, terminations, truncations, infos

    def send(self, actions, env_ids) -> None:
        """Asynchronous mode: one action per environment of env_ids (a row each, in that order)."""
        self._open_core()
        if self.batch_size is None:
            raise RuntimeError("VectorEnv.send needs batch_size (asynchronous mode)")
        if not self._started:
            raise RuntimeError("VectorEnv.send before reset")
        self._core.send(actions, np.asarray(env_ids, dtype=np.int64))

    def recv(self):
        """Asynchronous mode: the first batch_size environments to be done; infos["env_id"] says whose."""
        self._open_core()
        if self.batch_size is None:
            raise RuntimeError("VectorEnv.recv needs batch_size (asynchronous mode)")
        observations, rewards, terminations, truncations, infos, final, mask, env_ids = self._core.recv()
        infos["final_observation"] = final
        infos["_final_observation"] = mask
        infos["env_id"] = env_ids
        return observations, rewards, terminations, truncations, infos

    def close(self):
        """Frees the environments (their threads and buffers); any later call raises RuntimeError."""
        self.closed = True
        self._core = None
