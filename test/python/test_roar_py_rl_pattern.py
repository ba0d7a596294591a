"""ROAR_PY_RL's environment pattern (roar_py_rl_pattern_env) on roar_sim: episodes step through with
sampled actions and with a steady one, and under its training script's wrappers."""
import os

import numpy as np
import pytest

import roar_py_ros
from roar_py_ros import connection
from roar_py_rl_pattern_env import KEPT, gym, make_env, training_env


@pytest.fixture(scope="module")
def env():
    master_was_there = connection.master_online(os.environ.get("ROS_MASTER_URI", ""))
    instance = roar_py_ros.RoarPyRosInstance(map_name="roar_sprint")
    assert instance._private is not None or master_was_there
    yield make_env(instance)
    instance.close()


def test_an_episode_driven_steadily_earns_its_distance(env):
    observation, info = env.reset(seed=1)
    assert set(observation) >= {"collision_sensor", "velocimeter", "local_velocimeter", "location", "roll_pitch_yaw",
                                "gyroscope", "carla_camera", "waypoints_information"}
    assert observation["waypoints_information"]["waypoint_10.0"][0] > 5.0, "10 m ahead is in front of the car"
    start = info["world_time"]
    total = 0.0
    for _ in range(60):
        observation, reward, terminated, truncated, info = env.step(
            {"throttle": np.array([0.6]), "steer": np.array([0.0]), "brake": np.array([0.0]),
             "hand_brake": np.array([0.0]), "reverse": np.array([0])})
        total += reward
        assert not terminated and not truncated
    assert info["world_time"] == pytest.approx(start + 3.0)
    assert total > 20.0 * 5.0, f"three seconds of 0.6 throttle (2.5 m/s^2 in CARLA's Model 3) travel more than 5 m: reward {total:.1f}"
    frame = env.render()
    assert frame.shape == (48, 96, 3) and frame.std() > 5


def test_sampled_actions_step_through_episodes_and_a_crash_ends_one(env):
    env.action_space.seed(3)
    for episode in range(2):
        env.reset(seed=episode)
        for _ in range(40):
            _, reward, terminated, _, _ = env.step(env.action_space.sample())
            assert np.isfinite(reward)
            if terminated:
                break
    env.reset()
    yaw = env.roar_py_actor.get_roll_pitch_yaw()[2]
    env.roar_py_actor.set_linear_3d_velocity(np.array([-40.0 * np.sin(yaw), 40.0 * np.cos(yaw), 0.0]))
    ended = False
    for _ in range(60):
        _, reward, terminated, _, _ = env.step({"throttle": 0.0, "steer": 0.0, "brake": 0.0, "hand_brake": 0.0,
                                                "reverse": 0})
        if terminated:
            ended = True
            assert reward < 0, "the collision's penalty"
            break
    assert ended, "sliding sideways into the barrier ends the episode"


def test_roar_py_rls_training_wrappers_step_through_episodes(env):
    """ROAR_PY_RL's training set-up: its action filter, gymnasium's FilterObservation keeping three keys, a time
    limit and episode statistics, stepped synchronously under nest_asyncio as its train_online.py does."""
    import nest_asyncio
    nest_asyncio.apply()
    kept = KEPT
    wrapped = training_env(env, max_episode_steps=30)
    assert list(wrapped.observation_space.spaces) == sorted(kept), "the wrapped space's (sorted) order"
    assert list(wrapped.action_space.spaces) == ["steer", "throttle"] and wrapped.unwrapped is env
    wrapped.action_space.seed(5)
    lengths = []
    for episode in range(2):
        observation, _ = wrapped.reset(seed=episode)
        assert set(observation) == set(kept) and observation["gyroscope"].shape == (3,)
        for _ in range(40):
            observation, reward, terminated, truncated, info = wrapped.step(wrapped.action_space.sample())
            assert set(observation) == set(kept) and np.isfinite(reward)
            if terminated or truncated:
                lengths.append(int(info["episode"]["l"]))
                break
    assert lengths and all(n <= 30 for n in lengths) and len(wrapped.length_queue) == len(lengths)
    flat = gym.wrappers.FlattenObservation(gym.wrappers.FilterObservation(env, ["gyroscope", "local_velocimeter"]))
    observation, _ = flat.reset()
    assert observation.shape == (6,) and flat.observation_space.shape == (6,)
