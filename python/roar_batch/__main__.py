"""python3 -m roar_batch MATRIX.yaml [--out DIR] [--scheduler tcp://HOST:PORT] [--workers N] [--no-progress]"""
import argparse
import os
import sys

from . import BatchInterrupted, MatrixError, print_summary, read_matrix, run_batch, summary
from .batch import plot


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="roar_batch", description="Runs a matrix of races or time trials on Dask: "
                                     "an embedded local cluster, or a running one with --scheduler.")
    parser.add_argument("matrix", help="the matrix's YAML file")
    parser.add_argument("--out", help="the batch's folder (default: output/batch_<matrix name>); run again to resume")
    parser.add_argument("--scheduler", help="a running Dask scheduler, tcp://HOST:PORT (default: a local cluster)")
    parser.add_argument("--workers", type=int, help="the local cluster's worker processes (default: one a core)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    if args.workers is not None and not 1 <= args.workers <= 256:
        parser.error(f"--workers must be 1 to 256, got {args.workers}")
    try:
        matrix = read_matrix(args.matrix)
    except MatrixError as e:
        print(f"roar_batch: {e}", file=sys.stderr)
        return 2
    import roar_paths
    out = args.out or str(roar_paths.package_root() / "output" / f"batch_{matrix.name}")
    try:
        rows = run_batch(matrix, out, args.scheduler, args.workers, progress=not args.no_progress)
    except BatchInterrupted as e:
        print(f"roar_batch: {e}", file=sys.stderr)
        return 1
    groups = summary(rows)
    print_summary(groups)
    plot(groups, os.path.join(out, "summary.png"))
    failed = sum(r.get("status") != "done" for r in rows)
    print(f"results: {os.path.join(out, 'results.csv')} ({len(rows)} cells, {failed} failed), "
          f"{os.path.join(out, 'summary.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
