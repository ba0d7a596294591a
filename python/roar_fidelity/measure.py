"""Our car measured against CARLA's telemetry, on the same terms: the figures bench/carla_fidelity.py prints
and bench/carla_fit.py fits the car to. CARLA's side comes from the logs; ours from roar_core.World, driven
with the logs' own controls (open loop) or on a long straight (the start and the top speed)."""
import os
import tempfile
import typing

import numpy as np

import roar_paths

from .telemetry import TICK, Telemetry

BAND = 20.0 / 3.6         # m/s: the speed bands the accelerations are grouped in
STRAIGHT_STEER = 0.02     # |steer| of a straight-line tick
FULL = 0.999              # a pedal this far down is floored
WINDOW = 40               # ticks of an open-loop window: 2 s
CORNER_TURN = np.radians(5.0)  # a window whose path turns more is a corner's
COUNTERSTEER = 0.005      # steer (share of lock) x path yaw rate (rad/s) beyond which the wheel is turned out
# The log holds neither the car's heading nor its yaw rate, slip, wheel spin, steering or pedal states: before
# each window the car is held on the logged path for HISTORY ticks (put back each tick where the log has it,
# going its way at its speed) while those states are its own, then let go. A log written by our own car,
# rounded as ROAR's are, replays this way within the open-loop targets, where starting from the locations
# alone does not (test_carla_fidelity test_a_log_our_car_writes_replays_within_the_targets; the figures in
# doc/benchmarks.md).
HISTORY = 40


class Model(typing.NamedTuple):
    """A car model as roar_core.World loads it: a model name or CARLA blueprint and its folders."""
    name: str
    urdf_dir: str
    config_dir: str


def band_of(speed: float) -> int:
    return int(speed // BAND)


def band_label(band: int) -> str:
    return f"{band * 20:.0f}-{band * 20 + 20:.0f}"


def floored_straight(log: Telemetry, i: int, pedal: str) -> bool:
    """Tick i is a straight-line tick with `pedal` ("throttle" or "brake") floored and the other released."""
    other = log.brake if pedal == "throttle" else log.throttle
    return getattr(log, pedal)[i] >= FULL and other[i] == 0 and abs(log.steer[i]) < STRAIGHT_STEER


# ---- CARLA's figures from the logs ------------------------------------------------------------------------

def logged_accelerations(logs: typing.Sequence[Telemetry], pedal: str) -> typing.Dict[int, np.ndarray]:
    """Per speed band, the logged accelerations (m/s^2) of floored_straight ticks, within continuous driving."""
    out: typing.Dict[int, list] = {}
    for log in logs:
        for seg in log.segments():
            for i in seg[:-1]:
                if floored_straight(log, i, pedal):
                    out.setdefault(band_of(log.speed[i]), []).append((log.speed[i + 1] - log.speed[i]) / TICK)
    return {b: np.array(v) for b, v in sorted(out.items())}


def start_figures(speeds: np.ndarray, moved: np.ndarray) -> dict:
    """From a standing start at full throttle, tick 0 the first: ticks before the car moves, speed (km/h)
    after 1, 2, 5, 10 and 20 s, and the time to 100 km/h."""
    first = int(np.argmax(moved)) if moved.any() else len(moved)
    after = {s: speeds[int(round(s / TICK))] * 3.6 for s in (1, 2, 5, 10, 20) if int(round(s / TICK)) < len(speeds)}
    reach = np.where(speeds >= 100 / 3.6)[0]
    return {"still_ticks": first, "after_s": after, "zero_to_100": reach[0] * TICK if len(reach) else float("nan")}


def logged_start(log: Telemetry) -> typing.Optional[dict]:
    """The log's standing start: its first segment, if the car starts it at rest; None if it does not."""
    seg = log.segments()[0]
    if log.speed[seg[0]] > 0.5:
        return None
    moved = np.linalg.norm(log.loc[seg] - log.loc[seg[0]], axis=1) > 0.01
    return start_figures(log.speed[seg], moved)


# ---- our car ---------------------------------------------------------------------------------------------

def drag_strip(folder: str, straight: float = 14000.0, radius: float = 600.0) -> str:
    """A map folder with a flat oval of two long straights, for standing starts and top speed."""
    points = []
    for k in range(int(straight / 5)):
        points.append((k * 5.0, 0.0))
    for k in range(60):
        a = -np.pi / 2 + np.pi * k / 60
        points.append((straight + radius * np.cos(a), radius + radius * np.sin(a)))
    for k in range(int(straight / 5)):
        points.append((straight - k * 5.0, 2 * radius))
    for k in range(60):
        a = np.pi / 2 + np.pi * k / 60
        points.append((radius * np.cos(a), radius + radius * np.sin(a)))
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "centerline.csv"), "w") as f:
        f.write("# x_m,y_m,w_tr_right_m,w_tr_left_m\n")
        for x, y in points:
            f.write(f"{x:.3f},{y:.3f},6,6\n")
    with open(os.path.join(folder, "track.yaml"), "w") as f:
        f.write("name: drag strip\n")
    return folder


