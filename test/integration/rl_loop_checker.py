#!/usr/bin/env python3
"""rostest: the rospy example (scripts/rl_random_agent.py) runs 200 steps against roar_sim; what it observes
lies in the published spaces, each step's outcome and images carry the step's stamp, resets with one seed
start the same episode, driving forward is rewarded, and a step of many ticks delivers every tick's
observation and outcome to a listener that lags."""
import math
import os
import sys
import threading
import time
import unittest

import numpy as np
import rospkg
import rospy
import rostest

sys.path.insert(0, os.path.join(rospkg.RosPack().get_path("roar_ros"), "scripts"))
import rl_random_agent  # noqa: E402
from roar_ros.msg import EpisodeStep, Observation, VehicleControl  # noqa: E402
from roar_ros.srv import Step  # noqa: E402

ACTION_KEYS = ["brake", "hand_brake", "reverse", "steer", "throttle"]


class RlLoop(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.history, cls.env = rl_random_agent.run(200, "agent", seed=3, log_every=0)

    def test_1_two_hundred_steps_in_the_spaces(self):
        self.assertEqual(len(self.history), 200)
        self.assertEqual(list(self.env.action_space), ACTION_KEYS)
        self.assertEqual(self.env.action_space["steer"].low.tolist(), [-1.0])
        self.assertEqual(self.env.cameras, ["front_depth", "front_rgb", "front_semantic"])
        previous = None
        for i, (obs, reward, terminated, truncated, info) in enumerate(self.history):
            for key, space in self.env.observation_space.items():
                self.assertIn(key, obs, "step %d" % i)
                self.assertTrue(space.contains(obs[key]), "step %d: %s = %s" % (i, key, obs[key]))
                self.assertEqual(obs[key].dtype, space.dtype)
            self.assertEqual(obs["camera/front_rgb"].shape, (84, 84, 3))
            self.assertEqual(obs["camera/front_depth"].dtype, np.float32)
            self.assertTrue(math.isfinite(reward))
            if previous is not None and not (previous[2] or previous[3]):
                self.assertAlmostEqual((info["stamp"] - previous[4]["stamp"]).to_sec(), 0.05, places=6)
            previous = (obs, reward, terminated, truncated, info)

    def test_2_one_seed_one_start_and_progress_is_rewarded(self):
        first, _ = self.env.reset(seed=42)
        again, _ = self.env.reset(seed=42)
        other, _ = self.env.reset(seed=43)
        key = "waypoints_information/waypoint_10"
        np.testing.assert_array_equal(first[key], again[key])
        self.assertFalse(np.array_equal(first[key], other[key]))
        self.assertLess(float(first["speed"][0]), 0.05, "the car starts at rest")
        total = 0.0
        for _ in range(60):
            steer = float(np.clip(1.5 * math.atan2(first[key][1], first[key][0]), -1, 1))
            action = {"throttle": np.array([0.5]), "steer": np.array([steer]), "brake": np.array([0.0]),
                      "hand_brake": np.array([0.0]), "reverse": np.array([0])}
            first, reward, terminated, truncated, info = self.env.step(action)
            total += reward
            self.assertFalse(terminated or truncated)
        self.assertGreater(info["progress"], 20.0)
        self.assertGreater(total, 10.0 * info["progress"])
        self.assertAlmostEqual(total, info["episode_return"], places=6)

    def test_3_a_step_of_many_ticks_reaches_a_lagging_listener_whole(self):
        # A frame-skipping agent asks for many ticks at once; roar_sim publishes each tick's observation and
        # outcome as it simulates them, faster than this listener (20 ms a message) takes them.
        ticks = 100
        stamps = {"observation": set(), "step": set()}
        lock = threading.Condition()

        def slow_listener(kind):
            def keep(msg):
                time.sleep(0.02)
                with lock:
                    stamps[kind].add(msg.header.stamp)
                    lock.notify_all()
            return keep

        subscribers = [rospy.Subscriber("/agent/rl/observation", Observation, slow_listener("observation")),
                       rospy.Subscriber("/agent/rl/step", EpisodeStep, slow_listener("step"))]
        deadline = time.time() + 20.0
        while any(s.get_num_connections() == 0 for s in subscribers) and time.time() < deadline:
            time.sleep(0.05)
        self.env.reset(seed=7)
        step = rospy.ServiceProxy("/roar_sim/step", Step)
        answer = step(ticks=ticks, vehicle_names=["agent"], controls=[VehicleControl(throttle=0.3)])
        self.assertTrue(answer.success, answer.message)
        last = round(answer.stamp.to_sec(), 3)
        expected = {round(last - 0.05 * k, 3) for k in range(ticks)}

        def of_the_step(kind):
            return {round(s.to_sec(), 3) for s in stamps[kind]} & expected

        with lock:
            lock.wait_for(lambda: all(len(of_the_step(k)) == ticks for k in stamps), 60.0)
            for kind in stamps:
                self.assertEqual(len(of_the_step(kind)), ticks, "%s: %d of the %d ticks' messages arrived"
                                 % (kind, len(of_the_step(kind)), ticks))
        for subscriber in subscribers:
            subscriber.unregister()


if __name__ == "__main__":
    rospy.init_node("rl_loop_checker")
    rostest.rosrun("roar_ros", "rl_loop", RlLoop, sys.argv)
