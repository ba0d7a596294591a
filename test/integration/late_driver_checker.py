#!/usr/bin/env python3
"""rostest: with ~wait_for_drivers, roar_sim in lockstep does not tick before a driver of every driven car
listens; a driver that starts 3 s late answers the tick at t = 0 and drives from there."""
import sys
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from roar_ros.msg import VehicleControl

TICK = 0.05


class LateDriver(unittest.TestCase):
    def test_a_late_driver_hears_the_first_tick(self):
        # Without the wait, lockstep runs a car nobody drives freely: t would be far past 0 by now.
        time.sleep(3.0)
        heard = []
        control = rospy.Publisher("/ego/control", VehicleControl, queue_size=10)

        def answer(odom):
            heard.append(odom)
            if len(heard) <= 40:
                control.publish(VehicleControl(header=odom.header, throttle=1.0))

        rospy.Subscriber("/ego/odom", Odometry, answer, queue_size=50)
        # Well inside the 60 s roar_sim would wait for a driver of the parked car if it waited for one.
        deadline = time.time() + 20
        while time.time() < deadline and len(heard) < 40:
            time.sleep(0.05)
        self.assertGreaterEqual(len(heard), 40, "roar_sim ticks once ego's driver listens, not waiting for parked")
        stamps = [m.header.stamp.to_sec() for m in heard[:40]]
        self.assertEqual(stamps[0], 0.0, "the first tick the driver hears is t = 0")
        for i, stamp in enumerate(stamps):
            self.assertAlmostEqual(stamp, i * TICK, places=6, msg="lockstep: no tick without the driver's answer")
        start, later = heard[0].pose.pose.position, heard[39].pose.pose.position
        self.assertGreater(abs(later.x - start.x) + abs(later.y - start.y), 1.0, "full throttle moved the car")


if __name__ == "__main__":
    rospy.init_node("late_driver_checker")
    rostest.rosrun("roar_ros", "late_driver", LateDriver, sys.argv)
