#!/usr/bin/env python3
"""Fits a car model's physical parameters to CARLA's telemetry (the logs bench/carla_fidelity.py reads), in
three stages, each on the open-loop replay bench/carla_fidelity.py measures (our car held on the logged path
for 2 s, then driven with the logged controls alone), and prints the fitted values for
config/vehicles/<model>.yaml and its URDF:

1. longitudinal, on straight stretches: the pedal lags, the brakes' torque and the torque curve (scipy's
   least squares on every tick's speed, robust to the odd stretch where the car slid);
2. the brake pedal's rate limit and the pressure's build (a grid on the full-brake bands), then the standing
   start: the stand's length, the engine's inertia and the clutch (a grid on the first 3 s and the surge);
3. lateral, on every window and the closed-loop lap: tyre friction and stiffnesses, steering curve and
   response, weight distribution, yaw inertia, drive split, roll (scipy's Powell search from the model's
   values, on the position and speed errors at 0.5, 1, 1.5 and 2 s plus the closed-loop lap's time, contacts
   and excursions).

Stages 1 and 2 take a few minutes, stage 3 about an hour on one core. Fit physical parameters only: the car
must stay a car that any map and any controller drive.

    /usr/bin/python3 bench/carla_fit.py [--telemetry DIR] [--lap FILE] [--model carla_model3] [--stage 1 2 3]
        [--evaluations 400]
"""
import argparse
import copy
import glob
import itertools
import os
import re
import sys
import tempfile

import numpy as np
import yaml
from scipy.optimize import least_squares, minimize

import roar_paths
from roar_fidelity import measure, read_telemetry

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRAIGHT = np.radians(3.0)  # a stretch whose path turns less is straight
# The URDF's centre of mass: base_link's <inertial> <origin xyz="x ...">, its x the first group.
COM_ORIGIN = re.compile(r'(<inertial>\s*(?:<!--.*?-->\s*)?<origin xyz=")([-0-9.]+)', flags=re.S)
KNOTS_KMH = np.array([0, 50, 100, 150, 200, 230, 245, 252, 258, 264])  # the torque curve's speeds


class Car:
    """A candidate: the model's YAML and URDF text, written to a folder of its own for roar_core.World."""

    def __init__(self, config: dict, urdf: str, name: str):
        self.config, self.urdf, self.name = config, urdf, name

    def model(self, folder: str) -> measure.Model:
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, self.name + ".yaml"), "w") as f:
            yaml.safe_dump(self.config, f, sort_keys=False)
        with open(os.path.join(folder, self.name + ".urdf"), "w") as f:
            f.write(self.urdf)
        return measure.Model(self.name, folder, folder)

    def wheel(self) -> tuple:
        radius = float(re.search(r'<cylinder radius="([0-9.]+)"', self.urdf).group(1))
        return radius, self.config["gearbox"]["final_drive"] * self.config["gearbox"]["ratios"][0], \
            self.config["gearbox"]["efficiency"]


def replay(car: Car, logs, starts, history: int = measure.HISTORY):
    with tempfile.TemporaryDirectory() as folder:
        player = measure.Replayer(car.model(folder), "monza", str(roar_paths.layout()["maps"]), history)
        return [player.window(logs, k, i) for k, i in starts]


