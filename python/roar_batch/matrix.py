"""A batch's matrix: a YAML file of what to vary (maps, car models, laps, grip use, seeds, a race's field) and
the cells it expands to, each keyed by its content."""
import hashlib
import itertools
import json
import os
import typing

import yaml

KINDS = ("time_trial", "race")
KEYS = {"name", "kind", "maps", "models", "laps", "grip_use", "seeds", "field"}
FIELD_KEYS = {"cars", "pace_spread"}
MAX_CELLS = 100000


class MatrixError(ValueError):
    """A matrix that cannot be run; the message names the file and the field."""


def _as_list(value, path: str, field: str, kind: type, low=None, high=None) -> list:
    values = value if isinstance(value, list) else [value]
    if not values:
        raise MatrixError(f"{path}: {field} is empty")
    out = []
    for v in values:
        if isinstance(v, bool) or not isinstance(v, kind) and not (kind is float and isinstance(v, int)):
            raise MatrixError(f"{path}: {field}: {v!r} is not a {kind.__name__}")
        if low is not None and not low <= v <= high:
            raise MatrixError(f"{path}: {field}: {v!r} is outside [{low}, {high}]")
        out.append(kind(v))
    return out


def cell_key(cell: dict) -> str:
    """The cell's content as a name: the same cell, from any matrix, has the same key."""
    return hashlib.sha256(json.dumps(cell, sort_keys=True).encode()).hexdigest()[:20]


class Matrix(typing.NamedTuple):
    name: str
    cells: typing.List[dict]


def read_matrix(path: str) -> Matrix:
    """Reads and checks a matrix (MatrixError names the file and field) and expands it into its cells."""
    if not os.path.isfile(path):
        raise MatrixError(f"{path}: not a file")
    try:
        with open(path) as f:
            raw = yaml.safe_load(f)
    except yaml.YAMLError as e:
        raise MatrixError(f"{path}: not YAML: {e}") from None
    if not isinstance(raw, dict):
        raise MatrixError(f"{path}: expected a mapping of name, kind, maps, models, laps, grip_use, seeds, field")
    unknown = sorted(set(raw) - KEYS)
    if unknown:
        raise MatrixError(f"{path}: unknown field(s) {unknown} (known: {sorted(KEYS)})")
    kind = raw.get("kind", "time_trial")
    if kind not in KINDS:
        raise MatrixError(f"{path}: kind: {kind!r} is neither time_trial nor race")
    for required in ("maps", "models"):
        if required not in raw:
            raise MatrixError(f"{path}: {required} is missing")
    maps = _as_list(raw["maps"], path, "maps", str)
    models = _as_list(raw["models"], path, "models", str)
    laps = _as_list(raw.get("laps", 1), path, "laps", int, 1, 100)
    grip = _as_list(raw.get("grip_use", 0.85), path, "grip_use", float, 0.05, 1.0)
    field = raw.get("field")
    if kind == "time_trial":
        if "seeds" in raw or field is not None:
            raise MatrixError(f"{path}: a time trial is deterministic: seeds and field are a race's")
        seeds, fields = [None], [None]
    else:
        seeds_raw = raw.get("seeds", 1)
        if isinstance(seeds_raw, int) and not isinstance(seeds_raw, bool):
            if not 1 <= seeds_raw <= 10000:
                raise MatrixError(f"{path}: seeds: {seeds_raw} is outside [1, 10000]")
            seeds = list(range(seeds_raw))
        else:
            seeds = _as_list(seeds_raw, path, "seeds", int, 0, 2 ** 31 - 1)
        field = field or {}
        if not isinstance(field, dict) or set(field) - FIELD_KEYS:
            raise MatrixError(f"{path}: field: expected a mapping of {sorted(FIELD_KEYS)}")
        cars = _as_list(field.get("cars", 4), path, "field.cars", int, 1, 20)
        spreads = _as_list(field.get("pace_spread", 0.05), path, "field.pace_spread", float, 0.0, 0.5)
        fields = [{"cars": c, "pace_spread": p} for c, p in itertools.product(cars, spreads)]
    count = len(maps) * len(models) * len(laps) * len(grip) * len(seeds) * len(fields)
    if count > MAX_CELLS:
        raise MatrixError(f"{path}: {count} cells, more than {MAX_CELLS}")
    cells = []
    for m, model, lap, g, seed, f in itertools.product(maps, models, laps, grip, seeds, fields):
        cell = {"kind": kind, "map": m, "model": model, "laps": lap, "grip_use": g}
        if kind == "race":
            cell.update(seed=seed, field=f)
        cells.append(cell)
    name = raw.get("name", os.path.splitext(os.path.basename(path))[0])
    if not isinstance(name, str) or not name:
        raise MatrixError(f"{path}: name must be a non-empty string")
    return Matrix(name, cells)
