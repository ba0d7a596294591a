#!/usr/bin/env python3
"""rostest: waits for race_control's results of a one-lap race and checks them."""
import os
import sys
import time
import unittest

import rospy
import rostest
import yaml


class RaceLap(unittest.TestCase):
    def test_one_clean_lap(self):
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
        self.assertEqual(car["laps_completed"], 1)
        self.assertEqual(car["barrier_contacts"], 0)
        lap = car["laps"][0]
        self.assertGreater(lap["time_s"], 60.0)   # 4.25 km: faster would mean a short cut
        self.assertLess(lap["time_s"], 300.0)
        self.assertAlmostEqual(sum(lap["sectors_s"]), lap["time_s"], places=6)


if __name__ == "__main__":
    START = time.time()
    rospy.init_node("race_checker", anonymous=True)
    rostest.rosrun("roar_ros", "race_lap", RaceLap, sys.argv)