def our_standing_start(model: Model, seconds: float = 150.0) -> typing.Tuple[dict, float]:
    """Our car floored from rest on a flat straight: its start figures and its speed (km/h) after `seconds`."""
    import roar_core
    with tempfile.TemporaryDirectory() as tmp:
        world = roar_core.World(drag_strip(os.path.join(tmp, "strip")), tmp)
        world.spawn("ego", model.name, model.urdf_dir, model.config_dir, 0.0, 0.0)
        start = world.state("ego")["position"][:2]
        speeds, moved = [], []
        for _ in range(int(seconds / TICK)):
            world.set_control("ego", throttle=1.0)
            world.step()
            s = world.state("ego")
            speeds.append(s["speed"])
            moved.append(np.linalg.norm(s["position"][:2] - start) > 0.01)
        return start_figures(np.array(speeds), np.array(moved)), speeds[-1] * 3.6


class Window(typing.NamedTuple):
    log: int       # which log
    start: int     # its first tick's index
    turn: float    # rad the logged path turns over the window
    ours: np.ndarray    # (WINDOW, 3): x, y, speed after each tick
    logged: np.ndarray  # (WINDOW, 3): the same, logged


def windows_of(logs: typing.Sequence[Telemetry], stride: int = 25,
               history: int = HISTORY) -> typing.List[typing.Tuple[int, int]]:
    """Window starts every `stride` ticks within continuous driving, `history` ticks into it, the car moving."""
    out = []
    for k, log in enumerate(logs):
        for seg in log.segments():
            for i in range(seg[0] + max(history, 2) + 1, seg[-1] - WINDOW - 2, stride):
                if log.speed[i] > 1.0:
                    out.append((k, i))
    return out


