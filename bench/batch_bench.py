#!/usr/bin/env python3
"""The batch tool's speed on this machine: the same race cells (config/batches/traffic_seeds.yaml's kind, on
Roar Sprint) run as a loop in this process, then as a batch on an embedded local cluster of 1 and of 2 worker
processes; prints each one's wall time, the speed-up over the loop, and the scheduler's cost per job (the
1-worker batch's time over the loop's, per cell). Then the traffic benchmark's table (roar_bench --traffic,
15 races a seed) as its loop in one process and as a batch of 1 and of 2 workers (--batch-workers), the
tables checked alike.

    /usr/bin/python3 bench/batch_bench.py [--cells 12] [--traffic-seeds 1 (0: none)]
"""
import argparse
import os
import subprocess
import tempfile
import time

import yaml

import roar_paths
from roar_batch import read_matrix, run_batch, run_cell


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", type=int, default=12)
    parser.add_argument("--traffic-seeds", type=int, default=1)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "bench.yaml")
        with open(path, "w") as f:
            yaml.safe_dump({"name": "bench", "kind": "race", "maps": ["roar_sprint"], "models": [roar_paths.default_model()], "laps": 2,
                            "seeds": args.cells, "field": {"cars": 4, "pace_spread": 0.06}}, f)
        matrix = read_matrix(path)
        started = time.perf_counter()
        for cell in matrix.cells:
            run_cell(cell)
        loop = time.perf_counter() - started
        print(f"{len(matrix.cells)} races of 4 cars, 2 laps of Roar Sprint, on {os.cpu_count()} cores")
        print(f"  {'a loop in one process':32} {loop:7.1f} s  1.00x")
        times = {}
        for workers in (1, 2):
            started = time.perf_counter()
            run_batch(matrix, os.path.join(tmp, f"out{workers}"), workers=workers, progress=False)
            times[workers] = time.perf_counter() - started
            print(f"  {f'a batch, {workers} worker(s)':32} {times[workers]:7.1f} s  {loop / times[workers]:.2f}x")
        print(f"  the scheduler's cost: {(times[1] - loop) / len(matrix.cells) * 1000:.0f} ms a job (the cluster's "
              "start-up included)")
    if args.traffic_seeds > 0:
        traffic(args.traffic_seeds)


def traffic(seeds: int):
    bench = str(roar_paths.package_root() / "devel" / "lib" / "roar_ros" / "roar_bench")
    table = [bench, "--traffic", f"--seeds={seeds}"]
    figures = {}
    print(f"roar_bench --traffic --seeds={seeds}: its table's races")
    for name, extra in (("its loop in one process", []), ("a batch, 1 worker", ["--batch-workers=1"]),
                        ("a batch, 2 workers", ["--batch-workers=2"])):
        started = time.perf_counter()
        out = subprocess.run(table + extra, capture_output=True, text=True, check=True).stdout
        wall = time.perf_counter() - started
        figures[name] = ([line for line in out.splitlines() if "lockstep," not in line and " s wall;" not in line],
                         wall)
        loop = figures["its loop in one process"][1]
        print(f"  {name:32} {wall:7.1f} s  {loop / wall:.2f}x")
    same = len({tuple(lines) for lines, _ in figures.values()}) == 1
    print(f"  the three tables {'alike to the last digit' if same else 'DIFFER'}")


if __name__ == "__main__":
    main()
