"""roar_rl: the C++ vectorised racing environment from Python (no ROS): spaces, determinism, autoreset,
refused actions."""
import threading
import time

import numpy as np
import pytest

import roar_rl


@pytest.fixture(scope="module")
def envs():
    return roar_rl.VectorEnv("roar_sprint", "state", num_envs=4, num_threads=2)


def row(tree, i):
    return {k: row(v, i) for k, v in tree.items()} if isinstance(tree, dict) else np.array(tree[i])


def copy(tree):
    return {k: copy(v) for k, v in tree.items()} if isinstance(tree, dict) else np.array(tree)


def flat(tree, prefix=""):
    if isinstance(tree, dict):
        out = {}
        for k, v in tree.items():
            out.update(flat(v, prefix + "/" + k))
        return out
    return {prefix: tree}


def full_throttle(n, steer=0.0):
    return {"throttle": np.ones((n, 1)), "steer": np.full((n, 1), steer), "brake": np.zeros((n, 1)),
            "hand_brake": np.zeros((n, 1)), "reverse": np.zeros((n, 1), np.int8)}


def test_spaces_and_shapes(envs):
    assert envs.num_envs == 4
    assert list(envs.single_action_space.keys()) == ["brake", "hand_brake", "reverse", "steer", "throttle"]
    assert envs.single_action_space["steer"].low.tolist() == [-1.0]
    obs, infos = envs.reset(seed=3)
    for i in range(4):
        assert envs.single_observation_space.contains(row(obs, i)), f"environment {i}'s observation"
    assert envs.observation_space.contains(obs)
    assert infos["speed"].shape == (4,) and np.all(infos["episode_steps"] == 0)
    sample = envs.action_space.sample()
    obs, rewards, terminations, truncations, infos = envs.step(sample)
    assert rewards.shape == (4,) and terminations.dtype == bool and truncations.shape == (4,)
    assert envs.observation_space.contains(obs)
    assert "final_observation" in infos and infos["_final_observation"].shape == (4,)


def test_the_same_seed_gives_the_same_episodes_on_any_number_of_threads():
    def run(num_envs, threads):
        env = roar_rl.VectorEnv("roar_sprint", "state", num_envs=num_envs, num_threads=threads)
        obs, _ = env.reset(seed=11)
        history = [copy(obs)]
        for k in range(60):
            obs, rewards, *_ = env.step(full_throttle(num_envs, steer=0.2 * np.sin(0.1 * k)))
            history.append((copy(obs), np.array(rewards)))
        return history

    one = run(1, 1)
    four = run(4, 2)
    again = run(4, 2)
    for a, b, c in zip(one[1:], four[1:], again[1:]):
        fa, fb, fc = flat(a[0]), flat(b[0]), flat(c[0])
        assert len(fa) == 9
        for key in fa:
            assert np.array_equal(fa[key][0], fb[key][0]), "environment 0 of four is the single environment"
            assert np.array_equal(fb[key], fc[key]), "bit for bit, run to run"
        assert a[1][0] == b[1][0] and np.array_equal(b[1], c[1])


def test_autoreset_keeps_the_final_observation():
    env = roar_rl.VectorEnv("roar_sprint", "state", num_envs=2, num_threads=1)
    env.reset(seed=5)
    ended = None
    for _ in range(600):  # full throttle and full lock: into the barrier or off the track
        obs, rewards, terminations, truncations, infos = env.step(full_throttle(2, steer=1.0))
        if terminations[0] or truncations[0]:
            ended = (copy(obs), copy(infos))
            break
    assert ended is not None, "the episode ended"
    obs, infos = ended
    assert infos["_final_observation"][0]
    assert infos["episode_steps"][0] > 10, "the info is the ended episode's (Gymnasium's)"
    assert obs["speed"][0, 0] < 0.5, "the row holds the new episode's first observation: the car at rest"
    final = row(infos["final_observation"], 0)
    assert final["speed"][0] > obs["speed"][0, 0] + 1.0, "the final observation is the old episode's, still moving"
    assert env.single_observation_space.contains(final)


def test_bad_actions_and_arguments_are_named(envs):
    envs.reset(seed=1)
    bad = full_throttle(4)
    bad["steer"][2, 0] = 1.5
    with pytest.raises(ValueError, match=r"actions\[2\]\['steer'\]\[0\] = 1.5 is outside"):
        envs.step(bad)
    missing = full_throttle(4)
    del missing["brake"]
    with pytest.raises(KeyError, match=r"actions\['brake'\] is missing"):
        envs.step(missing)
    with pytest.raises(ValueError, match=r"actions\['throttle'\] has shape \(3, 1\), must be \(4, 1\)"):
        envs.step({**full_throttle(4), "throttle": np.ones((3, 1))})
    with pytest.raises(ValueError, match=r"actions\['throttle'\] has shape \(4, 1, 1\), must be \(4, 1\)"):
        envs.step({**full_throttle(4), "throttle": np.ones((4, 1, 1))})
    with pytest.raises(KeyError, match=r"actions has no entry 'steerr' \(did you mean 'steer'\?\)"):
        envs.step({**full_throttle(4), "steerr": np.zeros((4, 1))})
    envs.step({**full_throttle(4), "throttle": np.ones(4)})  # one number a row: (4,) is (4, 1)
    nan = full_throttle(4)
    nan["throttle"][0, 0] = np.nan
    with pytest.raises(ValueError, match=r"actions\[0\]\['throttle'\]"):
        envs.step(nan)
    with pytest.raises(ValueError, match="roar_sprint"):
        roar_rl.VectorEnv("no_such_map", "state", num_envs=1)
    with pytest.raises(ValueError, match="state"):
        roar_rl.VectorEnv("roar_sprint", "no_such_options", num_envs=1)
    with pytest.raises(ValueError, match="num_envs"):
        roar_rl.VectorEnv("roar_sprint", "state", num_envs=0)
    with pytest.raises(ValueError, match="num_envs must be a whole number, got 1.5"):
        roar_rl.VectorEnv("roar_sprint", "state", num_envs=1.5)


