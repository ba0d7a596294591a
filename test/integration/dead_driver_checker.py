#!/usr/bin/env python3
"""rostest: the controller is killed with SIGKILL (or, with ~kill: rosnode, shut down as `rosnode kill` does)
in the middle of a lockstep race. roar_sim takes the
driver as lost (its publisher gone, or after lockstep_timeout; once, not every tick) and the race goes on
(no faster than real time, with no driver left); the car, left at speed, is brought to a stop on the road
without touching the barrier, and race_control, its driver not back within ~driver_grace, retires it
("driver lost", as of when it was lost): every car retired and none finished, the race ends aborted."""
import os
import signal
import sys
import time
import unittest
import xmlrpc.client

import rosgraph
import rosnode
import rospy
import rostest
from nav_msgs.msg import Odometry
from roar_ros.msg import RaceStatus

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from race_checker import SimClock, this_runs_results  # noqa: E402


class DeadDriver(unittest.TestCase):
    def test_a_killed_controller_does_not_stall_the_race(self):
        rospy.init_node("dead_driver_checker")
        # race.launch on its own (no output_dir given) writes to a folder of its own under ROS_HOME.
        output_dir = rospy.get_param("/race_control/output_dir")
        self.assertTrue(output_dir.startswith(os.environ.get("ROS_HOME", os.path.expanduser("~/.ros"))), output_dir)
        latest = {}
        clock = SimClock()
        rospy.Subscriber("/ego/odom", Odometry, lambda m: latest.__setitem__("odom", m), queue_size=1)
        rospy.Subscriber("/race_status", RaceStatus, lambda m: latest.__setitem__("status", m), queue_size=1)
        self.assertTrue(clock.wait_until(20.0, 120), "the race reaches t = 20 s")
        speed = latest["odom"].twist.twist.linear.x
        self.assertGreater(speed, 15.0, "the car is at speed when its driver dies")

        if rospy.get_param("~kill", "sigkill") == "rosnode":
            # Shut down as `rosnode kill` does: the node unregisters its publishers on the way out.
            killed, _ = rosnode.kill_nodes(["/controller"])
            self.assertEqual(killed, ["/controller"])
        else:
            uri = rosgraph.Master("/dead_driver_checker").lookupNode("/controller")
            code, _, pid = xmlrpc.client.ServerProxy(uri).getPid("/dead_driver_checker")
            self.assertEqual(code, 1)
            os.kill(pid, signal.SIGKILL)
        killed_at, killed_wall = clock.now, time.time()

        # Not every tick waits the full 5 s lockstep_timeout (0.05 s of race per 5 s): one wait, then the race
        # runs on; 40 s of race in at most 90 s of wall time.
        while clock.now < killed_at + 40.0:
            self.assertLess(time.time() - killed_wall, 90.0,
                            f"the race stalled at t = {clock.now:.2f} s after the driver was killed")
            time.sleep(0.1)
        odom = latest["odom"]
        v = odom.twist.twist.linear
        self.assertLess((v.x ** 2 + v.y ** 2) ** 0.5, 0.5, "the car has been brought to a stop")
        ego = next(c for c in latest["status"].cars if c.name == "ego")
        self.assertEqual(ego.barrier_contacts, 0, "stopped on the road, not in the barrier")
        self.assertEqual(ego.track_limit_violations, 0)
        results_path = os.path.join(output_dir, "results.yaml")
        results = None
        while not results:
            self.assertLess(time.time() - killed_wall, 150.0, "race_control wrote results.yaml")
            time.sleep(0.2)
            results = this_runs_results(results_path, rospy.get_param("/run_id"))
        self.assertEqual(results["status"], "aborted", "no car finished: not a result")
        car = results["cars"][0]
        self.assertEqual(car["name"], "ego")
        self.assertEqual(car["retired"], "driver lost")
        self.assertFalse(car["finished"])
        self.assertAlmostEqual(car["retired_at_s"], killed_at, delta=6.0)


if __name__ == "__main__":
    rostest.rosrun("roar_ros", "dead_driver", DeadDriver)
