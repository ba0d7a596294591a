#!/usr/bin/env python3
"""rostest: the race bag holds every tick of the recorded topics, and feeding its controls to a second
roar_sim in step mode reproduces its odometry exactly."""
import sys
import threading
import time
import unittest

import rosbag
import rospy
import rostest
from nav_msgs.msg import Odometry
from race_checker import wait_for_bag
from roar_ros.srv import Step

BAG = None


def state(odom):
    p, q, v, w = odom.pose.pose.position, odom.pose.pose.orientation, odom.twist.twist.linear, odom.twist.twist.angular
    return (p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z)


class RecordResim(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.path = wait_for_bag(rospy.get_param("~output_dir"), START)
        cls.messages = {}
        if cls.path:
            with rosbag.Bag(cls.path) as bag:
                for topic, msg, _ in bag.read_messages():
                    cls.messages.setdefault(topic, []).append(msg)

    def test_1_bag_holds_every_tick(self):
        self.assertIsNotNone(self.path, "no race.bag")
        for topic in ["/clock", "/tf", "/ego/odom", "/ego/control", "/ego/vehicle_status", "/race_status",
                      "/racing_line", "/waypoints", "/track/markers", "/ego/local_trajectory"]:
            self.assertIn(topic, self.messages, topic)
        tick_of = lambda stamp: round(stamp.to_sec() / 0.05)
        recorded_ticks = {
            "/ego/odom": [tick_of(m.header.stamp) for m in self.messages["/ego/odom"]],
            "/ego/vehicle_status": [tick_of(m.header.stamp) for m in self.messages["/ego/vehicle_status"]],
            "/clock": [tick_of(m.clock) for m in self.messages["/clock"]],
            "/ego/joint_states": [tick_of(m.header.stamp) for m in self.messages["/ego/joint_states"]],
            # /tf: the car's transforms of each tick (other nodes' transforms come on their own messages).
            "/tf": [tick_of(m.transforms[0].header.stamp) for m in self.messages["/tf"]
                    if any(tf.child_frame_id.startswith("ego/") for tf in m.transforms)],
        }
        # roar_sim runs on after the race; stopping the recorder cuts its topics between two messages of
        # one tick. Up to the last tick every topic reached, each holds every tick from 0 exactly once.
        ticks = min(t[-1] for t in recorded_ticks.values()) + 1
        self.assertGreater(ticks, 2000, "a whole lap")
        for topic, stamps in recorded_ticks.items():
            self.assertEqual(stamps[:ticks], list(range(ticks)), topic)
            self.assertLessEqual(len(stamps) - ticks, 1, topic + ": at most the cut tick beyond the others")
        odom_stamps = [m.header.stamp for m in self.messages["/ego/odom"]][:ticks]
        # A control answers every tick's odometry (the last one may still be on its way).
        control_stamps = [m.header.stamp for m in self.messages["/ego/control"]][:ticks]
        self.assertEqual(control_stamps, odom_stamps[:len(control_stamps)])
        self.assertGreaterEqual(len(control_stamps), ticks - 1)

    def test_2_resimulation_reproduces_the_odometry(self):
        self.assertIsNotNone(self.path, "no race.bag")
        recorded = {m.header.stamp: m for m in self.messages["/ego/odom"]}
        latest = {}
        arrived = threading.Event()

        def on_odom(msg):
            latest["odom"] = msg
            arrived.set()

        rospy.Subscriber("/resim/ego/odom", Odometry, on_odom, tcp_nodelay=True)
        rospy.wait_for_service("/resim/roar_sim/step", timeout=30)
        step = rospy.ServiceProxy("/resim/roar_sim/step", Step, persistent=True)
        time.sleep(1.0)
        compared = 0
        for control in self.messages["/ego/control"][:1200]:  # the first minute
            arrived.clear()
            answer = step(ticks=1, vehicle_names=["ego"], controls=[control])
            self.assertTrue(answer.success, answer.message)
            self.assertTrue(arrived.wait(10.0))
            while latest["odom"].header.stamp != answer.stamp:
                arrived.clear()
                self.assertTrue(arrived.wait(10.0), "odometry of the step")
            mine, theirs = latest["odom"], recorded[answer.stamp]
            # Bit for bit (a bag's messages are of a class of their own, so compare the numbers).
            self.assertEqual(state(mine), state(theirs), "tick at t = %.2f s" % answer.stamp.to_sec())
            compared += 1
        self.assertEqual(compared, 1200)


if __name__ == "__main__":
    START = time.time()
    rospy.init_node("record_resim_checker")
    rostest.rosrun("roar_ros", "record_resim", RecordResim, sys.argv)
