"""PPO (Schulman et al. 2017) on roar_rl.VectorEnv with PyTorch, CPU.

The actor is the network rl_train and policy_driver use (the flattened observation normalised by the
policy format's mean and spread, tanh hidden layers, two tanh outputs: steer and pedal), so a trained
actor exports to a policy file that policy_driver drives a car with in a ROS race. The critic is its own
network. Exploration is Gaussian noise around the actor's output, clipped to [-1, 1].
"""
import dataclasses
import time
import typing

import numpy as np
import torch
from torch import nn

import roar_rl_core

from .vector_env import VectorEnv, _options_path


def flatten(tree) -> np.ndarray:
    """A batched observation dict as one (envs x numbers) array, keys sorted at every level (Gymnasium's
    flatten order, and the policy format's)."""
    if isinstance(tree, dict):
        return np.concatenate([flatten(tree[k]) for k in sorted(tree)], axis=1)
    array = np.asarray(tree, dtype=np.float32)
    return array.reshape(array.shape[0], -1)


def to_action(steer_pedal: np.ndarray) -> dict:
    """(envs x 2) steer and pedal in [-1, 1] as the environment's action dict."""
    n = steer_pedal.shape[0]
    pedal = steer_pedal[:, 1:2]
    return {"throttle": np.maximum(pedal, 0.0), "brake": np.maximum(-pedal, 0.0), "steer": steer_pedal[:, 0:1],
            "hand_brake": np.zeros((n, 1)), "reverse": np.zeros((n, 1))}


@dataclasses.dataclass
class PpoOptions:
    map_name: str = "roar_sprint"
    env_options: str = "state"
    num_envs: int = 8
    num_threads: typing.Optional[int] = None
    rollout_steps: int = 128           # per environment, per iteration
    epochs: int = 4
    minibatch: int = 256
    learning_rate: float = 3e-4
    gamma: float = 0.99
    gae_lambda: float = 0.95
    clip: float = 0.2
    value_coef: float = 0.5
    entropy_coef: float = 0.0
    max_grad_norm: float = 0.5
    reward_scale: float = 0.01         # the environment pays 20 per metre
    hidden: int = 32                   # the actor's hidden layer (the policy format's)
    initial_log_std: float = -0.7
    seed: int = 0


class ActorCritic(nn.Module):
    def __init__(self, mean: np.ndarray, spread: np.ndarray, hidden: int, initial_log_std: float):
        super().__init__()
        inputs = len(mean)
        self.register_buffer("mean", torch.as_tensor(mean, dtype=torch.float32))
        self.register_buffer("spread", torch.as_tensor(spread, dtype=torch.float32))
        self.hidden = nn.Linear(inputs, hidden)
        self.out = nn.Linear(hidden, 2)
        nn.init.zeros_(self.out.weight)  # start by driving straight with no pedal
        nn.init.zeros_(self.out.bias)
        self.log_std = nn.Parameter(torch.full((2,), float(initial_log_std)))
        self.critic = nn.Sequential(nn.Linear(inputs, 64), nn.Tanh(), nn.Linear(64, 64), nn.Tanh(), nn.Linear(64, 1))

    def normalised(self, obs: torch.Tensor) -> torch.Tensor:
        return (obs - self.mean) / self.spread

    def actor_mean(self, obs: torch.Tensor) -> torch.Tensor:
        return torch.tanh(self.out(torch.tanh(self.hidden(self.normalised(obs)))))

    def value(self, obs: torch.Tensor) -> torch.Tensor:
        return self.critic(self.normalised(obs)).squeeze(-1)

    def distribution(self, obs: torch.Tensor) -> torch.distributions.Normal:
        return torch.distributions.Normal(self.actor_mean(obs), self.log_std.exp())

    def policy_params(self) -> typing.List[float]:
        """The actor's weights in the policy format's order: per layer weights (out x in), then biases."""
        out = []
        for layer in (self.hidden, self.out):
            out += layer.weight.detach().numpy().astype(np.float32).reshape(-1).tolist()
            out += layer.bias.detach().numpy().astype(np.float32).tolist()
        return out


@dataclasses.dataclass
class Progress:
    iteration: int
    steps: int
    seconds: float
    steps_per_s: float
    episodes: int
    mean_return: float       # of the episodes ended in the last iterations
    mean_step_reward: float  # of this iteration's steps
    best_lap: float          # s, fastest lap completed so far (0: none)


