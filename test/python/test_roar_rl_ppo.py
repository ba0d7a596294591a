"""The PPO agent on roar_rl: a short run's reward rises, and its actor exports to the policy file format
that rl_train writes and policy_driver drives with, giving the same outputs there."""
import importlib.util
import os
import types

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


def load_ppo_script():
    path = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "roar_rl_ppo.py")
    spec = importlib.util.spec_from_file_location("roar_rl_ppo_script", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_learning_curve_has_a_lap_axis_only_with_laps_on_it():
    script = load_ppo_script()
    point = lambda seconds, best_lap: types.SimpleNamespace(seconds=seconds, mean_return=seconds, best_lap=best_lap)
    without = script.learning_curve_figure([point(60.0 * k, 0.0) for k in range(5)], "no laps")
    assert len(without.axes) == 1, "no empty best-lap axis"
    assert "no lap completed yet" in [t.get_text() for t in without.axes[0].get_legend().get_texts()]
    with_laps = script.learning_curve_figure([point(60.0 * k, 80.0 - k if k > 1 else 0.0) for k in range(5)], "laps")
    assert len(with_laps.axes) == 2 and with_laps.axes[1].get_ylabel() == "best lap (s)"
    assert len(with_laps.axes[1].get_lines()[0].get_xdata()) == 3
