#!/usr/bin/env python3
"""rostest: with ~wait_for_listeners, roar_sim does not tick before each named node listens to /clock and
every car's odom; one that starts listening 3 s late hears the tick at t = 0 and the ticks after it."""
import sys
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock


class LateListener(unittest.TestCase):
    def test_a_late_listener_hears_the_first_tick(self):
        # Without the wait, lockstep runs a car nobody drives freely: t would be far past 0 by now.
        time.sleep(3.0)
        clock, odom = [], []
        # The odometry first: roar_sim starts once both are connected, and the clock's first tick must
        # find this node listening to both.
        rospy.Subscriber("/ego/odom", Odometry, lambda m: odom.append(m.header.stamp.to_sec()), queue_size=100)
        rospy.Subscriber("/clock", Clock, lambda m: clock.append(m.clock.to_sec()), queue_size=100)
        deadline = time.time() + 20
        while time.time() < deadline and (len(odom) < 10 or len(clock) < 10):
            time.sleep(0.05)
        self.assertGreaterEqual(len(odom), 10, "roar_sim ticks once the listener listens")
        self.assertEqual(odom[0], 0.0, "the first odometry the listener hears is of t = 0")
        self.assertLessEqual(clock[0], 0.05, "the first clock it hears is the first tick's")


if __name__ == "__main__":
    rospy.init_node("late_listener_checker")
    rostest.rosrun("roar_ros", "late_listener", LateListener, sys.argv)
