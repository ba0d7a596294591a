"""Batches on Dask (python/roar_batch): a matrix read and refused naming the field; cells keyed by content; a
batch on a real `dask-scheduler` with two `dask-worker` processes on loopback that loses a worker to
SIGKILL mid-batch and still runs every cell once, keeps a failing cell as a row, resumes, and ends with what is
done when its scheduler goes; the overtaking planner's options swept; a ROAR tournament of competition
entries, each against a private roar_sim."""
import csv
import json
import os
import signal
import subprocess
import sys
import time

import pytest
import yaml

from roar_batch import MatrixError, cell_key, race_field, read_matrix


def write(tmp_path, matrix, name="m.yaml"):
    path = tmp_path / name
    path.write_text(yaml.safe_dump(matrix))
    return str(path)


@pytest.mark.parametrize("matrix, message", [
    ({"kind": "rally", "maps": ["roar_sprint"], "models": ["sedan"]}, "kind: 'rally' is not one of"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "lapz": 2}, "unknown field(s) ['lapz']"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "seeds": 3}, "a time trial is deterministic"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "laps": 0}, "laps: 0 is outside [1, 100]"),
    ({"maps": ["roar_sprint"]}, "models is missing"),
    ({"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "field": {"cars": 40}}, "field.cars: 40"),
    ({"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "overtake": {"passing.stal_time": 2}},
     "overtake.passing.stal_time: overtake: no option 'passing.stal_time' (did you mean 'passing.stall_time'?)"),
    ({"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "overtake": {"passing.stall_time": [2, 100]}},
     "overtake passing.stall_time 100 is outside [0.1, 60]"),
    ({"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "overtaking": "yes"}, "overtaking: 'yes'"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "overtake": {"passing.stall_time": 2}}, "for a time_trial"),
    ({"kind": "roar_py", "entries": ["competition"], "maps": ["monza"], "seeds": 3}, "deterministic here"),
    ({"kind": "roar_py", "entries": ["competition"], "maps": ["monza"], "models": ["sedan"]}, "in its own car"),
    ({"kind": "roar_py", "entries": ["fastest"], "maps": ["monza"]}, "'fastest' is not an entry"),
    ({"kind": "roar_py", "entries": ["example"], "maps": ["monza"], "camera": "big"}, "camera: 'big'"),
    ({"kind": "roar_py", "maps": ["monza"]}, "entries is missing"),
    ({"kind": "traffic", "maps": ["roar_sprint"], "fields": ["grid"]}, "fields: 'grid' is not one of pace_car"),
    ({"kind": "traffic", "maps": ["roar_sprint"], "pace_step": 0.5}, "pace_step: 0.5 is outside [0.01, 0.15]"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "controller": {"lookahed_time": 0.4}},
     "controller.lookahed_time: controller: no option 'lookahed_time' (did you mean 'lookahead_time'?)"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "controller": {"stanley_gain": [2, 99]}},
     "controller stanley_gain 99 is outside [0.01, 50]"),
    ({"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "controller": {"lateral_control": "mpc"}},
     "lateral_control 'mpc' is neither pure_pursuit nor stanley"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "controller": {"speed_gain": True}},
     "controller.speed_gain: True is not a int or float or str"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "controller": ["stanley"]}, "controller: expected a mapping"),
    ({"kind": "traffic", "maps": ["roar_sprint"], "controller": {"lookahead_time": 0.4}}, "for a traffic"),
    ({"kind": "policy", "maps": ["roar_sprint"], "policies": ["nowhere"]},
     "policies: policy 'nowhere' is neither a file nor one of config/policies"),
    ({"kind": "policy", "maps": ["roar_sprint"], "policies": ["roar_sprint"], "env": "pixels"},
     "env: env 'pixels' is neither a file nor one of config/rl"),
    ({"kind": "policy", "maps": ["roar_sprint"], "policies": ["roar_sprint"], "seeds": 4}, "deterministic (no seeds)"),
    ({"kind": "policy", "maps": ["roar_sprint"]}, "policies is missing"),
    ({"kind": "race", "scenarios": ["reverse_grid"], "seeds": 3}, "seeds: a scenario names its own map and cars"),
    ({"kind": "race", "scenarios": ["reverse_gird"]}, "scenarios: no scenario 'reverse_gird'"),
])
def test_a_matrix_is_refused_naming_the_file_and_field(tmp_path, matrix, message):
    path = write(tmp_path, matrix)
    with pytest.raises(MatrixError) as e:
        read_matrix(path)
    assert path in str(e.value) and message in str(e.value)


def test_a_matrix_expands_to_cells_keyed_by_their_content(tmp_path):
    m = read_matrix(write(tmp_path, {"kind": "race", "maps": ["roar_sprint", "roar_ring"], "models": ["sedan"],
                                     "laps": [1, 2], "seeds": 3, "field": {"cars": 3, "pace_spread": 0.05}}))
    assert len(m.cells) == 2 * 2 * 3 and m.name == "m"
    keys = [cell_key(c) for c in m.cells]
    assert len(set(keys)) == len(keys)
    again = read_matrix(write(tmp_path, {"name": "other", "kind": "race", "maps": ["roar_ring"], "models": ["sedan"],
                                         "laps": 2, "seeds": [1], "field": {"cars": 3, "pace_spread": 0.05}}, "o.yaml"))
    assert cell_key(again.cells[0]) in keys, "the same cell in another matrix has the same key"
    field = race_field(m.cells[0])
    assert race_field(m.cells[0]) == field and sorted(c["grid_slot"] for c in field) == [0, 1, 2]
    assert field[0]["pace"] == 1.0 and all(0.95 <= c["pace"] <= 1.0 for c in field)


def test_a_race_matrix_sweeps_the_overtaking_planners_options(tmp_path):
    plain = read_matrix(write(tmp_path, {"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "seeds": 2}))
    swept = read_matrix(write(tmp_path, {"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "seeds": 2,
                                         "overtaking": [True, False], "overtake": {"passing.min_gain": [2, 4],
                                                                                   "guard.predicted": False}}, "s.yaml"))
    assert len(swept.cells) == 2 * 2 * 2
    assert {c.get("overtaking", True) for c in swept.cells} == {True, False}
    assert {c["overtake"]["passing.min_gain"] for c in swept.cells} == {2, 4}
    assert all(c["overtake"]["guard.predicted"] is False for c in swept.cells)
    # A cell with the defaults keeps the key it had before options could be swept.
    assert "overtake" not in plain.cells[0] and "overtaking" not in plain.cells[0]
    assert cell_key(plain.cells[0]) == cell_key({"kind": "race", "map": "roar_sprint", "model": "sedan", "laps": 1,
                                                 "grip_use": 0.85, "seed": 0, "field": {"cars": 4,
                                                                                        "pace_spread": 0.05}})


def test_a_race_cell_takes_its_overtaking_settings():
    from roar_batch import run_cell
    cell = {"kind": "race", "map": "roar_sprint", "model": "sedan", "laps": 2, "grip_use": 0.85, "seed": 0,
            "field": {"cars": 2, "pace_spread": 0.0}}
    # Seed 0's grid puts car0 (full pace) behind; slowed to 80 %, car1 is passed only with overtaking on.
    import roar_batch.jobs as jobs
    original = jobs.race_field
    jobs.race_field = lambda c: [{"name": "slow", "grid_slot": 0, "pace": 0.8}, {"name": "fast", "grid_slot": 1,
                                                                                  "pace": 1.0}]
    try:
        on = run_cell(cell)
        off = run_cell({**cell, "overtaking": False})
        reluctant = run_cell({**cell, "overtake": {"passing.min_gain": 100}})
    finally:
        jobs.race_field = original
    assert on["status"] == off["status"] == reluctant["status"] == "done", (on, off, reluctant)
    assert on["passes_completed"] >= 1 and on["winner"] == "fast"
    assert off["passes_completed"] == 0 and off["winner"] == "slow"
    assert reluctant["passes_completed"] == 0 and reluctant["winner"] == "slow"


def test_time_trial_and_race_cells_take_the_trackers_settings(tmp_path):
    from roar_batch import run_cell
    swept = read_matrix(write(tmp_path, {"maps": ["roar_sprint"], "models": ["sedan"],
                                         "controller": {"lateral_control": ["pure_pursuit", "stanley"],
                                                        "lookahead_time": [0.3, 0.6]}}))
    assert len(swept.cells) == 4
    plain = read_matrix(write(tmp_path, {"maps": ["roar_sprint"], "models": ["sedan"]}, "p.yaml")).cells[0]
    assert "controller" not in plain
    rows = {(c["controller"]["lateral_control"], c["controller"]["lookahead_time"]): run_cell(c)
            for c in swept.cells}
    default = run_cell(plain)
    assert all(r["status"] == "done" for r in rows.values()), rows
    # The defaults set by name are the defaults; the other settings drive another lap.
    assert rows[("pure_pursuit", 0.3)]["best_lap"] == default["best_lap"]
    assert rows[("stanley", 0.3)]["best_lap"] != default["best_lap"]
    # Twice the lookahead cuts the corners: pure pursuit's tracking error grows (Stanley reads no lookahead).
    assert rows[("pure_pursuit", 0.6)]["rms_lateral_error"] > 2 * default["rms_lateral_error"]
    assert rows[("stanley", 0.6)]["best_lap"] == rows[("stanley", 0.3)]["best_lap"]
    race = read_matrix(write(tmp_path, {"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"],
                                        "field": {"cars": 2, "pace_spread": 0.0},
                                        "controller": {"max_speed": 20}}, "r.yaml")).cells[0]
    capped = run_cell(race)
    assert capped["status"] == "done" and capped["best_lap"] > default["best_lap"] * 1.2, capped


def test_policy_cells_lap_trained_policies_as_race_control_judges(tmp_path):
    from roar_batch import run_cell
    broken = tmp_path / "broken.yaml"
    broken.write_text("format: roar_ros mlp policy 1\nhidden: [4]\n")
    m = read_matrix(write(tmp_path, {"kind": "policy", "policies": ["roar_sprint", str(broken)],
                                     "maps": ["roar_sprint"], "models": ["sedan"], "laps": 2}))
    trained, bad = (run_cell(c) for c in m.cells)
    stack = run_cell({"kind": "time_trial", "map": "roar_sprint", "model": "sedan", "laps": 1, "grip_use": 0.85})
    # The shipped policy (rl_train's) laps clean from the grid, slower than the planner and controller.
    assert trained["status"] == "done" and trained["ended"] == "laps done", trained
    assert trained["clean"] and trained["finished"] and trained["laps_done"] == 2
    assert stack["best_lap"] < trained["best_lap"] < 1.2 * stack["best_lap"], (trained, stack)
    assert bad["status"] == "failed" and str(broken) in bad["error"], bad


def test_race_cells_of_scenarios_race_the_scenarios_cars(tmp_path):
    from roar_batch import run_cell
    m = read_matrix(write(tmp_path, {"kind": "race", "scenarios": ["five_percent", "multi_car"], "laps": 1,
                                     "overtaking": [True, False]}))
    assert len(m.cells) == 4 and all("map" not in c and "field" not in c for c in m.cells)
    rows = {(c["scenario"], c.get("overtaking", True)): run_cell(c) for c in m.cells}
    assert all(r["status"] == "done" and r["finished"] for r in rows.values()), rows
    # multi_car's pace car on pole is capped at 15 m/s: with overtaking off nobody gets by and it wins.
    assert rows[("multi_car", False)]["winner"] == "pace"
    assert rows[("multi_car", True)]["winner"] != "pace" and rows[("multi_car", True)]["passes_completed"] >= 1
    assert rows[("five_percent", False)]["winner"] == "slowed"


BENCH = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "devel", "lib",
                     "roar_ros", "roar_bench")


def test_roar_bench_traffic_as_a_batch_prints_the_table_its_loop_prints():
    table = ["--traffic", "--map=roar_sprint", "--field=pace_car", "--seeds=2", "--traffic-laps=1"]
    here = subprocess.run([BENCH] + table, capture_output=True, text=True, timeout=600)
    batch = subprocess.run([BENCH] + table + ["--batch-workers=2"], capture_output=True, text=True, timeout=600)
    assert here.returncode == 0 and batch.returncode == 0, here.stderr + batch.stderr

    def figures(out):  # every line but the header's way of running and the wall time
        return [line for line in out.splitlines() if "lockstep," not in line and " s wall;" not in line]
    assert "as a batch on Dask" in batch.stdout and "in one process" in here.stdout
    assert figures(batch.stdout) == figures(here.stdout)
    row = next(line for line in here.stdout.splitlines() if line.startswith("roar_sprint"))
    assert int(row.split()[3]) > 0, "the pace car is passed: the table counts something"
    assert "batch roar_bench_traffic: 2 cells" in batch.stderr, batch.stderr
    refused = subprocess.run([BENCH] + table + ["--batch", "--verbose"], capture_output=True, text=True, timeout=60)
    assert refused.returncode == 2 and "--verbose: the races of a batch" in refused.stderr
    refused = subprocess.run([BENCH] + table + ["--scheduler=10.0.0.5:8786"], capture_output=True, text=True,
                             timeout=60)
    assert refused.returncode == 2 and "expected tcp://HOST:PORT" in refused.stderr


def test_a_roar_tournament_runs_each_entry_against_a_private_roar_sim(tmp_path):
    # Two entries on a short circuit for a lap, a small camera (the runner's 1024x768 costs minutes), and a map
    # that does not exist: two ROAR_PY programs side by side on two workers, each with its own master.
    matrix = write(tmp_path, {"name": "tournament", "kind": "roar_py", "entries": ["competition", "example"],
                              "maps": ["roar_ring", "no_such_map"], "laps": 1, "camera": "64x48",
                              "max_seconds": 400})
    out = str(tmp_path / "out")
    env = {k: v for k, v in os.environ.items() if k != "ROS_MASTER_URI"}
    done = subprocess.run([sys.executable, "-m", "roar_batch", matrix, "--out", out, "--workers", "2",
                           "--no-progress"], capture_output=True, text=True, timeout=900, env=env)
    assert done.returncode == 0, done.stdout + done.stderr
    table = {(r["entry"], r["map"]): r for r in rows(out)}
    assert len(table) == 4
    for entry in ("competition", "example"):
        ran, missing = table[(entry, "roar_ring")], table[(entry, "no_such_map")]
        assert ran["status"] == "done" and ran["finished"] == "True" and ran["respawns"] == "0", ran
        assert float(ran["elapsed_time"]) == pytest.approx(float(ran["lap_times"]), abs=0.01)
        assert missing["status"] == "failed" and "no_such_map" in missing["error"], missing
    assert float(table[("competition", "roar_ring")]["elapsed_time"]) < \
        float(table[("example", "roar_ring")]["elapsed_time"]), "the competition entry outruns ROAR_PY's example"
    assert "elapsed_time" in done.stdout and os.path.exists(os.path.join(out, "summary.png"))


def start(cmd, env, log):
    return subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def stop(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)


def wait_for(condition, what, timeout=120.0):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if condition():
            return
        time.sleep(0.1)
    raise AssertionError(f"no {what} within {timeout} s")


def rows(out):
    with open(os.path.join(out, "results.csv")) as f:
        return list(csv.DictReader(f))


def test_a_batch_on_a_scheduler_and_two_workers_loses_one_and_resumes(tmp_path):
    env = dict(os.environ)
    scheduler_file = str(tmp_path / "scheduler.json")
    log = open(tmp_path / "cluster.log", "w")
    scheduler = start(["dask-scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                       "--scheduler-file", scheduler_file], env, log)
    workers = []
    try:
        wait_for(lambda: os.path.exists(scheduler_file) and os.path.getsize(scheduler_file) > 0, "scheduler file")
        address = json.load(open(scheduler_file))["address"]
        assert address.startswith("tcp://127.0.0.1:")
        for k in range(2):
            workers.append(start(["dask-worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                                  "--name", f"w{k}"], env, log))
        # Two-lap races of two cars (a second or two each), and a map that does not exist.
        matrix = write(tmp_path, {"name": "lost_worker", "kind": "race", "maps": ["roar_sprint", "no_such_map"],
                                  "models": ["sedan"], "laps": 2, "seeds": 8, "field": {"cars": 2}})
        out = str(tmp_path / "out")
        cells = os.path.join(out, "cells")
        batch = subprocess.Popen([sys.executable, "-m", "roar_batch", matrix, "--out", out, "--scheduler", address,
                                  "--no-progress"], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 text=True)
        wait_for(lambda: os.path.isdir(cells) and len(os.listdir(cells)) >= 3, "three finished cells")
        os.kill(workers[0].pid, signal.SIGKILL)  # mid-batch, with a cell on it or soon to be
        stdout, _ = batch.communicate(timeout=600)
        assert batch.returncode == 0, stdout
        table = rows(out)
        assert len(table) == 16 and len({r["key"] for r in table}) == 16
        done = [r for r in table if r["map"] == "roar_sprint"]
        failed = [r for r in table if r["map"] == "no_such_map"]
        assert all(r["status"] == "done" and r["finished"] == "True" for r in done), done
        assert all(r["status"] == "failed" and "no_such_map" in r["error"] for r in failed), failed
        assert {r["worker"].split(":")[0] for r in done}, "each row says where it ran"
        assert "16 cells, 0 done before, 16 to run" in stdout
        # Resume: a finished batch runs nothing; with three rows gone, those three.
        again = subprocess.run([sys.executable, "-m", "roar_batch", matrix, "--out", out, "--scheduler", address,
                                "--no-progress"], env=env, capture_output=True, text=True, timeout=600)
        assert again.returncode == 0 and "16 done before, 0 to run" in again.stdout, again.stdout + again.stderr
        for name in sorted(os.listdir(cells))[:3]:
            os.remove(os.path.join(cells, name))
        again = subprocess.run([sys.executable, "-m", "roar_batch", matrix, "--out", out, "--scheduler", address,
                                "--no-progress"], env=env, capture_output=True, text=True, timeout=600)
        assert "13 done before, 3 to run" in again.stdout, again.stdout + again.stderr
        assert [r["key"] for r in rows(out)] == [r["key"] for r in table], "the same cells, in the matrix's order"
        # The scheduler lost mid-batch: the batch ends, saying so, with the rows done kept.
        longer = write(tmp_path, {"name": "lost_scheduler", "kind": "race", "maps": ["roar_ring"],
                                  "models": ["sedan"], "laps": 3, "seeds": 20, "field": {"cars": 3}}, "l.yaml")
        out2 = str(tmp_path / "out2")
        batch = subprocess.Popen([sys.executable, "-m", "roar_batch", longer, "--out", out2, "--scheduler", address,
                                  "--no-progress"], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 text=True)
        wait_for(lambda: os.path.isdir(os.path.join(out2, "cells")) and os.listdir(os.path.join(out2, "cells")),
                 "a finished cell")
        stop(scheduler)
        stdout, _ = batch.communicate(timeout=300)
        assert batch.returncode == 1 and "the scheduler went away" in stdout, stdout
        kept = [n for n in os.listdir(os.path.join(out2, "cells")) if n.endswith(".json")]
        assert 1 <= len(kept) < 20
    finally:
        for proc in workers + [scheduler]:
            stop(proc)
        log.close()


def test_a_batch_runs_on_an_embedded_local_cluster(tmp_path):
    matrix = write(tmp_path, {"name": "local", "maps": ["roar_sprint"], "models": ["sedan", "hatchback"]})
    out = str(tmp_path / "out")
    done = subprocess.run([sys.executable, "-m", "roar_batch", matrix, "--out", out, "--workers", "2",
                           "--no-progress"], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    table = rows(out)
    assert [r["model"] for r in table] == ["sedan", "hatchback"]
    assert float(table[0]["best_lap"]) < float(table[1]["best_lap"]), "the sedan is the faster car"
    assert os.path.exists(os.path.join(out, "summary.png")) and "best_lap" in done.stdout


def test_every_shipped_matrix_reads():
    folder = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "config",
                          "batches")
    names = sorted(n for n in os.listdir(folder) if n.endswith(".yaml"))
    assert names, folder
    for name in names:
        assert read_matrix(os.path.join(folder, name)).cells, name


def test_a_time_trial_can_be_traced_tick_by_tick():
    import numpy as np
    import roar_core
    import roar_paths
    layout = roar_paths.layout()
    args = ("roar_sprint", str(layout["maps"]), "sedan", str(layout["urdf"]), str(layout["vehicles"]))
    plain = roar_core.run_time_trial(*args)
    traced = roar_core.run_time_trial(*args, trace=True)
    assert "trace" not in plain
    trace = traced.pop("trace")
    assert traced == plain, "tracing changes nothing the trial does"
    t, x, y, yaw, speed, steer, throttle, brake = trace.T
    assert trace.shape == (round(traced["sim_time"] / 0.05), 8)
    assert np.allclose(np.diff(t), 0.05) and t[-1] == pytest.approx(traced["sim_time"])
    # The positions are a car's: speed is the distance it covers, and the pedals and steer are in range.
    covered = np.hypot(np.diff(x), np.diff(y)) / 0.05
    assert np.median(np.abs(covered - speed[1:])) < 0.5
    assert speed.max() > 30 and np.all((throttle >= 0) & (throttle <= 1) & (brake >= 0) & (brake <= 1))
    assert np.all(np.abs(steer) <= 1) and np.all(np.abs(yaw) <= np.pi)
