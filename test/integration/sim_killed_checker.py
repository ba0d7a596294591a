#!/usr/bin/env python3
"""rostest: roar_sim is killed with SIGKILL once race_control has counted the first lap. race_control must
not call that a race that ran out of time: after sim_silence (10 s of wall time) with no odometry and no
answer from roar_sim, it writes results.yaml with status aborted, keeping the lap already timed."""
import os
import signal
import sys
import time
import unittest
import xmlrpc.client

import rosgraph
import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from race_checker import RaceStandings, wait_for_results  # noqa: E402


class SimKilled(unittest.TestCase):
    def test_a_killed_simulator_gives_an_aborted_race(self):
        # race_control's own count, not the simulated time (once the clock said 70 s with 27 s of race behind
        # it: race_control had come up after the drivers): the lap to be kept is one race_control counted.
        standings = RaceStandings()
        self.assertTrue(standings.wait_for_laps("ego", 1, 150), "race_control counted ego's first lap")
        uri = rosgraph.Master("/sim_killed_checker").lookupNode("/roar_sim")
        code, _, pid = xmlrpc.client.ServerProxy(uri).getPid("/sim_killed_checker")
        self.assertEqual(code, 1)
        os.kill(pid, signal.SIGKILL)
        results = wait_for_results(rospy.get_param("~output_dir"), time.time() + 60.0)
        self.assertTrue(results, "race_control wrote results after roar_sim died")
        self.assertEqual(results["status"], "aborted")
        car = results["cars"][0]
        self.assertEqual(car["name"], "ego")
        self.assertGreaterEqual(car["laps_completed"], 1, "the lap timed before the simulator died is kept")
        self.assertFalse(car["finished"])


if __name__ == "__main__":
    rospy.init_node("sim_killed_checker")
    rostest.rosrun("roar_ros", "sim_killed", SimKilled, sys.argv)
