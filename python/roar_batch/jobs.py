"""One cell of a batch: a time trial or race run through the C++ stack in the worker's process (no ROS master),
a trained policy's laps, or a ROAR_PY program run by the official runner's rules against a private roar_sim
of its own; a row of figures, or of why it failed."""
import ctypes
import os
import random
import signal
import socket
import subprocess
import sys
import tempfile
import time
import traceback
import typing

import yaml

import roar_paths


def race_field(cell: dict) -> typing.List[dict]:
    """A race's cars from its seed: the fastest at full pace, the others up to pace_spread slower, on a grid
    shuffled by the seed."""
    rng = random.Random(cell["seed"])
    count, spread = cell["field"]["cars"], cell["field"]["pace_spread"]
    paces = [1.0] + [round(1.0 - rng.uniform(0.0, spread), 4) for _ in range(count - 1)]
    grid = list(range(count))
    rng.shuffle(grid)
    return [{"name": f"car{k}", "grid_slot": grid[k], "pace": paces[k]} for k in range(count)]


def _time_trial(cell: dict, folders: dict) -> dict:
    import roar_core
    r = roar_core.run_time_trial(cell["map"], folders["maps"], cell["model"], folders["urdf"], folders["vehicles"],
                                 laps=cell["laps"], grip_use=cell["grip_use"], controller=cell.get("controller", {}))
    laps = r["lap_times"]
    return {"finished": r["finished"], "best_lap": r["best_lap"], "mean_lap": sum(laps) / len(laps) if laps else None,
            "promised_lap": r["promised_lap"], "barrier_contacts": r["barrier_contacts"],
            "worst_offroad": r["worst_offroad"], "max_lateral_error": r["max_lateral_error"],
            "rms_lateral_error": r["rms_lateral_error"], "sim_time": r["sim_time"]}


def scenario_race(cell: dict) -> typing.Tuple[str, str, int, typing.List[dict]]:
    """A scenario cell's map, car model, laps and cars (the scenario's unless the cell sets model or laps)."""
    import roar_core
    name = cell["scenario"]
    scenario = roar_core.load_scenario(name, str(roar_paths.package_root()))
    others = [c["name"] for c in scenario["cars"] if not c["driven"] or c["agent"]]
    if others:
        raise ValueError(f"scenario {name}: car(s) {', '.join(others)} are not the stack's to drive (undriven or "
                         "an agent's); a batch's race drives every car with the stack")
    models = {c["model"] for c in scenario["cars"]}
    if "model" not in cell and len(models) > 1:
        raise ValueError(f"scenario {name}: its cars are of {len(models)} models ({', '.join(sorted(models))}); "
                         "a batch's race is of one (set models)")
    cars = [{"name": c["name"], "grid_slot": c["spawn_point"], "pace": c["pace"], "max_speed": c["max_speed"]}
            for c in scenario["cars"]]
    return scenario["map"], cell.get("model", models.pop()), cell.get("laps", scenario["laps"]), cars


def _race(cell: dict, folders: dict) -> dict:
    import roar_core
    if "scenario" in cell:
        map_name, model, laps, cars = scenario_race(cell)
    else:
        map_name, model, laps, cars = cell["map"], cell["model"], cell["laps"], race_field(cell)
    r = roar_core.run_race(map_name, folders["maps"], model, folders["urdf"], folders["vehicles"],
                           cars, laps=laps, grip_use=cell["grip_use"],
                           overtaking=cell.get("overtaking", True), overtake=cell.get("overtake", {}),
                           controller=cell.get("controller", {}))
    cars = r["cars"]
    finishers = [c for c in cars if c["finished"]]
    return {"finished": r["finished"], "winner": cars[0]["name"] if cars else None,
            "winning_time": cars[0]["race_time"] if finishers else None,
            "mean_race_time": sum(c["race_time"] for c in finishers) / len(finishers) if finishers else None,
            "best_lap": min((t for c in cars for t in c["lap_times"]), default=None),
            "overtakes": r["overtakes"], "passes_completed": r["passes_completed"], "contacts": r["contacts"],
            "car_contacts": sum(c["car_contacts"] for c in cars),
            "barrier_contacts": sum(c["barrier_contacts"] for c in cars),
            "track_limit_violations": sum(c["track_limit_violations"] for c in cars),
            "time_in_traffic": sum(c["time_in_traffic"] for c in cars) / len(cars), "sim_time": r["sim_time"]}