def longitudinal(car: Car, logs) -> Car:
    starts = [(k, i) for k, i in measure.windows_of(logs, 10)
              if abs(logs[k].heading()[i + measure.WINDOW] - logs[k].heading()[i]) < STRAIGHT]
    radius, ratio, efficiency = car.wheel()
    rpm = KNOTS_KMH / 3.6 / radius * ratio * 60 / (2 * np.pi)

    def with_values(p):
        c = copy.deepcopy(car.config)
        c["engine"]["response_time_s"], c["brakes"]["rise_time_s"], c["brakes"]["release_time_s"] = map(float, p[:3])
        c["brakes"]["max_torque_front_nm"] = c["brakes"]["max_torque_rear_nm"] = float(p[3] / 4 * radius)
        c["engine"]["torque_curve_rpm_nm"] = [[float(round(r)), float(f * radius / ratio / efficiency)]
                                             for r, f in zip(rpm, p[4:])]
        c["engine"]["redline_rpm"] = float(round(rpm[-1] + 300))
        return Car(c, car.urdf, car.name)

    def residuals(p):
        return np.concatenate([w.ours[:, 2] - w.logged[:, 2] for w in replay(with_values(p), logs, starts)])

    # Start: the model's own values where it has them (its torque curve on these knots, its lags); else the
    # drive force falling with speed to nothing past the logs' top speed and 37 kN of brakes.
    e, b = car.config["engine"], car.config["brakes"]
    curve = np.array(e.get("torque_curve_rpm_nm", [[0.0, 0.0]]), float)
    force = np.interp(rpm, curve[:, 0], curve[:, 1]) * ratio * efficiency / radius
    if len(curve) < 2 or not np.any(force > 0):
        force = np.interp(KNOTS_KMH, [0, 250, 264], [8500, 4800, 0])
    p0 = np.r_[e.get("response_time_s", 0.25), b.get("rise_time_s", 0.25), b.get("release_time_s", 0.5),
               4 * b["max_torque_front_nm"] / radius, force]
    lo = np.r_[0.02, 0.02, 0.02, 20000, np.zeros(len(KNOTS_KMH))]
    hi = np.r_[0.8, 0.8, 1.0, 60000, np.full(len(KNOTS_KMH), 15000.0)]
    fit = least_squares(residuals, np.clip(p0, lo, hi), bounds=(lo, hi),
                        x_scale=np.r_[0.05, 0.05, 0.05, 2000, np.full(len(KNOTS_KMH), 300)],
                        diff_step=2e-2, loss="soft_l1", f_scale=0.3, max_nfev=300)
    print(f"longitudinal: {len(starts)} straight windows, rms speed error {np.sqrt(np.mean(residuals(fit.x) ** 2)):.3f} m/s")
    return with_values(fit.x)


def brake_onset(car: Car, logs) -> Car:
    """The brake pedal's rate limit and the pressure's build (a grid): the full-brake bands' worst error
    against the logs', in bands of 10 samples or more (bench/carla_fidelity.py's figure)."""
    logged = measure.logged_accelerations(logs, "brake")
    starts = measure.windows_of(logs, measure.WINDOW)
    best = None
    for rate, rise in itertools.product([3.0, 4.0, 5.0, 6.0, 8.0, 10.0], [0.1, 0.15, 0.2, 0.25]):
        c = copy.deepcopy(car.config)
        c["brakes"]["pedal_rate_per_s"], c["brakes"]["rise_time_s"] = rate, rise
        candidate = Car(c, car.urdf, car.name)
        ours = measure.our_accelerations(replay(candidate, logs, starts), logs, "brake")
        errors = [abs(np.median(ours[b]) / np.median(logged[b]) - 1) for b in logged
                  if len(logged[b]) >= 10 and len(ours.get(b, [])) >= 10]
        if errors and (best is None or max(errors) < best[0]):
            best = (max(errors), candidate)
    print(f"brake onset: worst band {best[0]:.1%} at {best[1].config['brakes']['pedal_rate_per_s']}/s and "
          f"{best[1].config['brakes']['rise_time_s']} s")
    return best[1]


