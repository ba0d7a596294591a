#!/usr/bin/env python3
"""rostest: ROAR_PY's documented examples (test/roar_py_examples/, each changed only where it imports and
creates the CARLA instance) run against the roar_sim of this launch. Endless loops end after a budget of
steps; the checks are on what each example did (its files, what it printed, where its car went)."""
import contextlib
import io
import os
import re
import runpy
import tempfile
import unittest

import numpy as np
import rospkg
import rospy
import rostest

import roar_py_interface
import roar_py_ros
from roar_py_ros.world import RoarPyRosWorld
from roar_ros.srv import LoadMap, SetStepping

EXAMPLES = os.path.join(rospkg.RosPack().get_path("roar_ros"), "test", "roar_py_examples")


class StepBudgetReached(Exception):
    pass


class Harness:
    """Counts world.step() calls (raising StepBudgetReached past the budget), records where every car is
    after each step, and closes every instance an example left open."""

    def __init__(self):
        self.instances = []
        self.budget = None
        self.steps = 0
        self.tracks = {}
        original_init, original_step = roar_py_ros.RoarPyRosInstance.__init__, RoarPyRosWorld.step
        harness = self

        def init(instance, *args, **kwargs):
            original_init(instance, *args, **kwargs)
            harness.instances.append(instance)

        async def step(world):
            if harness.budget is not None and harness.steps >= harness.budget:
                raise StepBudgetReached()
            harness.steps += 1
            dt = await original_step(world)
            for car in world.get_actors():
                harness.tracks.setdefault(car.ros_name, []).append(car.get_3d_location())
            return dt

        roar_py_ros.RoarPyRosInstance.__init__ = init
        RoarPyRosWorld.step = step

    def run(self, example, budget=None):
        """Runs an example in a fresh folder; returns what it printed and whether the budget ended it."""
        self.budget, self.steps, self.tracks = budget, 0, {}
        rospy.ServiceProxy("/roar_sim/set_stepping", SetStepping)(mode="step", control_dt=0.05, physics_dt=0.005,
                                                                   real_time_factor=-1)
        rospy.ServiceProxy("/roar_sim/load_map", LoadMap)(map="roar_ring")
        out = io.StringIO()
        stopped = False
        # The examples draw random spawn points and steering: the same draws every run (with seed 0 the
        # spawning example's random slot is 12, not the slot 1 it spawns its second car on).
        np.random.seed(0)
        self.folder = tempfile.mkdtemp(prefix="roar_py_example_")
        cwd = os.getcwd()
        os.chdir(self.folder)
        try:
            with contextlib.redirect_stdout(out):
                runpy.run_path(os.path.join(EXAMPLES, example), run_name="__main__")
        except StepBudgetReached:
            stopped = True
        finally:
            os.chdir(cwd)
        self.last_world = self.instances[-1].world if self.instances else None
        self.last_cars = list(self.last_world.get_actors()) if self.last_world else []
        return out.getvalue(), stopped

    def close_all(self):
        for instance in self.instances:
            instance.close()
        self.instances = []


