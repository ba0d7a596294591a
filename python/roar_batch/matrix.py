"""A batch's matrix: a YAML file of what to vary (time trials and races of the stack: maps, car models, laps,
grip use, seeds, a race's field or scenario, the overtaking planner's and the tracker's options; ROAR_PY programs:
competition entries, maps, laps; trained policies: policy files, maps, car models, laps) and the cells it
expands to, each keyed by its content."""
import hashlib
import itertools
import json
import math
import os
import typing

import yaml

KINDS = ("time_trial", "race", "traffic", "roar_py", "policy")
# The fields each kind takes (besides name and kind).
KEYS = {"time_trial": {"maps", "models", "laps", "grip_use", "controller"},
        "race": {"maps", "models", "laps", "grip_use", "seeds", "field", "overtaking", "overtake", "controller",
                 "scenarios"},
        "traffic": {"maps", "models", "fields", "seeds", "laps", "pace_step", "overtake"},
        "roar_py": {"entries", "maps", "laps", "camera", "max_seconds"},
        "policy": {"policies", "maps", "models", "laps", "env", "max_seconds"}}
FIELD_KEYS = {"cars", "pace_spread"}
# Options set by name, each checked by the C++ side's table: its binding, an example, the values it takes.
OPTION_TABLES = {"overtake": ("overtake_options", "passing.stall_time: 2", (int, float, bool)),
                 "controller": ("tracker_options", "lookahead_time: [0.3, 0.4]", (int, float, str))}
MAX_CELLS = 100000
RUNNER_CAMERA = "1024x768"  # the official runner's chase camera


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
        raise MatrixError(f"{path}: expected a mapping of name, kind and what to sweep")
    kind = raw.get("kind", "time_trial")
    if kind not in KINDS:
        raise MatrixError(f"{path}: kind: {kind!r} is not one of {', '.join(KINDS)}")
    fields = {k: v for k, v in raw.items() if k not in ("name", "kind")}
    unknown = sorted(set(fields) - KEYS[kind])
    if unknown:
        hint = (": a time trial is deterministic: seeds and field are a race's"
                if kind == "time_trial" and set(unknown) & {"seeds", "field"} else
                ": a ROAR_PY run is the official runner's, deterministic here (no seeds), in its own car"
                if kind == "roar_py" and set(unknown) & {"seeds", "models"} else
                ": a policy drives from the pole position without noise, deterministic (no seeds)"
                if kind == "policy" and "seeds" in unknown else "")
        raise MatrixError(f"{path}: unknown field(s) {unknown} for a {kind} (known: {sorted(KEYS[kind])}){hint}")
    cells = {"time_trial": _time_trial_cells, "race": _race_cells, "traffic": _traffic_cells,
             "roar_py": _roar_py_cells, "policy": _policy_cells}[kind](fields, path)
    if len(cells) > MAX_CELLS:
        raise MatrixError(f"{path}: {len(cells)} cells, more than {MAX_CELLS}")
    name = raw.get("name", os.path.splitext(os.path.basename(path))[0])
    if not isinstance(name, str) or not name:
        raise MatrixError(f"{path}: name must be a non-empty string")
    return Matrix(name, [{"kind": kind, **c} for c in cells])


def _required(fields: dict, key: str, path: str):
    if key not in fields:
        raise MatrixError(f"{path}: {key} is missing")
    return fields[key]


def _product(lists: typing.Dict[str, list], path: str) -> typing.List[dict]:
    """The cells of every combination of the lists, in their order (the first the slowest to change); refused
    before they are made when there are more than a batch takes."""
    count = math.prod(len(v) for v in lists.values())
    if count > MAX_CELLS:
        raise MatrixError(f"{path}: {count} cells, more than {MAX_CELLS}")
    return [dict(zip(lists, values)) for values in itertools.product(*lists.values())]


def _stack_lists(fields: dict, path: str) -> typing.Dict[str, list]:
    return {"map": _as_list(_required(fields, "maps", path), path, "maps", str),
            "model": _as_list(_required(fields, "models", path), path, "models", str),
            "laps": _as_list(fields.get("laps", 1), path, "laps", int, 1, 100),
            "grip_use": _as_list(fields.get("grip_use", 0.85), path, "grip_use", float, 0.05, 1.0)}


def _time_trial_cells(fields: dict, path: str) -> typing.List[dict]:
    return _with_settings(_product(_stack_lists(fields, path), path), fields, path, ["controller"])


