#!/usr/bin/env python3
"""rostest: the scripted cut-in. This node drives `swerver` (the scenario's car on pole, not the stack's)
round the racing line, at its speeds for ~getaway seconds (so that ego catches it well past the line,
where race_control times both) and at ~speed after, and whenever `ego` has pulled out beside its tail to pass, swerves into
ego's lateral place for ~hold seconds (at most ~swerves times). The stack's car must survive every swerve
by aborting (no contact) and still get by; race_control's results are checked at the end."""
import math
import os
import sys
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from nav_msgs.msg import Odometry
from roar_ros.msg import Trajectory, VehicleControl

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from race_checker import wait_for_results  # noqa: E402

WHEELBASE = 2.875  # m, the sedan's
MAX_STEER = 0.61   # rad at steer = 1 (config/vehicles/sedan.yaml)


class Line:
    """The racing line as arrays, with projection of a point onto it."""

    def __init__(self, msg):
        self.xy = np.array([[p.position.x, p.position.y] for p in msg.points])
        self.yaw = np.array([p.yaw for p in msg.points])
        self.s = np.array([p.s for p in msg.points])
        self.speed = np.array([p.speed for p in msg.points])
        self.length = msg.length

    def project(self, x, y):
        """(index, s, lateral m left of the line) of the nearest point."""
        d = self.xy - np.array([x, y])
        k = int(np.argmin(np.einsum("ij,ij->i", d, d)))
        normal = np.array([-math.sin(self.yaw[k]), math.cos(self.yaw[k])])
        return k, self.s[k], float(np.dot(np.array([x, y]) - self.xy[k], normal))

    def point(self, s, lateral):
        s %= self.length
        k = min(int(np.searchsorted(self.s, s)), len(self.s) - 1)
        normal = np.array([-math.sin(self.yaw[k]), math.cos(self.yaw[k])])
        return self.xy[k] + lateral * normal


def yaw_of(odom):
    q = odom.pose.pose.orientation
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class CutIn(unittest.TestCase):
    def test_the_passing_car_survives_a_cut_in(self):
        speed = rospy.get_param("~speed", 14.0)
        getaway = rospy.get_param("~getaway", 15.0)
        hold = rospy.get_param("~hold", 2.0)
        max_swerves = rospy.get_param("~swerves", 3)
        line_msg = rospy.wait_for_message("/racing_line", Trajectory, timeout=120)
        line = Line(line_msg)
        ego = {}
        swerves = []  # (t, ego's gap behind m, ego's lateral m, swerver's lateral m)
        state = {"lateral": 0.0, "target": 0.0, "until": -1.0, "last": None}
        control = rospy.Publisher("/swerver/control", VehicleControl, queue_size=10)

        ego_seen = threading.Condition()

        def on_ego(odom):
            p = odom.pose.pose.position
            with ego_seen:
                ego["odom"] = odom
                ego["place"] = line.project(p.x, p.y)
                ego_seen.notify_all()

        def drive(odom):
            t = odom.header.stamp.to_sec()
            # ego as it is at this very tick, whichever odometry arrived first: the script runs alike every time.
            with ego_seen:
                ego_seen.wait_for(lambda: "odom" in ego and ego["odom"].header.stamp >= odom.header.stamp, timeout=1.0)
            p = odom.pose.pose.position
            v = odom.twist.twist.linear.x
            k, s, lateral = line.project(p.x, p.y)
            dt = 0.05 if state["last"] is None else max(0.0, t - state["last"])
            state["last"] = t
            if "place" in ego and t > getaway and t > state["until"] and len(swerves) < max_swerves:
                _, ego_s, ego_lateral = ego["place"]
                behind = (s - ego_s) % line.length
                ego_speed = ego["odom"].twist.twist.linear.x
                # ego pulled out beside the swerver's tail, going faster: cut across into its lane.
                if 2.0 < behind < 15.0 and abs(ego_lateral - lateral) > 1.5 and ego_speed > v:
                    state["target"] = ego_lateral
                    state["until"] = t + hold
                    swerves.append((t, behind, ego_lateral, lateral))
            if t > state["until"]:
                state["target"] = 0.0
            # A swerve is a quick move: 3 m/s sideways.
            step = 3.0 * dt
            state["lateral"] += max(-step, min(step, state["target"] - state["lateral"]))
            look = max(8.0, 0.8 * v)
            tx, ty = line.point(s + look, state["lateral"])
            yaw = yaw_of(odom)
            dx, dy = tx - p.x, ty - p.y
            alpha = math.atan2(dy, dx) - yaw
            alpha = math.atan2(math.sin(alpha), math.cos(alpha))
            delta = math.atan2(2.0 * WHEELBASE * math.sin(alpha), math.hypot(dx, dy))
            error = min(line.speed[k], 1e9 if t < getaway else speed) - v
            control.publish(VehicleControl(
                header=odom.header,
                steer=max(-1.0, min(1.0, delta / MAX_STEER)),
                throttle=max(0.0, min(1.0, 0.2 + 0.3 * error)) if error > 0 else 0.0,
                brake=max(0.0, min(1.0, -0.3 * error)) if error < 0 else 0.0))

        rospy.Subscriber("/ego/odom", Odometry, on_ego, queue_size=50)
        rospy.Subscriber("/swerver/odom", Odometry, drive, queue_size=50)
        results = wait_for_results(rospy.get_param("~output_dir"), time.time() + 400)
        self.assertTrue(results, "race_control wrote no results of run %s in %s" % (rospy.get_param("/run_id"),
                                                                                    rospy.get_param("~output_dir")))
        rospy.loginfo("cut_in: swerves %s", swerves)
        self.assertGreaterEqual(len(swerves), 1, "ego never pulled out to pass: nothing was cut into")
        self.assertEqual(results["status"], "finished")
        for car in results["cars"]:
            self.assertEqual(car["car_contacts"], 0, "%s: %s" % (car["name"], car["incidents"]))
            self.assertEqual(car["barrier_contacts"], 0, car["name"])
        passes = [(o["passer"], o["passed"]) for o in results["overtakes"]]
        self.assertIn(("ego", "swerver"), passes, "ego got by after the swerves")
        first_pass = min(o["time_s"] for o in results["overtakes"] if o["passer"] == "ego")
        self.assertGreater(first_pass, swerves[0][0], "the first swerve came before ego was by")


if __name__ == "__main__":
    rospy.init_node("cut_in_driver")
    rostest.rosrun("roar_ros", "cut_in", CutIn, sys.argv)
