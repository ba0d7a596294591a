#!/usr/bin/env python3
"""rostest: car_models gives every car of the scenario its URDF (painted its colour) and turns roar_sim's
joint states into wheel frames that steer with the car; scripts/race_rviz shows every car."""
import math
import os
import subprocess
import sys
import tempfile
import time
import unittest

import rospkg
import rospy
import rostest
import tf2_ros
import yaml
from roar_ros.msg import VehicleControl, VehicleStatus
from roar_ros.srv import Step
from sensor_msgs.msg import JointState

CARS = ["pace", "ego", "rival", "third"]
PKG = rospkg.RosPack().get_path("roar_ros")


def wall_lookup(buffer, target, source, stamp, seconds):
    """The transform, waiting on the wall clock: tf2's own timeout is in simulated time, which stands still
    between steps, so lookup_transform(..., timeout) never returns when the transform is late."""
    deadline = time.time() + seconds
    while not buffer.can_transform(target, source, stamp):
        if time.time() > deadline:
            raise AssertionError("no transform %s -> %s at %s after %.0f s" % (target, source, stamp, seconds))
        time.sleep(0.02)
    return buffer.lookup_transform(target, source, stamp)


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class CarModels(unittest.TestCase):
    def test_1_every_car_has_its_painted_urdf(self):
        for car in CARS:
            deadline = time.time() + 20
            while time.time() < deadline and not rospy.has_param("/%s/robot_description" % car):
                time.sleep(0.1)
            urdf = rospy.get_param("/%s/robot_description" % car)
            self.assertIn("<robot", urdf, car)
        # The scenario paints the pace car [0.9, 0.75, 0.1] (linear): its body is no longer the URDF's red.
        self.assertNotIn('rgba="0.75 0.05 0.05 1"', rospy.get_param("/pace/robot_description"))

    def test_2_wheel_frames_steer_with_the_car(self):
        status = {}
        rospy.Subscriber("/ego/vehicle_status", VehicleStatus, lambda m: status.update(last=m))
        joints = {}
        rospy.Subscriber("/ego/joint_states", JointState, lambda m: joints.update(last=m))
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        rospy.wait_for_service("/roar_sim/step", timeout=30)
        step = rospy.ServiceProxy("/roar_sim/step", Step)
        left = VehicleControl(throttle=0.3, steer=0.8)
        for _ in range(30):
            self.assertTrue(step(ticks=1, vehicle_names=["ego"], controls=[left]).success)
            time.sleep(0.02)
        deadline = time.time() + 10
        while time.time() < deadline and ("last" not in status or "last" not in joints):
            time.sleep(0.05)
        self.assertIn("last", joints, "roar_sim publishes /ego/joint_states")
        steering = status["last"].steering_angle
        self.assertGreater(steering, 0.1, "steering left")
        stamp = joints["last"].header.stamp
        t = wall_lookup(buffer, "ego/base_link", "ego/steer_front_left", stamp, 20)
        # Ackermann: each front wheel turns by its own angle about the mean the status reports.
        self.assertAlmostEqual(yaw_of(t.transform.rotation), steering, delta=0.25 * steering)
        self.assertGreater(yaw_of(t.transform.rotation), 0.0)
        # The wheel turns about its axle while the car rolls.
        wheel = wall_lookup(buffer, "ego/steer_front_left", "ego/wheel_front_left", stamp, 10)
        self.assertAlmostEqual(wheel.transform.rotation.z, 0.0, places=6)
        self.assertGreater(abs(wheel.transform.rotation.y), 1e-3)
        # Every other car's frames exist too.
        for car in CARS:
            wall_lookup(buffer, car + "/base_link", car + "/wheel_rear_right", rospy.Time(0), 10)

    def test_3_rviz_shows_every_car_and_race_rviz_is_current(self):
        with tempfile.TemporaryDirectory() as folder:
            out = os.path.join(folder, "multi.rviz")
            subprocess.check_call([os.path.join(PKG, "scripts", "race_rviz"), "multi_car", "--output", out])
            with open(out) as f:
                displays = yaml.safe_load(f)["Visualization Manager"]["Displays"]
            models = {d["TF Prefix"]: d["Robot Description"] for d in displays if d["Class"] == "rviz/RobotModel"}
            self.assertEqual(models, {car: car + "/robot_description" for car in CARS})
            plans = [d["Topic"] for d in displays if d["Class"] == "rviz/Path"]
            self.assertEqual(plans, ["/racing_line/path"] + ["/%s/local_path" % car for car in CARS])
            markers = [d["Marker Topic"] for d in displays if d["Class"] == "rviz/MarkerArray"]
            for car in CARS:
                self.assertIn("/%s/manoeuvre" % car, markers, "each car's decision and predictions")
            shipped = os.path.join(folder, "race.rviz")
            subprocess.check_call([os.path.join(PKG, "scripts", "race_rviz"), "time_trial", "--sensors", "default",
                                   "--output", shipped])
            with open(shipped) as a, open(os.path.join(PKG, "rviz", "race.rviz")) as b:
                self.assertEqual(a.read(), b.read(), "rviz/race.rviz is scripts/race_rviz time_trial --sensors default")
        bad = subprocess.run([os.path.join(PKG, "scripts", "race_rviz"), "multi_car", "--follow", "nobody",
                              "--output", "/dev/null"], stderr=subprocess.PIPE, universal_newlines=True)
        self.assertNotEqual(bad.returncode, 0)
        self.assertIn("nobody", bad.stderr)


if __name__ == "__main__":
    rospy.init_node("car_models_checker")
    rostest.rosrun("roar_ros", "car_models", CarModels, sys.argv)
