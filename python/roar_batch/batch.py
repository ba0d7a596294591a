"""A batch on Dask's distributed scheduler: an embedded local cluster sized to the machine, or a running one
(--scheduler). Each cell's row is written to out/cells/<key>.json as it finishes, so a batch run again
resumes where it stopped, a worker lost has its cells run elsewhere by the scheduler, and a scheduler lost
ends the batch with every finished row kept."""
import csv
import json
import os
import statistics
import sys
import tempfile
import textwrap
import typing

from .jobs import run_cell
from .matrix import Matrix, cell_key

# The figure a summary groups: a time trial's best lap, a race's winning time, a traffic race's seconds a lap
# lost in traffic (the mean of its cars), a ROAR_PY run's score (the official runner's: the time to finish
# every lap).
FIGURES = {"time_trial": "best_lap", "race": "winning_time", "traffic": "mean_lap_loss", "roar_py": "elapsed_time",
           "policy": "best_lap"}


class BatchInterrupted(RuntimeError):
    """The scheduler went away: the rows done are kept, the rest are not."""


def _write_json(path: str, data: dict) -> None:
    folder = os.path.dirname(path)
    with tempfile.NamedTemporaryFile("w", dir=folder, suffix=".tmp", delete=False) as f:
        json.dump(data, f, sort_keys=True)
        tmp = f.name
    os.replace(tmp, path)  # a row is whole or absent, whatever stops the batch


def _read_row(path: str) -> typing.Optional[dict]:
    try:
        with open(path) as f:
            row = json.load(f)
        return row if isinstance(row, dict) and "cell" in row else None
    except (OSError, ValueError):
        return None


def _client(scheduler: typing.Optional[str], workers: typing.Optional[int]):
    from distributed import Client, LocalCluster
    if scheduler:
        return Client(scheduler, timeout="20s"), None
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                           dashboard_address=None, host="127.0.0.1")
    return Client(cluster), cluster


def run_batch(matrix: Matrix, out: str, scheduler: typing.Optional[str] = None, workers: typing.Optional[int] = None,
              progress: bool = True) -> typing.List[dict]:
    """Runs the matrix's cells not yet in `out` and returns every cell's row (the matrix's order)."""
    import asyncio
    import concurrent.futures

    from distributed import KilledWorker, as_completed
    cells_dir = os.path.join(out, "cells")
    os.makedirs(cells_dir, exist_ok=True)
    keyed = [(cell_key(c), c) for c in matrix.cells]
    todo = [(k, c) for k, c in keyed if _read_row(os.path.join(cells_dir, k + ".json")) is None]
    print(f"batch {matrix.name}: {len(keyed)} cells, {len(keyed) - len(todo)} done before, {len(todo)} to run",
          flush=True)
    if todo:
        client, cluster = _client(scheduler, workers)
        bar = None
        if progress:
            try:
                from tqdm import tqdm
                bar = tqdm(total=len(todo), unit="cell", file=sys.stderr)
            except ImportError:
                pass
        try:
            futures = client.map(run_cell, [c for _, c in todo], key=[f"roar-cell-{k}" for k, _ in todo], pure=False)
            by_key = {f.key: (k, c) for f, (k, c) in zip(futures, todo)}
            for future in as_completed(futures):
                key, cell = by_key[future.key]
                try:
                    row = future.result()
                except KilledWorker as e:  # a cell whose workers died under it, again and again: its row says so
                    row = {"status": "failed", "error": f"{type(e).__name__}: {e}"}
                _write_json(os.path.join(cells_dir, key + ".json"), {"cell": cell, "key": key, **row})
                if bar is not None:
                    bar.update(1)
        except (OSError, TimeoutError, asyncio.CancelledError, concurrent.futures.CancelledError) as e:
            raise BatchInterrupted(f"the scheduler went away ({type(e).__name__}: {e}); the rows done are in "
                                   f"{cells_dir}: run the batch again to resume") from None
        finally:
            if bar is not None:
                bar.close()
            client.close()
            if cluster is not None:
                cluster.close()
    rows = [_read_row(os.path.join(cells_dir, k + ".json")) or {"cell": c, "key": k, "status": "missing"}
            for k, c in keyed]
    write_table(rows, os.path.join(out, "results.csv"))
    _write_json(os.path.join(out, "results.json"), rows)
    return rows


def flat(row: dict) -> dict:
    """A row as one level of columns: the cell's fields first (a race's field as field_cars, field_pace_spread)."""
    out = {}
    for k, v in row["cell"].items():
        if isinstance(v, dict):
            out.update({f"{k}_{kk}": vv for kk, vv in v.items()})
        else:
            out[k] = v
    out.update({k: v for k, v in row.items() if k not in ("cell", "trace")})
    return out


