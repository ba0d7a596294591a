#!/usr/bin/env python3
"""rostest: waits for race_control's results and checks them: every car of ~cars finished ~laps laps
without touching a barrier or another car, lap times within [~min_lap, ~max_lap], sectors adding up, and
race_control published /race_status on the way. The results are this launch's when their run_id is ours,
however early the race ended."""
import os
import sys
import time
import unittest

import rosnode
import rospy
import rostest
import yaml
from roar_ros.msg import RaceStatus, VehicleStatus
from rosgraph_msgs.msg import Clock, Log
from visualization_msgs.msg import Marker, MarkerArray

STATUS = []
LOGGED = []
LEAST_DRAG = {}  # car: the smallest drag_share its vehicle_status reported
MANOEUVRES = {}  # car: (decision texts its /<car>/manoeuvre showed, most points of one predicted car)


def this_runs_results(path, run_id):
    """results.yaml once race_control of this launch has written it at the race's end, else None (the
    results it writes after each lap say status: running)."""
    try:
        with open(path) as f:
            results = yaml.safe_load(f)
    except (OSError, yaml.YAMLError):
        return None
    if not isinstance(results, dict) or results.get("run_id") != run_id or "cars" not in results:
        return None
    if results.get("status") == "running":
        return None
    time.sleep(0.5)  # let the writer finish the rest of the report
    with open(path) as f:
        return yaml.safe_load(f)


def wait_for_results(output_dir, until):
    """This launch's results.yaml in output_dir once race_control has written it, or None at wall time until."""
    path, run_id = os.path.join(output_dir, "results.yaml"), rospy.get_param("/run_id")
    while time.time() < until and not rospy.is_shutdown():
        results = this_runs_results(path, run_id)
        if results:
            return results
        time.sleep(0.5)
    return None


def wait_for_bag(output_dir, since):
    """This launch's race.bag in output_dir once the race is over and the recorder, stopped, has closed it
    (a bag newer than `since`, a time.time()), or None."""
    if wait_for_results(output_dir, time.time() + 250) is None:
        return None
    rosnode.kill_nodes(["/recorder"])
    path = os.path.join(output_dir, "race.bag")
    deadline = time.time() + 60
    while time.time() < deadline and not (os.path.exists(path) and os.path.getmtime(path) > since):
        time.sleep(0.5)
    return path if os.path.exists(path) and os.path.getmtime(path) > since else None


def wait_for(condition, wall_seconds):
    """Whether condition() came true within wall_seconds (polled; false at once when the node shuts down)."""
    deadline = time.time() + wall_seconds
    while not condition():
        if time.time() > deadline or rospy.is_shutdown():
            return False
        time.sleep(0.05)
    return True


class RaceStandings:
    """The standings race_control last published on /race_status (none before the first)."""

    def __init__(self):
        self.status = None
        rospy.Subscriber("/race_status", RaceStatus, self._on_status, queue_size=1)

    def _on_status(self, msg):
        self.status = msg

    def laps_of(self, car):
        """The laps race_control has counted for `car` (0 before it has said)."""
        for standing in self.status.cars if self.status else []:
            if standing.name == car:
                return standing.laps_completed
        return 0

    def wait_for_laps(self, car, laps, wall_seconds):
        """Whether race_control counted `laps` laps of `car` within wall_seconds."""
        return wait_for(lambda: self.laps_of(car) >= laps, wall_seconds)


class SimClock:
    """The simulated time /clock last gave (0 before the first tick)."""

    def __init__(self):
        self.now = 0.0
        rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=1)

    def _on_clock(self, msg):
        self.now = msg.clock.to_sec()

    def wait_until(self, t, wall_seconds):
        """Whether simulated time reached t within wall_seconds."""
        return wait_for(lambda: self.now >= t, wall_seconds)