class Replayer:
    """Our car in each logged state, then driven with the logged controls alone (open loop): held on the logged
    path for `history` ticks first (HISTORY), or with history 0 started from the locations alone (its heading
    the direction of travel, its slip and inner states at rest)."""

    def __init__(self, model: Model, map_name: str, maps_dir: str, history: int = HISTORY):
        import roar_core
        self.world = roar_core.World(map_name, maps_dir)
        self.model = model
        self.history = history
        self.spawned = False
        # Per log (by identity, the log kept with it): its smoothed direction of travel and its rate.
        self.motion: typing.Dict[int, typing.Tuple[Telemetry, np.ndarray, np.ndarray]] = {}

    def _control(self, log: Telemetry, i: int) -> None:
        # ROAR_PY's steer is positive right; ours positive left.
        self.world.set_control("ego", log.throttle[i], -log.steer[i], log.brake[i])

    def _start(self, log: Telemetry, i: int, direction: np.ndarray, rate: np.ndarray) -> None:
        w = self.world
        if not self.spawned:
            w.spawn("ego", self.model.name, self.model.urdf_dir, self.model.config_dir, log.loc[i, 0], log.loc[i, 1],
                    0.0, direction[i])
            self.spawned = True
        w.reset("ego", log.loc[i, 0], log.loc[i, 1], 0.0, direction[i])
        self._control(log, i - 1)  # set moving, its pedals' lags settle at the control before
        v = log.speed[i]
        w.set_velocity("ego", (v * np.cos(direction[i]), v * np.sin(direction[i]), 0.0), (0.0, 0.0, rate[i]))

    def _hold(self, log: Telemetry, i: int, direction: np.ndarray) -> None:
        """One tick driven, then the car put where the log has it next, going its way at its speed, its slip kept."""
        w = self.world
        self._control(log, i)
        w.step()
        s = w.state("ego")
        velocity = s["linear_velocity"]
        slip = 0.0
        if np.hypot(velocity[0], velocity[1]) > 0.5:
            slip = np.remainder(s["yaw"] - np.arctan2(velocity[1], velocity[0]) + np.pi, 2 * np.pi) - np.pi
        w.move("ego", log.loc[i + 1, 0], log.loc[i + 1, 1], direction[i + 1] + slip, log.speed[i + 1])

    def window(self, logs: typing.Sequence[Telemetry], k: int, i: int, turned: float = 0.0) -> Window:
        """The window from tick i of log k; with `turned` (rad), the car turned by it when let go (its velocity
        with it, its slip and yaw rate kept): what a start heading that much off makes of the window."""
        log = logs[k]
        if id(log) not in self.motion:
            self.motion[id(log)] = (log, *log.smoothed_motion())
        _, direction, rate = self.motion[id(log)]
        first = i - self.history
        self._start(log, first, direction, rate)
        for j in range(first, i):
            self._hold(log, j, direction)
        if turned:
            s = self.world.state("ego")
            self.world.move("ego", s["position"][0], s["position"][1], s["yaw"] + turned, s["speed"])
        ours = np.zeros((WINDOW, 3))
        for q in range(WINDOW):
            self._control(log, i + q)
            self.world.step()
            s = self.world.state("ego")
            ours[q] = (s["position"][0], s["position"][1], s["speed"])
        logged = np.column_stack([log.loc[i + 1:i + WINDOW + 1], log.speed[i + 1:i + WINDOW + 1]])
        path = log.heading()
        return Window(k, i, abs(path[i + WINDOW] - path[i]), ours, logged)


def window_errors(windows: typing.Sequence[Window]) -> np.ndarray:
    """Per window: final position error (m), final speed error (share of the logged speed), corner (0/1)."""
    return np.array([(np.linalg.norm(w.ours[-1, :2] - w.logged[-1, :2]),
                      abs(w.ours[-1, 2] - w.logged[-1, 2]) / max(w.logged[-1, 2], 1.0),
                      float(w.turn >= CORNER_TURN)) for w in windows])


def steering_travel(windows: typing.Sequence[Window], logs: typing.Sequence[Telemetry]) -> np.ndarray:
    """Per window: how far the logged steering moved over it (the sum of its changes tick to tick)."""
    return np.array([np.abs(np.diff(logs[w.log].steer[w.start:w.start + WINDOW])).sum() for w in windows])


def countersteering(windows: typing.Sequence[Window], logs: typing.Sequence[Telemetry],
                    history: int = HISTORY) -> np.ndarray:
    """Per window: the share of ticks, over the window or over the history it was held on (the larger), on
    which the logged steering points out of the turn the logged path makes, by more than COUNTERSTEER: CARLA's
    car held in a drift. The log has no heading, so a replay starts a drift with our car's own slip."""
    out = []
    for w in windows:
        log = logs[w.log]
        _, rate = log.smoothed_motion()
        # ROAR_PY's steer is positive right, the path's rate positive left: the same sign is a countersteer.
        against = log.steer * rate > COUNTERSTEER
        out.append(max(against[w.start:w.start + WINDOW].mean(), against[max(0, w.start - history):w.start].mean()))
    return np.array(out)


def our_accelerations(windows: typing.Sequence[Window], logs: typing.Sequence[Telemetry],
                      pedal: str) -> typing.Dict[int, np.ndarray]:
    """Per speed band (the logged speed's, so that both sides count the same ticks), our car's accelerations
    on the ticks logged_accelerations counts, where an open-loop window drove them (the lags settled over its
    history)."""
    out: typing.Dict[int, list] = {}
    for w in windows:
        log = logs[w.log]
        for k in range(WINDOW - 1):
            i = w.start + k + 1
            if floored_straight(log, i, pedal):
                out.setdefault(band_of(log.speed[i]), []).append((w.ours[k + 1, 2] - w.ours[k, 2]) / TICK)
    return {b: np.array(v) for b, v in sorted(out.items())}


