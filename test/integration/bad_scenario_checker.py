#!/usr/bin/env python3
"""rostest: roar_sim, planner and race_control, started on a bad scenario file, exit at once with an error
naming the file, the field and the problem."""
import os
import subprocess
import sys
import tempfile
import unittest

import roslib.packages
import rospy
import rostest

CAR = "cars:\n  - {name: ego, spawn_point: 0}\n"
BAD = {
    "unknown_map": ("map: monaco\n" + CAR, "map: unknown map 'monaco'"),
    "one_spawn_point": ("map: roar_ring\ncars:\n  - {name: a, spawn_point: 2}\n  - {name: b, spawn_point: 2}\n",
                        "cars[1].spawn_point: 2 is taken by another car"),
    "unknown_sensor": ("map: roar_ring\ncars:\n  - {name: a, sensors: radar}\n", "cars[0].sensors: no sensor set 'radar'"),
    "misspelt_key": ("map: roar_ring\ncars:\n  - {name: a, color: [1, 0, 0]}\n",
                     "cars[0].color: is not a known key (did you mean 'colour'?)"),
}


def start(node, scenario):
    """Runs the node on the scenario; returns its exit code and what it printed."""
    # Found as roslaunch finds it (rosrun looks in the source tree only).
    executable = roslib.packages.find_node("roar_ros", node)[0]
    run = subprocess.run([executable, "__name:=bad_" + node, "_scenario:=" + scenario],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=60)
    return run.returncode, run.stdout


class BadScenarios(unittest.TestCase):
    def test_every_node_names_the_problem(self):
        with tempfile.TemporaryDirectory() as folder:
            for name, (text, problem) in BAD.items():
                path = os.path.join(folder, name + ".yaml")
                with open(path, "w") as f:
                    f.write(text)
                for node in ["roar_sim", "planner", "race_control"]:
                    code, output = start(node, path)
                    self.assertNotEqual(code, 0, "%s started on %s" % (node, name))
                    self.assertIn(path, output, node)
                    self.assertIn(problem, output, "%s on %s said: %s" % (node, name, output))


if __name__ == "__main__":
    rospy.init_node("bad_scenario_checker")
    rostest.rosrun("roar_ros", "bad_scenario", BadScenarios, sys.argv)