def _traffic(cell: dict, folders: dict) -> dict:
    import roar_core
    t = roar_core.traffic_race(cell["map"], folders["maps"], cell["model"], folders["urdf"], folders["vehicles"],
                               cell["field"], cell["seed"], laps=cell["laps"], pace_step=cell["pace_step"],
                               overtake=cell.get("overtake", {}))
    loss = t["lap_loss"]
    return {**t, "mean_lap_loss": sum(loss) / len(loss) if loss else None, "sim_time": t["race_seconds"]}


class RoarPyRunFailed(RuntimeError):
    """The runner ended without a result: the message is its own last words."""


def _die_with_parent():
    # The runner (and through its watchdog its private roar_sim) goes when the worker running it goes, killed
    # or not: PR_SET_PDEATHSIG.
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)


def _roar_py(cell: dict, folders: dict) -> dict:
    """The competition entry driven by scripts/roar_py_competition.py (the official runner's calls and rules)
    in a process of its own, which starts a private ROS master and roar_sim (no ROS_MASTER_URI): cells run
    side by side on one machine without meeting."""
    script = roar_paths.package_root() / "scripts" / "roar_py_competition.py"
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME")}
    with tempfile.TemporaryDirectory(prefix="roar_batch_") as folder:
        out = os.path.join(folder, "result.yaml")
        cmd = [sys.executable, str(script), "--entry", cell["entry"], "--map", cell["map"], "--laps", str(cell["laps"]),
               "--camera", cell["camera"], "--max-seconds", str(cell["max_seconds"]), "--output", out]
        run = subprocess.run(cmd, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, preexec_fn=_die_with_parent)
        if not os.path.exists(out):
            said = (run.stderr.strip() or run.stdout.strip()).splitlines()[-5:]
            raise RoarPyRunFailed(f"the runner ended ({run.returncode}) without a result: " + " / ".join(said))
        with open(out) as f:
            r = yaml.safe_load(f)
    laps = r["laps"]
    return {"finished": r["finished"], "elapsed_time": r["elapsed_time"] if r["finished"] else None,
            "laps_done": len(laps), "best_lap": min(laps) if laps else None,
            "lap_times": " ".join(f"{t:.2f}" for t in laps), "respawns": len(r["respawns"]),
            "sim_time": r["elapsed_time"], "real_time_factor": r["real_time_factor"]}


def _policy(cell: dict, folders: dict) -> dict:
    """The policy file's laps from the pole position (roar_rl_core.policy_laps: rl_train's test, judged as race
    control judges a car)."""
    import roar_core
    import roar_rl_core
    from .matrix import env_file, policy_file
    r = roar_rl_core.policy_laps(policy_file(cell["policy"]), roar_core.resolve_map_folder(cell["map"], folders["maps"]),
                                 env_file(cell["env"]), cell["model"], folders["urdf"], folders["vehicles"],
                                 laps=cell["laps"], time_limit=cell["max_seconds"])
    laps = r["lap_times"]
    return {"finished": len(laps) >= cell["laps"], "clean": r["clean"], "ended": r["ended"], "laps_done": len(laps),
            "best_lap": r["best_lap"], "lap_times": " ".join(f"{t:.2f}" for t in laps), "progress": r["progress"],
            "sim_time": r["sim_time"]}


JOBS = {"time_trial": _time_trial, "race": _race, "traffic": _traffic, "roar_py": _roar_py, "policy": _policy}


def run_cell(cell: dict) -> dict:
    """The cell's row: its figures, or its error (a bad map or model is a row saying why, not the batch's end)."""
    started = time.time()
    row = {"status": "done", "error": ""}
    try:
        folders = {k: str(v) for k, v in roar_paths.layout().items()}
        row.update(JOBS[cell["kind"]](cell, folders))
    except Exception as e:  # every failure of a cell is its row's, the batch goes on
        row.update(status="failed", error=f"{type(e).__name__}: {e}".strip()[:2000],
                   trace=traceback.format_exc(limit=3)[-2000:])
    row.update(wall_s=round(time.time() - started, 3), worker=f"{socket.gethostname()}:{os.getpid()}")
    return row
