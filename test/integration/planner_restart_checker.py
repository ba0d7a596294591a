#!/usr/bin/env python3
"""rostest: the planner is shut down (rosnode kill) at t = 20 s of a lockstep race and a new one started
2 s of wall time later, with the parameters the first left on the server. The controller keeps the car on
the road on the last window it had, the new planner's racing line and windows take over, and the race
finishes with both laps and no contact.

With ~restart false (planner_killed.test) the planner is SIGKILLed and never comes back: the controller
waits for its window once, then follows the latched racing line, and the race finishes all the same,
in bounded wall time."""
import os
import signal
import subprocess
import sys
import time
import unittest

import rosnode
import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from race_checker import SimClock, wait_for_results  # noqa: E402


class PlannerRestart(unittest.TestCase):
    def test_the_race_resumes_after_the_planner_restarts(self):
        started = time.time()
        self.assertTrue(SimClock().wait_until(20.0, 120), "the race reaches t = 20 s")
        restart = rospy.get_param("~restart", True)
        if restart:
            killed, _ = rosnode.kill_nodes(["/planner"])
            self.assertEqual(killed, ["/planner"])
            time.sleep(2.0)
            planner = subprocess.Popen(["rosrun", "roar_ros", "planner", "__name:=planner"],
                                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        else:
            pid = int(subprocess.check_output(["pgrep", "-f", "roar_ros/planner __name:=planner"]).split()[0])
            os.kill(pid, signal.SIGKILL)
            planner = subprocess.Popen(["sleep", "0"])
        try:
            results = wait_for_results(rospy.get_param("~output_dir"), started + 270.0)
            self.assertTrue(results, "the race finished after the planner came back")
            self.assertEqual(results["status"], "finished")
            car = results["cars"][0]
            self.assertEqual(car["laps_completed"], 2)
            self.assertEqual(car["barrier_contacts"], 0)
            self.assertEqual(car["track_limit_violations"], 0)
        finally:
            planner.terminate()
            planner.wait(timeout=10)


if __name__ == "__main__":
    rospy.init_node("planner_restart_checker")
    rostest.rosrun("roar_ros", "planner_restart", PlannerRestart, sys.argv)