def test_a_closed_env_refuses_every_call():
    env = roar_rl.VectorEnv("roar_sprint", "state", num_envs=1)
    env.reset(seed=0)
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.reset(seed=0)
    with pytest.raises(RuntimeError, match="closed"):
        env.step(full_throttle(1))


@pytest.mark.parametrize("batch_size", [None, 2])
def test_two_threads_stepping_one_env_get_an_error_not_a_crash(batch_size):
    env = roar_rl.VectorEnv("roar_sprint", "state", num_envs=2, num_threads=2, batch_size=batch_size)
    env.reset(seed=0)
    errors, steps = [], [0]

    def stepper():
        for _ in range(300):
            try:
                env.step(full_throttle(2))
                steps[0] += 1
            except RuntimeError as error:
                errors.append(str(error))

    threads = [threading.Thread(target=stepper) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert steps[0] > 0
    assert all("another thread is inside this VectorEnv" in e for e in errors), errors[:3]
    assert errors, "three threads stepping one VectorEnv 900 times never met"


def test_asynchronous_batches_give_each_environment_the_same_episode():
    """EnvPool's way: recv() returns the first batch_size environments done; each environment, stepped
    whenever its batch comes back, runs the same episode as in the synchronous VectorEnv."""
    n = 4
    sync = roar_rl.VectorEnv("roar_sprint", "state", num_envs=n, num_threads=1)
    obs, _ = sync.reset(seed=5)
    expected = {i: [] for i in range(n)}
    for k in range(40):
        _, rewards, *_ = sync.step(full_throttle(n, steer=0.1))
        for i in range(n):
            expected[i].append(float(rewards[i]))

    env = roar_rl.VectorEnv("roar_sprint", "state", num_envs=n, num_threads=2, batch_size=2)
    first, _ = env.reset(seed=5)
    assert flat(first)["/speed"].shape[0] == n
    got = {i: [] for i in range(n)}
    # Every environment is sent again until each has made its 40 steps (which come back in any order: an idle
    # thread steps whichever is waiting), then the two batches in flight are drained.
    env.send(full_throttle(n, steer=0.1), np.arange(n))
    while min(len(rewards) for rewards in got.values()) < 40:
        _, rewards, terminations, truncations, infos = env.recv()
        ids = np.array(infos["env_id"])
        assert len(ids) == 2 and len(set(ids.tolist())) == 2
        for row_index, i in enumerate(ids):
            got[int(i)].append(float(rewards[row_index]))
        env.send(full_throttle(2, steer=0.1), ids)
    for _ in range(n // 2):
        env.recv()
    assert {i: rewards[:40] for i, rewards in got.items()} == expected

    with pytest.raises(RuntimeError, match="batch_size = num_envs"):
        env.step(full_throttle(n))
    with pytest.raises(ValueError, match="batch_size must be in"):
        roar_rl.VectorEnv("roar_sprint", "state", num_envs=2, batch_size=3)
    env.send(full_throttle(1), [0])
    with pytest.raises(ValueError, match="environment 0 is still stepping"):
        env.send(full_throttle(1), [0])
    with pytest.raises(ValueError, match="batch_size 2 with 1 environment"):
        env.recv()


def test_a_batch_stays_as_it_is_while_its_environments_step_again():
    """Each result is copied into its rows by the thread that stepped it, batches going round a ring of
    buffers: a batch recv() returned is not overwritten by the results done while the learner still reads it,
    its environments sent again already, and the next batch is other environments' or later steps'."""
    n = 4
    env = roar_rl.VectorEnv("roar_sprint", "state", num_envs=n, num_threads=2, batch_size=2)
    env.reset(seed=3)
    env.send(full_throttle(n), np.arange(n))
    seen = set()
    for _ in range(12):
        obs, rewards, terminations, truncations, infos = env.recv()
        kept = [np.array(a) for a in (*flat(obs).values(), rewards, terminations, infos["env_id"], infos["speed"])]
        env.send(full_throttle(2), np.array(infos["env_id"]))
        time.sleep(0.05)  # the environments in flight, these two among them, are done meanwhile
        now = [np.array(a) for a in (*flat(obs).values(), rewards, terminations, infos["env_id"], infos["speed"])]
        assert all(np.array_equal(a, b) for a, b in zip(kept, now))
        assert np.allclose(flat(obs)["/speed"][:, 0], infos["speed"])  # each row one environment's
        seen.update(int(i) for i in infos["env_id"])
    assert seen == set(range(n))
    for _ in range(n // 2):
        env.recv()
