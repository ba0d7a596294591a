#!/usr/bin/python3
"""Learns to race a circuit with PPO (PyTorch, CPU) on roar_rl.VectorEnv, within a time budget: a progress
line per iteration (steps/s, episodes, return, best lap), then a learning curve (learning_curve.png), the
policy in rl_train's format (policy.yaml: `race.launch policy:=<it>` races it), and the fastest clean
lap the policy drives from the grid.

    rosrun roar_ros roar_rl_ppo.py --map roar_sprint --minutes 15 [--output DIR] [--envs 8] [--threads 2]
"""
import argparse
import datetime
import os
import sys
import tempfile

import numpy as np
import torch
import yaml

from roar_rl.ppo import Ppo, PpoOptions, flatten, to_action
from roar_rl.vector_env import ROOT, VectorEnv


def evaluate_from_grid(ppo: Ppo, laps: int = 2, max_time: float = 300.0) -> dict:
    """The policy without exploration noise, from the pole position: its lap times until it stops."""
    with open(ppo.options_path) as f:
        options = yaml.safe_load(f)
    options["spawn"] = "grid"
    options.setdefault("termination", {})["time_limit"] = max_time
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(options, f)
        path = f.name
    env = VectorEnv(ppo.options.map_name, path, num_envs=1, num_threads=1)
    obs, _ = env.reset(seed=0)
    lap_times, ended = [], "time limit"
    for _ in range(int(max_time / 0.05) + 10):
        with torch.no_grad():
            action = ppo.model.actor_mean(torch.as_tensor(flatten(obs))).numpy()
        obs, _, terminated, truncated, infos = env.step(to_action(action))
        if infos["laps"][0] > len(lap_times):
            lap_times.append(float(infos["last_lap_time"][0]))
        if terminated[0] or truncated[0] or len(lap_times) >= laps:
            if infos["collided"][0]:
                ended = "collision"
            elif infos["off_track"][0]:
                ended = "off track"
            elif len(lap_times) >= laps:
                ended = "laps done"
            break
    os.unlink(path)
    return {"laps": lap_times, "ended": ended, "best_clean_lap": min(lap_times) if lap_times else None}


def learning_curve_figure(curve, title: str):
    """The mean return over wall minutes and, once an episode has finished a lap, the best lap on a second
    axis; the legend sits below the axes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    minutes = [p.seconds / 60 for p in curve]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(minutes, [p.mean_return for p in curve], color="tab:blue", label="mean episode return (last 20)")
    ax.set_xlabel("wall minutes")
    ax.set_ylabel("episode return")
    lines, labels = ax.get_legend_handles_labels()
    laps = [(m, p.best_lap) for m, p in zip(minutes, curve) if p.best_lap > 0]
    if laps:
        ax2 = ax.twinx()
        ax2.plot(*zip(*laps), color="tab:red", label="best lap so far (s)")
        ax2.set_ylabel("best lap (s)")
        lines += ax2.get_legend_handles_labels()[0]
        labels += ax2.get_legend_handles_labels()[1]
    else:
        # No lap axis with nothing on it: say that no episode has finished a lap yet.
        lines.append(plt.Line2D([], [], linestyle="none"))
        labels.append("no lap completed yet")
    # Below the axes: inside, some part of a curve is always under it.
    ax.legend(lines, labels, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def plot(curve, path: str, title: str):
    import matplotlib.pyplot as plt

    fig = learning_curve_figure(curve, title)
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default="roar_sprint")
    parser.add_argument("--env", default="state", help="config/rl/<name>.yaml or a path")
    parser.add_argument("--minutes", type=float, default=15.0)
    parser.add_argument("--envs", type=int, default=8)
    parser.add_argument("--threads", type=int, default=None)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--output", default=None, help="default: output/ppo_<map>_<date>/")
    args = parser.parse_args([a for a in (argv if argv is not None else sys.argv[1:]) if ":=" not in a])
    if args.minutes <= 0:
        parser.error(f"--minutes must be positive, got {args.minutes}")
    out = args.output or str(ROOT / "output" / f"ppo_{args.map}_{datetime.datetime.now():%Y%m%d_%H%M%S}")
    os.makedirs(out, exist_ok=True)
    torch.set_num_threads(1)  # the environments have the other cores
    ppo = Ppo(PpoOptions(map_name=args.map, env_options=args.env, num_envs=args.envs, num_threads=args.threads,
                         seed=args.seed))
    curve = []
    while True:
        p = ppo.iterate()
        curve.append(p)
        print(f"{p.seconds / 60:5.1f} min  {p.steps:9d} steps  {p.steps_per_s:6.0f} steps/s  {p.episodes:6d} episodes  "
              f"return {p.mean_return:8.1f}  best lap {p.best_lap:6.2f} s" if p.best_lap else
              f"{p.seconds / 60:5.1f} min  {p.steps:9d} steps  {p.steps_per_s:6.0f} steps/s  {p.episodes:6d} episodes  "
              f"return {p.mean_return:8.1f}  best lap -", flush=True)
        if p.seconds > args.minutes * 60:
            break
    ppo.export(os.path.join(out, "policy.yaml"))
    with open(os.path.join(out, "curve.csv"), "w") as f:
        f.write("seconds,steps,episodes,mean_return,mean_step_reward,best_lap_s\n")
        for p in curve:
            f.write(f"{p.seconds:.3f},{p.steps},{p.episodes},{p.mean_return:.3f},{p.mean_step_reward:.4f},{p.best_lap:.3f}\n")
    plot(curve, os.path.join(out, "learning_curve.png"), f"PPO on {args.map}, {args.envs} environments")
    grid = evaluate_from_grid(ppo)
    summary = {"map": args.map, "minutes": round(curve[-1].seconds / 60, 2), "steps": curve[-1].steps,
               "episodes": curve[-1].episodes, "best_lap_in_training_s": curve[-1].best_lap or None,
               "from_the_grid": grid}
    with open(os.path.join(out, "summary.yaml"), "w") as f:
        yaml.safe_dump(summary, f, sort_keys=False)
    print(f"from the grid: laps {grid['laps']} ({grid['ended']}); policy, learning_curve.png and summary.yaml in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
