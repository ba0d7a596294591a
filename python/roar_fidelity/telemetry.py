"""CARLA's telemetry of ROAR's car: the per-tick logs ROAR competition entries write while racing in CARLA
(one JSON object keyed by tick number, each tick the car's `loc` [x, y], the action sent, `throttle`,
`brake`, `steer` (ROAR_PY's: positive right), and `speed` in km/h). The one reader of such logs."""
import json
import math
import os
import typing

import numpy as np
from scipy.signal import savgol_filter

TICK = 0.05  # s: the official runner's control step (set_control_steps(0.05, 0.005))
MAX_BYTES = 64 * 1024 * 1024
# A jump between ticks this much longer than the speed explains is a respawn or a new run, not driving.
JUMP_TOLERANCE = 0.3  # m
SMOOTHING = 5  # ticks either side the direction of travel is fitted over


class TelemetryError(ValueError):
    """A log that is not CARLA telemetry as ROAR entries write it; the message names the file and tick."""


class Telemetry(typing.NamedTuple):
    name: str
    ticks: np.ndarray     # the log's tick numbers, consecutive
    loc: np.ndarray       # (N, 2) m, ROAR_PY's world frame
    throttle: np.ndarray  # 0..1
    brake: np.ndarray     # 0..1
    steer: np.ndarray     # -1..1, ROAR_PY's: positive right
    speed: np.ndarray     # m/s
    lap: np.ndarray       # the entry's own lap count (0 where it logged none)

    def segments(self) -> typing.List[np.ndarray]:
        """Index runs of continuous driving: split where the car jumps (a respawn, or another run appended)."""
        step = np.linalg.norm(np.diff(self.loc, axis=0), axis=1)
        expected = 0.5 * (self.speed[:-1] + self.speed[1:]) * TICK
        cuts = np.where(np.abs(step - expected) > JUMP_TOLERANCE)[0] + 1
        return np.split(np.arange(len(self.speed)), cuts)

    def heading(self) -> np.ndarray:
        """Direction of travel (rad, unwrapped) from successive locations; the log has no heading."""
        d = np.diff(self.loc, axis=0)
        h = np.arctan2(d[:, 1], d[:, 0])
        return np.unwrap(np.append(h, h[-1]))

    def smoothed_motion(self) -> typing.Tuple[np.ndarray, np.ndarray]:
        """Direction of travel (rad, unwrapped) and its rate (rad/s) at each tick, from a cubic fitted to the
        locations SMOOTHING ticks either side within each run: the locations are rounded to 0.1 m, which in
        one tick's step of 2 m at speed is 3 degrees of direction."""
        direction, rate = np.zeros(len(self.speed)), np.zeros(len(self.speed))
        for seg in self.segments():
            window = 2 * SMOOTHING + 1
            if len(seg) < window:
                direction[seg] = self.heading()[seg]
                continue
            dx = savgol_filter(self.loc[seg, 0], window, 3, deriv=1)
            dy = savgol_filter(self.loc[seg, 1], window, 3, deriv=1)
            direction[seg] = np.unwrap(np.arctan2(dy, dx))
            rate[seg] = savgol_filter(direction[seg], window, 3, deriv=1) / TICK
        return direction, rate

    def lap_indices(self, lap: int) -> np.ndarray:
        return np.where(self.lap == lap)[0]


def _number(path, tick, entry, field, lo, hi):
    value = entry.get(field)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise TelemetryError(f"{path}: tick {tick}: {field} is not a finite number: {value!r}")
    if not lo <= value <= hi:
        raise TelemetryError(f"{path}: tick {tick}: {field} {value} is outside [{lo}, {hi}]")
    return float(value)


def read_telemetry(path: str) -> Telemetry:
    """Reads a log (a regular file of at most 64 MiB); TelemetryError names the file, tick and field."""
    if not os.path.isfile(path):
        raise TelemetryError(f"{path}: not a regular file")
    if os.path.getsize(path) > MAX_BYTES:
        raise TelemetryError(f"{path}: larger than {MAX_BYTES} bytes")
    try:
        with open(path, encoding="utf-8") as f:
            raw = json.load(f)
    except (ValueError, UnicodeDecodeError) as e:
        raise TelemetryError(f"{path}: not JSON: {e}") from None
    if not isinstance(raw, dict) or not raw:
        raise TelemetryError(f"{path}: expected an object of ticks keyed by tick number")
    try:
        order = sorted(raw, key=int)
    except ValueError:
        raise TelemetryError(f"{path}: a key is not a tick number") from None
    ticks = np.array([int(k) for k in order])
    if np.any(np.diff(ticks) != 1):
        gap = int(np.argmax(np.diff(ticks) != 1))
        raise TelemetryError(f"{path}: ticks are not consecutive after tick {ticks[gap]}")
    rows = []
    for key in order:
        entry = raw[key]
        if not isinstance(entry, dict):
            raise TelemetryError(f"{path}: tick {key}: not an object")
        loc = entry.get("loc")
        if not isinstance(loc, list) or len(loc) != 2:
            raise TelemetryError(f"{path}: tick {key}: loc must be [x, y]")
        xy = [_number(path, key, {"loc": c}, "loc", -1e6, 1e6) for c in loc]
        lap = entry.get("lap", 0)
        if isinstance(lap, bool) or not isinstance(lap, int) or lap < 0:
            raise TelemetryError(f"{path}: tick {key}: lap must be a whole number >= 0: {lap!r}")
        rows.append((xy[0], xy[1], _number(path, key, entry, "throttle", 0, 1),
                     _number(path, key, entry, "brake", 0, 1), _number(path, key, entry, "steer", -1, 1),
                     _number(path, key, entry, "speed", 0, 600) / 3.6, lap))
    a = np.array(rows)
    return Telemetry(os.path.basename(path), ticks, a[:, :2], a[:, 2], a[:, 3], a[:, 4], a[:, 5],
                     a[:, 6].astype(int))