def standing_start(car: Car, logs) -> Car:
    target = logs[0].speed[:60] * 3.6
    best = None
    for engage, inertia, clutch in itertools.product([1.5, 1.55], [0.1, 0.15, 0.2, 0.3, 0.4, 0.6], [0.5, 1, 1.5, 2, 4]):
        c = copy.deepcopy(car.config)
        c["gearbox"]["engage_time_s"], c["engine"]["inertia_kg_m2"] = engage, inertia
        c["gearbox"]["clutch_strength_nm_s_per_rad"] = clutch
        candidate = Car(c, car.urdf, car.name)
        with tempfile.TemporaryDirectory() as folder:
            import roar_core
            world = roar_core.World(measure.drag_strip(os.path.join(folder, "strip")), folder)
            model = candidate.model(folder)
            world.spawn("ego", model.name, model.urdf_dir, model.config_dir, 0.0, 0.0)
            speeds = []
            for _ in range(60):
                world.set_control("ego", throttle=1.0)
                world.step()
                speeds.append(world.state("ego")["speed"] * 3.6)
        # The first 3 s, and the surge's first four moving ticks as much again (both as CARLA's log has them).
        surge = slice(31, 35)
        error = np.sqrt(np.mean((np.array(speeds[25:]) - target[25:60]) ** 2)) + \
            np.sqrt(np.mean((np.array(speeds[surge]) - target[surge]) ** 2))
        if best is None or error < best[0]:
            best = (error, candidate)
    print(f"standing start: rms {best[0]:.2f} km/h over the first 3 s and the surge")
    return best[1]


LATERAL = [  # name, low, high
    ("grip", 2.0, 4.0), ("lat_stiff_value", 10, 120), ("lat_stiff_max_load", 1, 8),
    ("log_long_stiff_value", np.log(800), np.log(60000)), ("share_60", 0.3, 1.0), ("share_120", 0.2, 1.0),
    ("steer_response", 0.0, 0.3), ("steer_rate", 1.0, 12.0), ("com_x", -0.45, 0.3), ("izz", 1500, 6000),
    ("front_drive", 0.0, 1.0), ("roll_influence", 0.02, 1.0), ("anti_roll_front", 0, 80000),
    ("anti_roll_rear", 0, 80000)]


def lateral_values(car: Car) -> np.ndarray:
    """The model's own values of LATERAL: where the search starts."""
    c, t = car.config, car.config["tyre"]
    curve = dict((k, v) for k, v in c["steering"]["speed_curve_kmh_share"])
    com_x = float(COM_ORIGIN.search(car.urdf).group(2))
    izz = float(re.search(r'izz="([0-9.]+)"', car.urdf).group(1))
    return np.array([t["grip"], t["carsimed"]["lat_stiff_value"], t["carsimed"]["lat_stiff_max_load"],
                     np.log(t["carsimed"]["long_stiff_value"]), curve[60], curve[120],
                     c["steering"]["response_time_s"], c["steering"]["max_rate_rad_per_s"], com_x, izz,
                     c["drivetrain"]["front_drive_share"], c["suspension"]["roll_influence"],
                     c["suspension"]["anti_roll_front_n_per_m"], c["suspension"]["anti_roll_rear_n_per_m"]])


def with_lateral(car: Car, x) -> Car:
    d = dict(zip([n for n, _, _ in LATERAL], map(float, x)))
    c = copy.deepcopy(car.config)
    t = c["tyre"]
    for key in ("longitudinal", "lateral"):
        t.pop(key, None)
    t.update(curve="carsimed", grip=d["grip"], load_sensitivity=0.0,
             carsimed={"lat_stiff_value": d["lat_stiff_value"], "lat_stiff_max_load": d["lat_stiff_max_load"],
                       "long_stiff_value": float(np.exp(d["log_long_stiff_value"]))})
    c["steering"].update(speed_curve_kmh_share=[[0, 1.0], [20, 0.9], [60, d["share_60"]], [120, d["share_120"]]],
                         response_time_s=d["steer_response"], max_rate_rad_per_s=d["steer_rate"])
    c["drivetrain"]["front_drive_share"] = d["front_drive"]
    c["suspension"].update(roll_influence=d["roll_influence"], anti_roll_front_n_per_m=d["anti_roll_front"],
                           anti_roll_rear_n_per_m=d["anti_roll_rear"])
    urdf = COM_ORIGIN.sub(rf'\g<1>{d["com_x"]:.3f}', car.urdf)
    urdf = re.sub(r'izz="[0-9.]+"', f'izz="{d["izz"]:.0f}"', urdf, count=1)
    return Car(c, urdf, car.name)