def _seeds(fields: dict, path: str) -> list:
    seeds_raw = fields.get("seeds", 1)
    if isinstance(seeds_raw, int) and not isinstance(seeds_raw, bool):
        if not 1 <= seeds_raw <= 10000:
            raise MatrixError(f"{path}: seeds: {seeds_raw} is outside [1, 10000]")
        return list(range(seeds_raw))
    return _as_list(seeds_raw, path, "seeds", int, 0, 2 ** 31 - 1)


def _fields(fields: dict, path: str) -> typing.List[dict]:
    field = fields.get("field") or {}
    if not isinstance(field, dict) or set(field) - FIELD_KEYS:
        raise MatrixError(f"{path}: field: expected a mapping of {sorted(FIELD_KEYS)}")
    cars = _as_list(field.get("cars", 4), path, "field.cars", int, 1, 20)
    spreads = _as_list(field.get("pace_spread", 0.05), path, "field.pace_spread", float, 0.0, 0.5)
    return [{"cars": c, "pace_spread": p} for c, p in itertools.product(cars, spreads)]


def _option_settings(fields: dict, path: str, key: str) -> typing.List[dict]:
    """The settings of `key`'s options to sweep (overtake: {"passing.stall_time": [1, 2]}, controller:
    {"lateral_control": [pure_pursuit, stanley]}: each a value or a list), each checked by the C++ side's own
    table (roar_core.overtake_options, roar_core.tracker_options)."""
    import roar_core
    check, example, kinds = OPTION_TABLES[key]
    options = fields.get(key) or {}
    if not isinstance(options, dict):
        raise MatrixError(f"{path}: {key}: expected a mapping of options by name ({example})")
    lists = {}
    for name, values in options.items():
        lists[str(name)] = values if isinstance(values, list) and values else [values]
        for v in lists[str(name)]:
            if not isinstance(v, kinds) or isinstance(v, bool) and bool not in kinds:
                raise MatrixError(f"{path}: {key}.{name}: {v!r} is not a {' or '.join(k.__name__ for k in kinds)}")
            try:
                getattr(roar_core, check)({str(name): v})
            except ValueError as e:
                raise MatrixError(f"{path}: {key}.{name}: {e}") from None
    return _product(lists, path)


def _with_settings(cells: typing.List[dict], fields: dict, path: str, keys: typing.Sequence[str]) -> typing.List[dict]:
    """Each cell once per combination of the option settings of `keys`; only settings made are in a cell, so
    that a cell without them keeps its key."""
    for key in keys:
        settings = _option_settings(fields, path, key)
        cells = [{**cell, **({key: setting} if setting else {})} for cell in cells for setting in settings]
    return cells


def _scenario_lists(fields: dict, path: str) -> typing.Dict[str, list]:
    """Races of scenario files (config/scenarios names or paths): each its map, cars, grid and paces; `models`
    and `laps`, where given, replace the scenario's for every car."""
    import roar_core
    import roar_paths
    clash = sorted({"maps", "field", "seeds"} & set(fields))
    if clash:
        raise MatrixError(f"{path}: {', '.join(clash)}: a scenario names its own map and cars, and races them "
                          f"deterministically (no seeds)")
    scenarios = _as_list(fields["scenarios"], path, "scenarios", str)
    for name in scenarios:
        try:
            roar_core.load_scenario(name, str(roar_paths.package_root()))
        except ValueError as e:
            raise MatrixError(f"{path}: scenarios: {e}") from None
    lists = {"scenario": scenarios,
             "grip_use": _as_list(fields.get("grip_use", 0.85), path, "grip_use", float, 0.05, 1.0)}
    if "models" in fields:
        lists["model"] = _as_list(fields["models"], path, "models", str)
    if "laps" in fields:
        lists["laps"] = _as_list(fields["laps"], path, "laps", int, 1, 100)
    return lists


def _race_cells(fields: dict, path: str) -> typing.List[dict]:
    if "scenarios" in fields:
        lists = _scenario_lists(fields, path)
    else:
        lists = _stack_lists(fields, path)
        lists.update(seed=_seeds(fields, path), field=_fields(fields, path))
    overtaking = fields.get("overtaking", True)
    overtaking = overtaking if isinstance(overtaking, list) and overtaking else [overtaking]
    for v in overtaking:
        if not isinstance(v, bool):
            raise MatrixError(f"{path}: overtaking: {v!r} is not true or false")
    # Only what differs from the defaults is in the cell, so that a cell's key stays what it was.
    cells = [{**cell, **({} if on else {"overtaking": False})} for cell in _product(lists, path) for on in overtaking]
    return _with_settings(cells, fields, path, ["overtake", "controller"])


