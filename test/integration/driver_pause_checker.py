#!/usr/bin/env python3
"""rostest: the controller, which drives every car, is stopped (SIGSTOP) at t = 2 s of a lockstep race and
continued 12 s of wall time later. The cars are then on the start straight, where roar_sim's safe stop
brings each to rest on the road (one left at the limit into a corner can slide into the barrier:
race_test SafeStop). roar_sim takes its drivers as lost after lockstep_timeout and, with no
driver answering, runs no faster than real time; race_control waits ~driver_grace for them. The drivers
come back in time: the race finishes with every car finished, having lost the time they stood."""
import os
import signal
import subprocess
import sys
import time
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from race_checker import SimClock, wait_for_results  # noqa: E402


class DriverPause(unittest.TestCase):
    def test_a_paused_controller_costs_time_not_the_race(self):
        started = time.time()
        clock = SimClock()
        self.assertTrue(clock.wait_until(2.0, 120), "the race reaches t = 2 s")
        pid = int(subprocess.check_output(["pgrep", "-f", "roar_ros/controller __name:=controller"]).split()[0])
        os.kill(pid, signal.SIGSTOP)
        stopped_at = clock.now
        try:
            time.sleep(12.0)
        finally:
            os.kill(pid, signal.SIGCONT)
        # The race runs at real time: a checker a second late stops the controller a second later, not many.
        self.assertLess(stopped_at, 6.0, "the controller stopped while the cars are on the start straight")
        results = wait_for_results(rospy.get_param("~output_dir"), started + 280.0)
        self.assertTrue(results, "the race finished after the controller continued")
        self.assertEqual(results["status"], "finished")
        for car in results["cars"]:
            self.assertTrue(car["finished"], car)
            self.assertNotIn("retired", car)
            self.assertEqual(car["barrier_contacts"], 0, car)


if __name__ == "__main__":
    rospy.init_node("driver_pause_checker")
    rostest.rosrun("roar_ros", "driver_pause", DriverPause, sys.argv)