def window_cost(windows) -> float:
    total = 0.0
    for w in windows:
        for k in (9, 19, 29, 39):
            e = np.linalg.norm(w.ours[k, :2] - w.logged[k, :2])
            s = abs(w.ours[k, 2] - w.logged[k, 2]) / max(w.logged[k, 2], 1.0) * 25
            total += np.hypot(1, e) + np.hypot(1, s)
    return total / len(windows)


def lap_cost(lap: dict, logged_lap: float) -> float:
    """Per cent of lap time off the log's, twice; three a contact; two a metre beyond half a metre from the edge."""
    if not lap["finished"]:
        return 100.0
    return 200 * abs(lap["lap"] / logged_lap - 1) + 3 * lap["barrier_contacts"] + 2 * max(0.0, lap["worst_offroad"] + 0.5)


def lateral(car: Car, logs, lap_log, evaluations: int) -> Car:
    lo, hi = np.array([l for _, l, _ in LATERAL]), np.array([h for _, _, h in LATERAL])
    starts = measure.windows_of(logs, 25)
    logged_lap = len(lap_log.speed) * measure.TICK

    def cost(u):
        candidate = with_lateral(car, lo + np.clip(u, 0, 1) * (hi - lo))
        try:
            with tempfile.TemporaryDirectory() as folder:
                model = candidate.model(folder)
                player = measure.Replayer(model, "monza", str(roar_paths.layout()["maps"]))
                windows = [player.window(logs, k, i) for k, i in starts]
                lap = measure.closed_loop_lap(model, lap_log)
        except ValueError:  # a candidate that cannot be spawned or driven
            return 1e9
        return window_cost(windows) + lap_cost(lap, logged_lap)

    u0 = np.clip((lateral_values(car) - lo) / (hi - lo), 0, 1)
    fit = minimize(cost, u0, method="Powell", bounds=[(0, 1)] * len(u0),
                   options={"maxfev": evaluations, "xtol": 1e-3, "ftol": 1e-4})
    print(f"lateral: cost {cost(u0):.3f} -> {fit.fun:.3f} over {len(starts)} windows and the lap")
    return with_lateral(car, lo + fit.x * (hi - lo))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--telemetry", default=os.path.join(ROOT, "..", "shared", "fixtures", "carla_telemetry"))
    parser.add_argument("--model", default="carla_model3")
    parser.add_argument("--stage", type=int, nargs="+", default=[1, 2, 3], choices=[1, 2, 3])
    parser.add_argument("--lap", default=os.path.join(ROOT, "test", "data", "carla_telemetry", "monza_lap2_entry_a.json"),
                        help="a log of one whole lap (the closed-loop lap)")
    parser.add_argument("--evaluations", type=int, default=400, help="of the lateral search")
    args = parser.parse_args()
    files = sorted(glob.glob(os.path.join(args.telemetry, "*.json")))
    if not files:
        sys.exit(f"carla_fit: no telemetry (*.json) in {args.telemetry}")
    logs = [read_telemetry(f) for f in files]
    with open(roar_paths.layout()["vehicles"] / (args.model + ".yaml")) as f:
        config = yaml.safe_load(f)
    with open(roar_paths.layout()["urdf"] / (args.model + ".urdf")) as f:
        car = Car(config, f.read(), args.model)
    if 1 in args.stage:
        car = longitudinal(car, logs)
    if 2 in args.stage:
        car = standing_start(brake_onset(car, logs), logs)
    if 3 in args.stage:
        car = lateral(car, logs, read_telemetry(args.lap), args.evaluations)
    print(yaml.safe_dump(car.config, sort_keys=False))
    inertial = re.search(r"<inertial>.*?</inertial>", car.urdf, flags=re.S).group(0)
    print(f"URDF base_link:\n{inertial}")


if __name__ == "__main__":
    main()