class Ppo:
    def __init__(self, options: PpoOptions):
        self.options = options
        torch.manual_seed(options.seed)
        self.rng = np.random.default_rng(options.seed)
        self.env = VectorEnv(options.map_name, options.env_options, num_envs=options.num_envs,
                             num_threads=options.num_threads, seed=options.seed)
        self.options_path = _options_path(options.env_options)
        mean, spread, _ = roar_rl_core.mlp_normalisation(self.options_path, [options.hidden])
        self.model = ActorCritic(np.array(mean), np.array(spread), options.hidden, options.initial_log_std)
        self.optimiser = torch.optim.Adam(self.model.parameters(), lr=options.learning_rate)
        obs, _ = self.env.reset(seed=options.seed)
        self.obs = flatten(obs)
        self.returns = np.zeros(options.num_envs)
        self.episode_returns: typing.List[float] = []
        self.best_lap = 0.0
        self.steps = 0
        self.iteration = 0
        self.started = time.perf_counter()

    def _collect(self):
        o, n, T = self.options, self.options.num_envs, self.options.rollout_steps
        obs = np.zeros((T, n, self.obs.shape[1]), np.float32)
        actions = np.zeros((T, n, 2), np.float32)
        log_probs = np.zeros((T, n), np.float32)
        rewards = np.zeros((T, n), np.float32)
        dones = np.zeros((T, n), np.float32)
        values = np.zeros((T + 1, n), np.float32)
        bootstrap = np.zeros((T, n), np.float32)  # value of a truncated episode's final observation
        for t in range(T):
            obs[t] = self.obs
            with torch.no_grad():
                tensor = torch.as_tensor(self.obs)
                dist = self.model.distribution(tensor)
                action = dist.sample()
                log_probs[t] = dist.log_prob(action).sum(-1).numpy()
                values[t] = self.model.value(tensor).numpy()
            actions[t] = action.numpy()
            next_obs, reward, terminated, truncated, infos = self.env.step(to_action(np.clip(actions[t], -1.0, 1.0)))
            rewards[t] = reward * o.reward_scale
            done = terminated | truncated
            dones[t] = done
            self.returns += reward
            laps_done = infos["last_lap_time"] > 0
            for i in np.nonzero(laps_done)[0]:
                lap = float(infos["last_lap_time"][i])
                if self.best_lap == 0.0 or lap < self.best_lap:
                    self.best_lap = lap
            if np.any(truncated & ~terminated):
                final = flatten(infos["final_observation"])
                with torch.no_grad():
                    v = self.model.value(torch.as_tensor(final)).numpy()
                bootstrap[t] = np.where(truncated & ~terminated, v, 0.0)
            for i in np.nonzero(done)[0]:
                self.episode_returns.append(float(self.returns[i]))
                self.returns[i] = 0.0
            self.obs = flatten(next_obs)
        with torch.no_grad():
            values[T] = self.model.value(torch.as_tensor(self.obs)).numpy()
        advantages = np.zeros((T, n), np.float32)
        gae = np.zeros(n, np.float32)
        for t in reversed(range(T)):
            next_value = np.where(dones[t] > 0, bootstrap[t] * 1.0, values[t + 1])
            delta = rewards[t] + o.gamma * next_value - values[t]
            gae = delta + o.gamma * o.gae_lambda * (1.0 - dones[t]) * gae
            advantages[t] = gae
        returns = advantages + values[:T]
        self.steps += T * n
        return (obs.reshape(T * n, -1), actions.reshape(T * n, 2), log_probs.reshape(-1), advantages.reshape(-1),
                returns.reshape(-1), float(rewards.mean() / o.reward_scale))

    def _update(self, obs, actions, old_log_probs, advantages, returns):
        o = self.options
        obs_t, act_t = torch.as_tensor(obs), torch.as_tensor(actions)
        old_t, ret_t = torch.as_tensor(old_log_probs), torch.as_tensor(returns)
        adv_t = torch.as_tensor((advantages - advantages.mean()) / (advantages.std() + 1e-8))
        count = len(obs)
        for _ in range(o.epochs):
            order = torch.as_tensor(self.rng.permutation(count))
            for start in range(0, count, o.minibatch):
                idx = order[start:start + o.minibatch]
                dist = self.model.distribution(obs_t[idx])
                log_prob = dist.log_prob(act_t[idx]).sum(-1)
                ratio = (log_prob - old_t[idx]).exp()
                policy_loss = -torch.min(ratio * adv_t[idx], ratio.clamp(1 - o.clip, 1 + o.clip) * adv_t[idx]).mean()
                value_loss = (self.model.value(obs_t[idx]) - ret_t[idx]).pow(2).mean()
                loss = policy_loss + o.value_coef * value_loss - o.entropy_coef * dist.entropy().sum(-1).mean()
                self.optimiser.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(self.model.parameters(), o.max_grad_norm)
                self.optimiser.step()

    def iterate(self) -> Progress:
        obs, actions, log_probs, advantages, returns, step_reward = self._collect()
        self._update(obs, actions, log_probs, advantages, returns)
        self.iteration += 1
        seconds = time.perf_counter() - self.started
        recent = self.episode_returns[-20:]
        return Progress(self.iteration, self.steps, seconds, self.steps / max(seconds, 1e-9), len(self.episode_returns),
                        float(np.mean(recent)) if recent else 0.0, step_reward, self.best_lap)

    def export(self, path: str):
        """The actor as a policy file policy_driver drives with (rl_train's format)."""
        roar_rl_core.write_mlp_policy(path, self.options_path, [self.options.hidden], self.model.policy_params())
