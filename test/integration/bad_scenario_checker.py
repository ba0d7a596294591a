#!/usr/bin/env python3
"""rostest: roar_sim, planner, race_control, controller and car_models, started on a bad scenario file or bad
~vehicles, exit at once with an error naming the file or parameter, the field and the problem."""
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


# ~vehicles without a scenario, read by the same reader: what each node says of it.
BAD_VEHICLES = {
    "[{name: ego, modle: sedan}]": "vehicles[0].modle: is not a known key (did you mean 'model'?)",
    "[ego, ego]": "vehicles[1].name: 'ego' is used by another car",
    "[{name: ego, pace: 3}]": "vehicles[0].pace",
}
NODES = ["roar_sim", "planner", "race_control", "controller", "car_models"]


def start(node, name, *args):
    """Runs the node as `name` with the private parameters given; returns its exit code and what it printed."""
    # Found as roslaunch finds it (rosrun looks in the source tree only).
    executable = roslib.packages.find_node("roar_ros", node)[0]
    run = subprocess.run([executable, "__name:=" + name] + list(args),
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=60)
    return run.returncode, run.stdout


class BadScenarios(unittest.TestCase):
    def test_every_node_names_the_problem(self):
        with tempfile.TemporaryDirectory() as folder:
            for name, (text, problem) in BAD.items():
                path = os.path.join(folder, name + ".yaml")
                with open(path, "w") as f:
                    f.write(text)
                for node in NODES:
                    code, output = start(node, "bad_" + node, "_scenario:=" + path)
                    self.assertNotEqual(code, 0, "%s started on %s" % (node, name))
                    self.assertIn(path, output, node)
                    self.assertIn(problem, output, "%s on %s said: %s" % (node, name, output))

    def test_every_node_names_the_problem_of_its_vehicles(self):
        for vehicles, problem in BAD_VEHICLES.items():
            for node in NODES:
                # (a name of its own: the scenario runs left theirs on the parameter server)
                code, output = start(node, "no_scenario_" + node, "_vehicles:=" + vehicles)
                self.assertNotEqual(code, 0, "%s started with vehicles %s" % (node, vehicles))
                self.assertIn("parameter /no_scenario_%s/vehicles: %s" % (node, problem), output,
                              "%s with vehicles %s said: %s" % (node, vehicles, output))


if __name__ == "__main__":
    rospy.init_node("bad_scenario_checker")
    rostest.rosrun("roar_ros", "bad_scenario", BadScenarios, sys.argv)
