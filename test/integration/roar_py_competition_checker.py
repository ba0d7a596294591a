#!/usr/bin/env python3
"""rostest: the ROAR_PY competition runner (scripts/roar_py_competition.py) does its 3 laps of Monza (the
map imported from ROAR_PY's Monza waypoints) with every competition sensor reading, respawning after hard
collisions; the result goes to $ROS_HOME/roar_py_competition.yaml for the README."""
import asyncio
import os
import sys
import unittest

import rospkg
import rospy
import rostest
import yaml

sys.path.insert(0, os.path.join(rospkg.RosPack().get_path("roar_ros"), "scripts"))
import roar_py_competition  # noqa: E402


class Competition(unittest.TestCase):
    def test_three_laps_of_monza(self):
        rospy.init_node("roar_py_competition_checker")
        lines = []
        result = asyncio.run(roar_py_competition.run("monza", 3, max_sim_time=2400.0, log=lines.append))
        print("\n".join(lines))
        with open(os.path.join(os.environ.get("ROS_HOME", "/tmp"), "roar_py_competition.yaml"), "w") as f:
            yaml.safe_dump(result, f, sort_keys=False)
        self.assertEqual(result["map"], "Monza")
        self.assertTrue(result["finished"], lines[-1])
        self.assertEqual(len(result["laps"]), 3)
        self.assertEqual(result["sensors"], ["camera", "location", "velocimeter", "rpy", "occupancy_map", "collision"])
        for lap in result["laps"]:
            # 5.6 km at the agent's 20 m/s is 281 s; respawns and corners cost some, a lap cut short would be faster.
            self.assertGreater(lap, 281.0)
            self.assertLess(lap, 600.0)


if __name__ == "__main__":
    rostest.rosrun("roar_ros", "roar_py_competition", Competition)