def yaw_rates(windows: typing.Sequence[Window]) -> np.ndarray:
    """Per corner window: the path's mean yaw rate (rad/s) over it, logged and ours."""
    def rate(xy):
        d = np.diff(xy, axis=0)
        h = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
        return (h[-1] - h[0]) / ((len(h) - 1) * TICK)
    return np.array([(rate(w.logged[:, :2]), rate(w.ours[:, :2])) for w in windows if w.turn >= CORNER_TURN])


def closed_loop_lap(model: Model, lap: Telemetry, pedals: bool = True, maps_dir: typing.Optional[str] = None) -> dict:
    """The closed-loop check: the time trial's tracker follows the logged lap's path at its speeds, with the
    pedals that drove it fed forward (or, pedals=False, the stack's own speed control on its speeds), an
    out-lap from the grid, then the timed lap. roar_core.follow_recorded_lap's dict, with `lap` its lap time."""
    import roar_core
    maps_dir = maps_dir or str(roar_paths.layout()["maps"])
    r = roar_core.follow_recorded_lap("monza", maps_dir, model.name, model.urdf_dir, model.config_dir, lap.loc,
                                      lap.speed, pedals=(lap.throttle - lap.brake) if pedals else [], laps=1)
    r["lap"] = r["lap_times"][0] if r["lap_times"] else float("nan")
    return r


def _own_telemetry(trace: np.ndarray, rounded: bool) -> Telemetry:
    """A closed_loop_lap trace as a ROAR log pairs it (each row is the state after a tick with the control it was
    stepped with: a tick's state goes with the control sent from it, the next row's); rounded as ROAR's logs
    are (locations to 0.1 m, speeds to 0.001 km/h) or exact."""
    loc, speed = trace[:-1, 1:3].copy(), trace[:-1, 3].copy()
    if rounded:
        loc, speed = np.round(loc, 1), np.round(speed * 3.6, 3) / 3.6
    n = len(speed)
    return Telemetry("own log", np.arange(1, n + 1), loc, trace[1:, 4], trace[1:, 5], -trace[1:, 6], speed,
                     np.ones(n, dtype=int))


def rounding_heading_error(model: Model, lap: Telemetry, maps_dir: typing.Optional[str] = None) -> np.ndarray:
    """Per moving tick of a lap our car drives (closed_loop_lap), how far (rad) the direction of travel the
    bench derives from locations rounded to 0.1 m, as ROAR's logs have them, is from the one it derives from
    the exact locations: how well a ROAR log's locations fix a window's start heading."""
    trace = np.array(closed_loop_lap(model, lap, maps_dir=maps_dir)["trace"])
    exact, _ = _own_telemetry(trace, rounded=False).smoothed_motion()
    rounded, _ = _own_telemetry(trace, rounded=True).smoothed_motion()
    error = np.abs(np.remainder(rounded - exact + np.pi, 2 * np.pi) - np.pi)
    return error[trace[:-1, 3] > 10.0]


def apart(windows: typing.Sequence[Window], others: typing.Sequence[Window]) -> np.ndarray:
    """Per window pair: how far apart (m) their cars end."""
    return np.array([np.linalg.norm(a.ours[-1, :2] - b.ours[-1, :2]) for a, b in zip(windows, others)])


def own_log(model: Model, lap: Telemetry, maps_dir: typing.Optional[str] = None) -> Telemetry:
    """A log our car writes itself, as ROAR's entries write theirs (locations to 0.1 m, speeds to 0.001 km/h, the
    controls it was sent), driving the logged lap with its pedals (closed_loop_lap): what the open-loop bench
    gives for a model that is exactly the car (the bench's floor)."""
    return _own_telemetry(np.array(closed_loop_lap(model, lap, maps_dir=maps_dir)["trace"]), rounded=True)
