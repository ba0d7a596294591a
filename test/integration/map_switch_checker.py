#!/usr/bin/env python3
"""rostest: a map loaded in the middle of a race (/roar_sim/load_map, cars respawned) reaches every node
with none restarted: waypoint_server serves the new map, the planner plans its racing line, race_control
writes the interrupted race's results (nothing recorded lost) and runs a new race, which the stack's car
laps."""
import math
import os
import sys
import unittest

import rospy
import rostest
import yaml
from roar_ros.msg import MapInfo, RaceStatus, Trajectory, WaypointArray
from roar_ros.srv import ListMaps, LoadMap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import race_checker  # noqa: E402


def wait_for(condition, timeout, what):
    if not race_checker.wait_for(condition, timeout):
        raise AssertionError(f"timed out waiting for {what}")


class MapSwitch(unittest.TestCase):
    def test_a_map_switch_mid_race(self):
        rospy.init_node("map_switch_checker")
        output_dir = rospy.get_param("~output_dir")
        latest = {}
        for topic, cls in (("/race_status", RaceStatus), ("/waypoints", WaypointArray), ("/racing_line", Trajectory),
                           ("/roar_sim/map", MapInfo)):
            rospy.Subscriber(topic, cls, lambda m, t=topic: latest.__setitem__(t, m), queue_size=1)
        wait_for(lambda: "/race_status" in latest and latest["/race_status"].cars
                 and latest["/race_status"].cars[0].laps_completed >= 1, 240, "ego's first lap of Roar Ring")
        laps_before = latest["/race_status"].cars[0].laps_completed
        for car in latest["/race_status"].cars:  # every figure is a number while the race runs
            for field in car.__slots__:
                value = getattr(car, field)
                self.assertFalse(isinstance(value, float) and not math.isfinite(value), f"{car.name}.{field} = {value}")

        bad = rospy.ServiceProxy("/roar_sim/load_map", LoadMap)(map="no_such_map", respawn_vehicles=True)
        self.assertFalse(bad.success)
        self.assertIn("roar_sprint", bad.message, "an unknown map lists the maps there are")
        reply = rospy.ServiceProxy("/roar_sim/load_map", LoadMap)(map="roar_sprint", respawn_vehicles=True)
        self.assertTrue(reply.success, reply.message)
        self.assertEqual(reply.name, "Roar Sprint")

        wait_for(lambda: latest.get("/roar_sim/map") and latest["/roar_sim/map"].generation == 1, 30, "/roar_sim/map")
        self.assertEqual(latest["/roar_sim/map"].reason, "load")
        wait_for(lambda: latest.get("/waypoints") and latest["/waypoints"].map_name == "Roar Sprint", 30,
                 "waypoint_server's waypoints of Roar Sprint")
        self.assertEqual(rospy.ServiceProxy("/waypoint_server/list_maps", ListMaps)().current, "Roar Sprint")
        wait_for(lambda: latest.get("/racing_line") and latest["/racing_line"].map_name == "Roar Sprint", 60,
                 "the planner's racing line of Roar Sprint")

        results = os.path.join(output_dir, "interrupted_1", "results.yaml")
        wait_for(lambda: os.path.exists(results), 30, results)
        with open(results) as f:
            interrupted = yaml.safe_load(f)
        self.assertEqual(interrupted["status"], "interrupted")
        self.assertEqual(interrupted["map"], "Roar Ring")
        self.assertGreaterEqual(interrupted["cars"][0]["laps_completed"], laps_before, "nothing recorded is lost")
        self.assertTrue(os.path.exists(os.path.join(output_dir, "interrupted_1", "laps.csv")))

        wait_for(lambda: latest["/race_status"].map_name == "Roar Sprint", 30, "race_control's race on Roar Sprint")
        wait_for(lambda: latest["/race_status"].cars[0].laps_completed >= 1, 240, "ego's first lap of Roar Sprint")
        lap = latest["/race_status"].cars[0].last_lap
        self.assertGreater(lap, 55.0)
        self.assertLess(lap, 80.0, "a clean lap of Roar Sprint (the stack's is 63 s)")


if __name__ == "__main__":
    rostest.rosrun("roar_ros", "map_switch", MapSwitch)