class RoarPyExamples(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("roar_py_examples_checker")
        cls.harness = Harness()

    def tearDown(self):
        self.harness.close_all()

    def test_01_rl_loop_with_a_camera(self):
        out, stopped = self.harness.run("ex01_rl_loop.py", budget=300)
        self.assertTrue(stopped, "the loop ran until the step budget")
        # A camera attached without a name has ROAR_PY's CARLA backend's default name.
        self.assertIn("Observation space: Dict('carla_camera': Box(0, 255, (84, 84, 3), uint8))", out)
        self.assertIn("'steer': Box(-1.0, 1.0, (1,), float32)", out)
        track = np.array(self.harness.tracks[self.harness.last_cars[0].ros_name])
        self.assertGreater(np.linalg.norm(track[-1] - track[0]), 20.0, "half throttle moves the car")

    def test_02_instance_set_up_and_stepping_modes(self):
        self.harness.run("ex02_instance_setup.py")
        self.assertTrue(self.harness.instances[-1].is_closed())
        out, _ = self.harness.run("ex02_stepping_modes.py")
        dt = float(re.search(r"Time delta: ([0-9.e-]+) seconds", out).group(1))
        elapsed = float(re.search(r"Total elapsed: ([0-9.e-]+) seconds", out).group(1))
        self.assertGreater(dt, 0.0)
        self.assertGreater(elapsed, dt)

    def test_03_spawn_points_and_spawning(self):
        out, _ = self.harness.run("ex03_spawning.py")
        self.assertIn("Available spawn points: 20", out)
        extent = re.search(r"Vehicle extent: \[([^\]]+)\]", out).group(1).split()
        self.assertAlmostEqual(float(extent[0]), 2.395, places=3)  # CARLA's model3: 4.79 m long

    def test_04_a_car_with_several_sensors(self):
        out, _ = self.harness.run("ex04_sensors.py")
        self.assertIn("Total sensors: 5", out)
        from PIL import Image

        with Image.open(os.path.join(self.harness.folder, "capture.png")) as image:
            self.assertEqual(image.size, (1024, 768))
            self.assertGreater(np.asarray(image).std(), 5.0, "a picture of something")

    def test_05_lidar(self):
        out, _ = self.harness.run("ex05_lidar.py")
        self.assertGreater(int(re.search(r"Number of points: (\d+)", out).group(1)), 500)
        self.assertIn("Channels: 32", out)

    def test_06_actions(self):
        out, _ = self.harness.run("ex06_actions.py")
        self.assertIn("'reverse': MultiBinary(1)", out)

    def test_07_maps(self):
        out, _ = self.harness.run("ex07_maps.py")
        self.assertIn("Roar Speedway roar_py_ros", out)
        self.assertIn("'roar_ring'", out)

    def test_08_waypoints_saved_as_roar_py_files(self):
        self.harness.run("ex08_waypoints.py")
        folder = self.harness.folder
        centre = roar_py_interface.RoarPyWaypoint.load_waypoint_list(np.load(os.path.join(folder, "final_major_map_waypoints.npz")))
        lanes = roar_py_interface.RoarPyWaypoint.load_waypoint_list(np.load(os.path.join(folder, "Monza.npz")))
        self.assertEqual(len(lanes), 2 * len(centre))
        self.assertAlmostEqual(lanes[0].lane_width, centre[0].lane_width / 2, places=6)
        spawns = np.load(os.path.join(folder, "final_major_map_spawn_points.npz"))
        self.assertEqual(spawns["locations"].shape[1], 3)
        self.assertGreaterEqual(len(spawns["locations"]), 10)

    def test_09_geolocation(self):
        out, _ = self.harness.run("ex09_geolocation.py")
        lat, lon, alt = (float(v.rstrip("m")) for v in re.search(r"GPS: (\S+), (\S+), (\S+)", out).groups())
        self.assertTrue(-90 <= lat <= 90 and -180 <= lon <= 180)

    def test_10_the_proportional_controller_follows_the_track(self):
        _, stopped = self.harness.run("ex10_waypoint_follower.py", budget=1200)
        self.assertTrue(stopped)
        world = self.harness.last_world
        track = np.array(self.harness.tracks[self.harness.last_cars[0].ros_name])
        travelled = np.sum(np.linalg.norm(np.diff(track[:, :2], axis=0), axis=1))
        self.assertGreater(travelled, 700.0, "a minute at up to 20 m/s")
        centres = np.array([w.location[:2] for w in world.maneuverable_waypoints])
        half_width = world.maneuverable_waypoints[0].lane_width / 2
        off_centre = [np.min(np.linalg.norm(centres - p[:2], axis=1)) for p in track[::5]]
        self.assertLess(max(off_centre), half_width, "the car stayed on the road")


if __name__ == "__main__":
    rostest.rosrun("roar_ros", "roar_py_examples", RoarPyExamples)
