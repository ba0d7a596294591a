#!/usr/bin/env python3
"""rostest: planner and controller refuse bad input by name, keep what they had, and the controller brakes
a car whose odometry stops."""
import math
import sys
import threading
import time
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from roar_ros.msg import Trajectory, TrajectoryPoint, VehicleControl, Waypoint, WaypointArray


class StackInputs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.log = []
        cls.controls = []
        cls.lines = []
        cls.lock = threading.Lock()
        rospy.Subscriber("/rosout_agg", Log, cls.on_log)
        rospy.Subscriber("/rosout", Log, cls.on_log)
        rospy.Subscriber("/ego/control", VehicleControl, cls.on_control)
        # Subscribed before anything is planned: a subscription made just as the planner publishes can miss
        # even a latched message.
        racing_line = rospy.Subscriber("/racing_line", Trajectory, cls.on_line)
        cls.waypoints = rospy.Publisher("/waypoints", WaypointArray, queue_size=1, latch=True)
        cls.trajectory = rospy.Publisher("/ego/local_trajectory", Trajectory, queue_size=1, latch=True)
        cls.odom = rospy.Publisher("/ego/odom", Odometry, queue_size=10)
        cls.solo_controls = []
        rospy.Subscriber("/solo/control", VehicleControl, lambda m: cls.solo_controls.append(m))
        cls.solo_odom = rospy.Publisher("/solo/odom", Odometry, queue_size=10)
        cls.solo_window = rospy.Publisher("/solo/local_trajectory", Trajectory, queue_size=10)
        deadline = time.time() + 30
        while time.time() < deadline and (cls.odom.get_num_connections() < 2 or cls.trajectory.get_num_connections() < 1
                                          or cls.waypoints.get_num_connections() < 1
                                          or racing_line.get_num_connections() < 1
                                          or cls.solo_odom.get_num_connections() < 1
                                          or cls.solo_window.get_num_connections() < 1):
            time.sleep(0.1)

    @classmethod
    def on_log(cls, msg):
        with cls.lock:
            cls.log.append(msg.msg)

    @classmethod
    def on_line(cls, msg):
        with cls.lock:
            cls.lines.append(msg)

    @classmethod
    def on_control(cls, msg):
        with cls.lock:
            cls.controls.append(msg)

    def wait_for_log(self, text, timeout=10.0):
        deadline = time.time() + timeout
        while time.time() < deadline:
            with self.lock:
                if any(text in m for m in self.log):
                    return True
            time.sleep(0.05)
        return False

    def wait_for_control(self, predicate, timeout=10.0):
        deadline = time.time() + timeout
        while time.time() < deadline:
            with self.lock:
                found = [c for c in self.controls if predicate(c)]
            if found:
                return found[-1]
            time.sleep(0.05)
        return None

    def circle(self, closed=True):
        msg = WaypointArray(map_name="test ring", closed=closed, friction=1.0)
        for i in range(120):
            a = 2 * math.pi * i / 120
            w = Waypoint(lane_width=12.0, yaw=a + math.pi / 2)
            w.location.x, w.location.y = 100 * math.cos(a), 100 * math.sin(a)
            msg.waypoints.append(w)
        return msg

    # The car and the straight below lie on the test ring of test_1 (heading north at (100, 0)), where the
    # planner's windows for ego are too: whichever window the controller answers with, the car is on it (a
    # car far from its trajectory is braked, not steered at it).
    def odometry(self, stamp, x=0.0):
        msg = Odometry()
        msg.header.stamp = stamp
        msg.header.frame_id = "map"
        msg.pose.pose.position.x = 100.0
        msg.pose.pose.position.y = x
        msg.pose.pose.orientation.z = math.sin(math.pi / 4)
        msg.pose.pose.orientation.w = math.cos(math.pi / 4)
        msg.twist.twist.linear.x = 10.0
        return msg

    def test_1_planner_refuses_waypoints_that_are_no_circuit(self):
        self.waypoints.publish(WaypointArray(map_name="empty", closed=True, friction=1.0))
        self.assertTrue(self.wait_for_log("waypoints on /waypoints refused: the waypoint list is empty"))
        self.waypoints.publish(self.circle(closed=False))
        # An open one is a point-to-point course, whose start and finish lines this one (0, 0) does not place.
        self.assertTrue(self.wait_for_log("a point-to-point course needs its start line"))
        # A good circuit after the bad ones is planned and latched.
        self.waypoints.publish(self.circle())
        deadline = time.time() + 20
        while time.time() < deadline and not self.lines:
            time.sleep(0.05)
        with self.lock:
            self.assertEqual(len(self.lines), 1, "one racing line, for the good circuit only")
            line = self.lines[0]
        self.assertTrue(line.closed)
        self.assertGreater(len(line.points), 100)
        for p in line.points:
            self.assertLess(abs(math.hypot(p.position.x, p.position.y) - 100.0), 6.0 - 0.925 - 0.5 + 0.05)

    def test_2_controller_keeps_its_trajectory_when_sent_nan_and_brakes_without_odometry(self):
        good = self.straight()
        self.trajectory.publish(good)
        time.sleep(0.5)
        stamp = rospy.Time(1000, 0)
        self.odom.publish(self.odometry(stamp))
        answer = self.wait_for_control(lambda c: c.header.stamp == stamp)
        self.assertIsNotNone(answer, "the controller answers odometry with a control of the same stamp")
        self.assertGreater(answer.throttle, 0.5)

        bad = Trajectory(closed=False, length=200.0, points=list(good.points))
        bad.points[3] = TrajectoryPoint(s=3.0, speed=20.0, curvature=float("nan"))
        self.trajectory.publish(bad)
        self.assertTrue(self.wait_for_log("trajectory on /ego/local_trajectory refused: trajectory: point 3 has a non-finite curvature"))
        stamp = rospy.Time(1000, 50000000)
        self.odom.publish(self.odometry(stamp, x=1.0))
        answer = self.wait_for_control(lambda c: c.header.stamp == stamp)
        self.assertIsNotNone(answer)
        self.assertGreater(answer.throttle, 0.5, "still driving on the previous trajectory")

        # Odometry stops: within the timeout (1 s) and a little, the controller brakes and says so.
        stop = self.wait_for_control(lambda c: c.brake == 1.0 and c.throttle == 0.0, timeout=5.0)
        self.assertIsNotNone(stop, "the controller brakes when odometry stops")
        self.assertTrue(self.wait_for_log("no odometry on /ego/odom for 1.0 s: braking 'ego' to a stop"))

    def straight(self, stamp=None):
        line = Trajectory(closed=False, length=200.0)
        for i in range(201):
            line.points.append(TrajectoryPoint(s=float(i), speed=20.0, yaw=math.pi / 2))
            line.points[-1].position.x = 100.0
            line.points[-1].position.y = float(i) - 100.0
        if stamp is not None:
            line.header.stamp = stamp
        return line

    def test_3_controller_answers_a_tick_with_the_window_of_that_tick(self):
        def answered(stamp, timeout):
            deadline = time.time() + timeout
            while time.time() < deadline:
                if any(c.header.stamp == stamp for c in list(self.solo_controls)):
                    return True
                time.sleep(0.02)
            return False

        # The tester plays solo's planner, which answers odometry: its window carries the odometry's stamp.
        t = [rospy.Time(1500, 0), rospy.Time(1500, 50000000), rospy.Time(1500, 100000000)]
        self.solo_odom.publish(self.odometry(t[0]))
        time.sleep(0.2)
        self.solo_window.publish(self.straight(t[0]))
        self.assertTrue(answered(t[0], 5.0), "the first window answers the odometry held for it")
        # The next tick's window is late (a busy planner): the controller waits for it, so a lockstep
        # simulator does not run on with the old window.
        self.solo_odom.publish(self.odometry(t[1], x=1.0))
        self.assertFalse(answered(t[1], 0.5), "no answer before the window of the tick")
        self.solo_window.publish(self.straight(t[1]))
        self.assertTrue(answered(t[1], 2.0), "answered once the window came")
        # A window that never comes: after window_wait (1 s) the tick is answered with the latest, and said.
        sent = time.time()
        self.solo_odom.publish(self.odometry(t[2], x=2.0))
        self.assertTrue(answered(t[2], 5.0))
        self.assertGreater(time.time() - sent, 0.9)
        self.assertTrue(self.wait_for_log("no window on /solo/local_trajectory for t = 1500.10 s after 1.0 s"))

    def test_4_gains_are_tuned_live(self):
        self.trajectory.publish(self.straight())
        client = dynamic_reconfigure.client.Client("/ego_controller", timeout=20)
        client.update_configuration({"max_speed": 5.0})
        self.assertTrue(self.wait_for_log("max 5.000000 m/s"))
        stamp = rospy.Time(2000, 0)
        self.odom.publish(self.odometry(stamp, x=2.0))  # 10 m/s, now twice the cap
        answer = self.wait_for_control(lambda c: c.header.stamp == stamp)
        self.assertIsNotNone(answer)
        self.assertEqual(answer.throttle, 0.0)
        self.assertGreater(answer.brake, 0.5)
        client.update_configuration({"max_speed": 0.0})
        # A law the tracker's table does not know is refused by it, and the gains stay as they were.
        client.update_configuration({"lateral_control": "mpc"})
        self.assertTrue(self.wait_for_log("controller lateral_control 'mpc' is neither pure_pursuit nor stanley; "
                                          "keeping the gains as they were"))
        client.update_configuration({"lateral_control": "pure_pursuit"})


if __name__ == "__main__":
    rospy.init_node("stack_input_tester")
    rostest.rosrun("roar_ros", "stack_inputs", StackInputs, sys.argv)
