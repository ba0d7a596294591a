"""Batches on Dask (python/roar_batch): a matrix read and refused naming the field; cells keyed by content; a
batch on a real `dask-scheduler` with two `dask-worker` processes on loopback that loses a worker to
SIGKILL mid-batch and still runs every cell once, keeps a failing cell as a row, resumes, and ends with what is
done when its scheduler goes."""
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
    ({"kind": "rally", "maps": ["roar_sprint"], "models": ["sedan"]}, "kind: 'rally' is neither"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "lapz": 2}, "unknown field(s) ['lapz']"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "seeds": 3}, "a time trial is deterministic"),
    ({"maps": ["roar_sprint"], "models": ["sedan"], "laps": 0}, "laps: 0 is outside [1, 100]"),
    ({"maps": ["roar_sprint"]}, "models is missing"),
    ({"kind": "race", "maps": ["roar_sprint"], "models": ["sedan"], "field": {"cars": 40}}, "field.cars: 40"),
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