def write_table(rows: typing.List[dict], path: str) -> None:
    """results.csv: a row per cell, every column any row has; results.parquet beside it where pyarrow is."""
    table = [flat(r) for r in rows]
    columns = list(dict.fromkeys(k for r in table for k in r))
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, columns)
        writer.writeheader()
        writer.writerows(table)
    try:
        import pandas
        import pyarrow  # noqa: F401 - Debian 12 has none; where it is, the table is Parquet too
        pandas.DataFrame(table, columns=columns).to_parquet(os.path.splitext(path)[0] + ".parquet")
    except ImportError:
        pass


def describe(cell: dict) -> str:
    """A group's cell as a line: its map, then each field that was swept ("roar_sprint sedan laps 2 grip 0.85
    field 4x0.06 overtake passing.stall_time=2")."""
    parts = []
    order = ["map", "model", "entry", "policy", "laps", "grip_use", "field", "overtaking", "overtake", "controller",
             "camera", "max_seconds"]
    for k in sorted(cell, key=lambda k: order.index(k) if k in order else len(order)):
        v = cell[k]
        if k in ("kind", "seed"):
            continue
        if k == "field":
            parts.append(f"field {v['cars']}x{v['pace_spread']}" if isinstance(v, dict) else str(v))
        elif k in ("overtake", "controller"):
            parts.append(f"{k} " + ",".join(f"{n}={x}" for n, x in v.items()))
        elif k == "overtaking":
            parts.append("overtaking " + ("on" if v else "off"))
        elif k in ("map", "model", "entry", "policy"):
            parts.append(str(v))
        else:
            parts.append(f"{k.replace('_use', '').replace('max_seconds', 'max_s')} {v}")
    return " ".join(parts)


def summary(rows: typing.List[dict]) -> typing.List[dict]:
    """Per group (every cell field but the seed): how many cells, how many failed, and the group's figure
    (FIGURES) as mean, spread (standard deviation) and range."""
    groups: typing.Dict[str, dict] = {}
    for row in rows:
        cell = {k: v for k, v in row["cell"].items() if k != "seed"}
        key = json.dumps(cell, sort_keys=True)
        g = groups.setdefault(key, {"cell": cell, "values": [], "cells": 0, "failed": 0})
        g["cells"] += 1
        figure = row.get(FIGURES[cell["kind"]])
        if row.get("status") != "done":
            g["failed"] += 1
        elif figure is not None:
            g["values"].append(figure)
    out = []
    for g in groups.values():
        v = g["values"]
        out.append({"kind": g["cell"]["kind"], "group": describe(g["cell"]), "cell": g["cell"], "cells": g["cells"],
                    "failed": g["failed"], "figure": FIGURES[g["cell"]["kind"]],
                    "mean": statistics.fmean(v) if v else None,
                    "spread": statistics.pstdev(v) if len(v) > 1 else 0.0 if v else None,
                    "low": min(v) if v else None, "high": max(v) if v else None})
    return out


def print_summary(groups: typing.List[dict]) -> None:
    width = max([len(g["group"]) for g in groups] + [5])
    print(f"{'group':{width}} {'cells':>5} {'failed':>6}  figure")
    for g in groups:
        figure = (f"{g['figure']} {g['mean']:.2f} s +- {g['spread']:.2f} ({g['low']:.2f}-{g['high']:.2f})"
                  if g["mean"] is not None else f"{g['figure']}: none")
        print(f"{g['group']:{width}} {g['cells']:5d} {g['failed']:6d}  {figure}")


def plot(groups: typing.List[dict], path: str) -> None:
    """Each group's figure with its range over the seeds, one bar a group."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    shown = [g for g in groups if g["mean"] is not None]
    if not shown:
        return
    fig, ax = plt.subplots(figsize=(max(6, 0.6 * len(shown) + 2), 4.5))
    labels = [textwrap.fill(g["group"], 22) for g in shown]
    means = [g["mean"] for g in shown]
    errors = [[g["mean"] - g["low"] for g in shown], [g["high"] - g["mean"] for g in shown]]
    ax.bar(range(len(shown)), means, yerr=errors, capsize=4, color="tab:blue")
    ax.set_xticks(range(len(shown)), labels, fontsize=7)
    ax.set_ylabel(f"{shown[0]['figure']}, s (bars: the range over seeds)")
    ax.set_ylim(min(g["low"] for g in shown) * 0.97, max(g["high"] for g in shown) * 1.02)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
