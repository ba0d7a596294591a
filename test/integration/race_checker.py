#!/usr/bin/env python3
"""rostest: waits for race_control's results of a two-lap race of the full stack and checks them."""
import os
import sys
import time
import unittest

import rospy
import rostest
import yaml
from roar_ros.msg import RaceStatus

STATUS = []


class RaceLap(unittest.TestCase):
    def test_two_clean_laps(self):
        path = os.path.join(os.environ["ROS_LOG_DIR"], "race_test", "results.yaml")
        deadline = time.time() + 280
        while time.time() < deadline and not rospy.is_shutdown():
            if os.path.exists(path) and os.path.getmtime(path) > START:
                break
            time.sleep(0.5)
        self.assertTrue(os.path.exists(path) and os.path.getmtime(path) > START, "race_control wrote no results")
        time.sleep(0.5)  # let the writer finish
        with open(path) as f:
            results = yaml.safe_load(f)
        self.assertEqual(results["status"], "finished")
        (car,) = results["cars"]
        self.assertEqual(car["name"], "ego")
        self.assertEqual(car["laps_completed"], 2)
        self.assertEqual(car["barrier_contacts"], 0)
        self.assertEqual([lap["lap"] for lap in car["laps"]], [1, 2])
        for lap in car["laps"]:
            self.assertGreater(lap["time_s"], 90.0)   # 4.25 km: faster would mean a short cut
            self.assertLess(lap["time_s"], 150.0)     # the racing stack, not a cautious drive
            self.assertAlmostEqual(sum(lap["sectors_s"]), lap["time_s"], places=6)
        self.assertAlmostEqual(car["best_lap_s"], min(lap["time_s"] for lap in car["laps"]), places=6)
        self.assertEqual(car["position"], 1)
        self.assertEqual(car["penalties_s"], 0.0)
        self.assertEqual(car["incidents"], [])
        with open(os.path.join(os.path.dirname(path), "sectors.csv")) as f:
            self.assertEqual(len(f.read().splitlines()), 1 + 2 * 3)
        # race_control published the race as it went.
        self.assertTrue(STATUS, "no /race_status")
        self.assertEqual(STATUS[-1].cars[0].name, "ego")
        self.assertGreaterEqual(max(s.cars[0].laps_completed for s in STATUS), 1)


if __name__ == "__main__":
    START = time.time()
    rospy.init_node("race_checker", anonymous=True)
    rospy.Subscriber("/race_status", RaceStatus, STATUS.append)
    rostest.rosrun("roar_ros", "race_lap", RaceLap, sys.argv)
