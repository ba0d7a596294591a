#!/usr/bin/env python3
"""rostest: the bag of a race recorded on a loaded machine holds every tick of every per-tick topic of
every car (odom, vehicle_status, joint_states, control, local_trajectory), /clock and /tf, and every
reading of the sensor car (IMU and GNSS at 100 Hz, three cameras and a LiDAR at 20 Hz), each once, from
tick 0 to the finish; and the bag ends with the race."""
import sys
import time
import unittest

import rosbag
import rospy
import rostest

from race_checker import wait_for_bag

TICK = 0.05


def stamp_of(topic, msg):
    if topic == "/clock":
        return msg.clock.to_sec()
    if topic == "/tf":
        return msg.transforms[0].header.stamp.to_sec()
    return msg.header.stamp.to_sec()


class RecordUnderLoad(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.path = wait_for_bag(rospy.get_param("~output_dir"), START)
        cls.stamps, cls.finish = {}, None
        if not cls.path:
            return
        with rosbag.Bag(cls.path) as bag:
            for topic, msg, _ in bag.read_messages():
                if topic == "/race_status":
                    if msg.finished and cls.finish is None:
                        cls.finish = msg.header.stamp.to_sec()
                    continue
                if topic == "/tf" and not any(t.child_frame_id.endswith("/base_link") for t in msg.transforms):
                    continue  # the cars' transforms are roar_sim's, one message a tick
                if hasattr(msg, "header") or topic in ("/clock", "/tf"):
                    cls.stamps.setdefault(topic, []).append(stamp_of(topic, msg))

    def setUp(self):
        self.assertIsNotNone(self.path, "no race.bag")
        self.assertIsNotNone(self.finish, "no /race_status saying the race finished in the bag")

    def assert_every_reading(self, topic, period, last):
        """Every reading of `topic` from its first to `last` (s), `period` apart, once each."""
        self.assertIn(topic, self.stamps, topic + " not recorded")
        got = [round(t / period) for t in self.stamps[topic] if t <= last + 1e-6]
        first = got[0]
        self.assertLessEqual(first * period, 0.1, topic + ": its first reading is missing")
        expected = list(range(first, round(last / period) + 1))
        missing = sorted(set(expected) - set(got))
        self.assertEqual(missing, [], "%s: %d readings missing, first at t = %.2f s" %
                         (topic, len(missing), missing[0] * period if missing else 0))
        self.assertEqual(len(got), len(set(got)), topic + ": a reading recorded twice")

    def test_1_every_tick_of_every_car(self):
        last = self.finish
        self.assertGreater(last / TICK, 1000, "a lap of the pace car")
        self.assert_every_reading("/clock", TICK, last)
        self.assert_every_reading("/tf", TICK, last)
        for car in rospy.get_param("~cars"):
            for topic in ("odom", "vehicle_status", "joint_states"):
                self.assert_every_reading("/%s/%s" % (car, topic), TICK, last)
            # A control answers each tick (its odometry's stamp); the planner a window each tick.
            self.assert_every_reading("/%s/control" % car, TICK, last - TICK)
            self.assert_every_reading("/%s/local_trajectory" % car, TICK, last - TICK)

    def test_2_every_sensor_reading(self):
        car, last = rospy.get_param("~sensor_car"), self.finish
        self.assert_every_reading("/%s/imu" % car, 0.01, last)
        self.assert_every_reading("/%s/gnss" % car, 0.01, last)
        for camera in ("front_rgb", "front_depth", "front_semantic"):
            self.assert_every_reading("/%s/camera/%s/image" % (car, camera), TICK, last)
        self.assert_every_reading("/%s/lidar/top_lidar/points" % car, TICK, last)

    def test_3_the_bag_ends_with_the_race(self):
        self.assertLessEqual(max(self.stamps["/clock"]), self.finish + 0.5,
                             "the bag runs on past the finish at t = %.2f s" % self.finish)


if __name__ == "__main__":
    START = time.time()
    rospy.init_node("record_load_checker")
    rostest.rosrun("roar_ros", "record_load", RecordUnderLoad, sys.argv)