class RaceResults(unittest.TestCase):
    def test_every_car_finishes_clean(self):
        cars = rospy.get_param("~cars", ["ego"])
        laps = rospy.get_param("~laps", 2)
        min_lap, max_lap = rospy.get_param("~min_lap", 90.0), rospy.get_param("~max_lap", 150.0)
        max_lap_of = rospy.get_param("~max_lap_of", {})  # per car, tighter than max_lap
        expected_passes = rospy.get_param("~passes", [])  # ["passer>passed", ...] that must be in the results
        # Each lap after the second within this share of the second (0: not checked): nothing the stack
        # carries from lap to lap changes how a car drives in clean air.
        lap_repeat = rospy.get_param("~lap_repeat_share", 0.0)
        path = os.path.join(rospy.get_param("~output_dir"), "results.yaml")
        results = wait_for_results(rospy.get_param("~output_dir"), time.time() + 280)
        self.assertTrue(results, "race_control wrote no results of run %s in %s" % (rospy.get_param("/run_id"), path))
        self.assertEqual(results["status"], "finished")
        self.assertEqual(sorted(car["name"] for car in results["cars"]), sorted(cars))
        self.assertEqual(sorted(car["position"] for car in results["cars"]), list(range(1, len(cars) + 1)))
        recorded = {f"{o['passer']}>{o['passed']}" for o in results.get("overtakes", [])}
        for expected in expected_passes:
            self.assertIn(expected, recorded, f"race_control recorded the passes {sorted(recorded)}")
        for car in results["cars"]:
            self.assertEqual(car["laps_completed"], laps, car["name"])
            self.assertEqual(car["barrier_contacts"], 0, car["name"])
            self.assertEqual(car["car_contacts"], 0, car["name"])
            self.assertEqual(car["penalties_s"], 0.0, car["name"])
            self.assertEqual(car["incidents"], [], car["name"])
            self.assertEqual([lap["lap"] for lap in car["laps"]], list(range(1, laps + 1)))
            for lap in car["laps"]:
                self.assertGreater(lap["time_s"], min_lap, car["name"])  # faster would mean a short cut
                self.assertLess(lap["time_s"], max_lap_of.get(car["name"], max_lap), car["name"])
                self.assertAlmostEqual(sum(lap["sectors_s"]), lap["time_s"], places=6)
            self.assertAlmostEqual(car["best_lap_s"], min(lap["time_s"] for lap in car["laps"]), places=6)
            if lap_repeat > 0:
                second = car["laps"][1]["time_s"]
                for lap in car["laps"][2:]:
                    self.assertLess(abs(lap["time_s"] - second), lap_repeat * second,
                                    f"{car['name']}: lap {lap['lap']} {lap['time_s']:.3f} s, lap 2 {second:.3f} s")
            self.assertGreaterEqual(car["time_in_traffic_s"], 0.0, car["name"])
        # Every car that passed another was in traffic behind it first, and race_control said so.
        passers = {o["passer"] for o in results.get("overtakes", [])}
        for car in results["cars"]:
            if car["name"] in passers:
                self.assertGreater(car["time_in_traffic_s"], 0.0, car["name"])
        with open(os.path.join(os.path.dirname(path), "sectors.csv")) as f:
            self.assertEqual(len(f.read().splitlines()), 1 + len(cars) * laps * 3)
        # race_control published the race as it went.
        self.assertTrue(STATUS, "no /race_status")
        self.assertEqual(sorted(c.name for c in STATUS[-1].cars), sorted(cars))
        self.assertGreaterEqual(max(c.laps_completed for s in STATUS for c in s.cars), 1)
        final = {c.name: c for c in STATUS[-1].cars}
        for car in results["cars"]:
            self.assertAlmostEqual(final[car["name"]].time_in_traffic, car["time_in_traffic_s"], delta=0.5)
        # Lines the nodes must have logged on the way (~logged: substrings of /rosout messages).
        for expected in rospy.get_param("~logged", []):
            self.assertTrue(any(expected in line for line in LOGGED), "nothing on /rosout says '%s'" % expected)
        # Cars that must have driven in another's slipstream (~towed): roar_sim's drag_share below 0.9.
        for car in rospy.get_param("~towed", []):
            self.assertLess(LEAST_DRAG.get(car, 1.0), 0.9, "%s never drove in a slipstream" % car)
        # Decisions rviz must have shown (~manoeuvres: {car: text}), each with the predicted cars drawn.
        for car, text in rospy.get_param("~manoeuvres", {}).items():
            texts, most_points = MANOEUVRES.get(car, (set(), 0))
            self.assertTrue(any(t.startswith(text) for t in texts),
                            "/%s/manoeuvre never showed '%s' (showed %s)" % (car, text, sorted(texts)))
            self.assertGreater(most_points, 5, "/%s/manoeuvre drew no predicted car's path" % car)


def on_manoeuvre(car, markers):
    texts, most_points = MANOEUVRES.setdefault(car, (set(), 0))
    for m in markers.markers:
        if m.type == Marker.TEXT_VIEW_FACING:
            texts.add(m.text)
        elif m.type == Marker.LINE_STRIP:
            most_points = max(most_points, len(m.points))
    MANOEUVRES[car] = (texts, most_points)


if __name__ == "__main__":
    rospy.init_node("race_checker", anonymous=True)
    rospy.Subscriber("/race_status", RaceStatus, STATUS.append)
    rospy.Subscriber("/rosout", Log, lambda m: LOGGED.append(m.msg), queue_size=1000)
    for towed in rospy.get_param("~towed", []):
        rospy.Subscriber(
            "/%s/vehicle_status" % towed,
            VehicleStatus,
            lambda m, car=towed: LEAST_DRAG.__setitem__(car, min(LEAST_DRAG.get(car, 1.0), m.drag_share)),
            queue_size=100,
        )
    for watched in rospy.get_param("~manoeuvres", {}):
        rospy.Subscriber("/%s/manoeuvre" % watched, MarkerArray, lambda m, car=watched: on_manoeuvre(car, m),
                         queue_size=100)
    rostest.rosrun("roar_ros", "race_results", RaceResults, sys.argv)
