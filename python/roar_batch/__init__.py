"""Batches of races and time trials on Dask's distributed scheduler (python3-distributed): a matrix of maps,
car models, laps, grip use, seeds and fields, each cell one in-process race or time trial through the C++
stack (no ROS master), on an embedded local cluster or a running one. `python3 -m roar_batch MATRIX.yaml`."""
from .batch import BatchInterrupted, print_summary, run_batch, summary, write_table  # noqa: F401
from .jobs import race_field, run_cell  # noqa: F401
from .matrix import Matrix, MatrixError, cell_key, read_matrix  # noqa: F401
