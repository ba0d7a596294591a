"""The PPO agent on roar_rl: a short run's reward rises, and its actor exports to the policy file format
that rl_train writes and policy_driver drives with, giving the same outputs there."""
import numpy as np
import pytest
import torch

import roar_rl_core
from roar_rl.ppo import Ppo, PpoOptions, flatten


@pytest.fixture(scope="module")
def trained():
    torch.set_num_threads(1)
    ppo = Ppo(PpoOptions(num_envs=8, num_threads=2, seed=1))
    progress = [ppo.iterate() for _ in range(24)]
    return ppo, progress


def test_a_short_run_learns_to_make_progress(trained):
    _, progress = trained
    first = np.mean([p.mean_step_reward for p in progress[:3]])
    last = np.mean([p.mean_step_reward for p in progress[-3:]])
    assert last > first + 2.0, f"reward per step {first:.2f} -> {last:.2f}"
    assert progress[-1].episodes > 20 and progress[-1].steps == 24 * 8 * 128


def test_the_actor_exports_to_the_policy_format(trained, tmp_path):
    ppo, _ = trained
    path = str(tmp_path / "policy.yaml")
    ppo.export(path)
    obs, _ = ppo.env.reset(seed=5)
    flat = flatten(obs)
    with torch.no_grad():
        expected = ppo.model.actor_mean(torch.as_tensor(flat)).numpy()
    for i in range(len(flat)):
        got = roar_rl_core.mlp_policy_outputs(path, flat[i].tolist())
        assert np.allclose(got, expected[i], atol=1e-5), f"environment {i}: C++ {got}, PyTorch {expected[i]}"
    with pytest.raises(ValueError, match="parameters"):
        roar_rl_core.write_mlp_policy(path, ppo.options_path, [32], [0.0] * 3)