def _traffic_cells(fields: dict, path: str) -> typing.List[dict]:
    """roar_bench --traffic's races: each a field of the benchmark's drawn from its seed on a circuit."""
    import roar_core
    import roar_paths
    known = list(roar_core.TRAFFIC_FIELDS)
    kinds = _as_list(fields.get("fields", known), path, "fields", str)
    for k in kinds:
        if k not in known:
            raise MatrixError(f"{path}: fields: {k!r} is not one of {', '.join(known)}")
    lists = {"map": _as_list(_required(fields, "maps", path), path, "maps", str),
             "model": _as_list(fields.get("models", roar_paths.default_model()), path, "models", str),
             "field": kinds, "seed": _seeds(fields, path),
             "laps": _as_list(fields.get("laps", 3), path, "laps", int, 1, 100),
             "pace_step": _as_list(fields.get("pace_step", 0.05), path, "pace_step", float,
                                   *roar_core.TRAFFIC_PACE_STEPS)}
    return _with_settings(_product(lists, path), fields, path, ["overtake"])


def roar_py_entries() -> typing.List[str]:
    """The competition entries written here: scripts/roar_py_competition.py's, the one list of them."""
    import importlib.util
    import roar_paths
    script = roar_paths.package_root() / "scripts" / "roar_py_competition.py"
    spec = importlib.util.spec_from_file_location("roar_py_competition", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return sorted(module.ENTRIES)


def _roar_py_cells(fields: dict, path: str) -> typing.List[dict]:
    entries = _as_list(_required(fields, "entries", path), path, "entries", str)
    known = roar_py_entries()
    for e in entries:
        if e not in known:
            raise MatrixError(f"{path}: entries: {e!r} is not an entry (scripts/roar_py_competition.py has "
                              f"{', '.join(known)})")
    cameras = _as_list(fields.get("camera", RUNNER_CAMERA), path, "camera", str)
    for c in cameras:
        size = c.split("x")
        if len(size) != 2 or not all(v.isdigit() and 0 < int(v) <= 8192 for v in size):
            raise MatrixError(f"{path}: camera: {c!r} is not WIDTHxHEIGHT")
    return _product({"entry": entries,
                     "map": _as_list(_required(fields, "maps", path), path, "maps", str),
                     "laps": _as_list(fields.get("laps", 3), path, "laps", int, 1, 100),
                     "camera": cameras,
                     "max_seconds": _as_list(fields.get("max_seconds", 1200.0), path, "max_seconds", float, 1.0,
                                             86400.0)}, path)


def _shipped_or_file(name: str, folder: str, what: str) -> str:
    """`name` as a file, or the name of one in the package's `folder` (roar_paths.layout); FileNotFoundError."""
    import roar_paths
    if os.path.isfile(name):
        return os.path.abspath(name)
    shipped = roar_paths.layout()[folder] / f"{name}.yaml"
    if shipped.is_file():
        return str(shipped)
    raise FileNotFoundError(f"{what} {name!r} is neither a file nor one of config/{folder}")


def policy_file(name: str) -> str:
    """A policy as a matrix names it: a file (rl_train's or roar_rl_ppo.py's policy.yaml), or the name of one
    in the package's config/policies."""
    return _shipped_or_file(name, "policies", "policy")


def env_file(name: str) -> str:
    """An environment options file, or the name of one in the package's config/rl (state)."""
    return _shipped_or_file(name, "rl", "env")


def _policy_cells(fields: dict, path: str) -> typing.List[dict]:
    """Trained policies' laps from the pole position: each policy file on each map in each car."""
    import roar_paths
    policies = _as_list(_required(fields, "policies", path), path, "policies", str)
    envs = _as_list(fields.get("env", "state"), path, "env", str)
    for field, names, find in (("policies", policies, policy_file), ("env", envs, env_file)):
        for name in names:
            try:
                find(name)
            except FileNotFoundError as e:
                raise MatrixError(f"{path}: {field}: {e}") from None
    return _product({"policy": policies,
                     "map": _as_list(_required(fields, "maps", path), path, "maps", str),
                     "model": _as_list(fields.get("models", roar_paths.default_model()), path, "models", str),
                     "laps": _as_list(fields.get("laps", 2), path, "laps", int, 1, 100),
                     "env": envs,
                     "max_seconds": _as_list(fields.get("max_seconds", 600.0), path, "max_seconds", float, 1.0,
                                             36000.0)}, path)
