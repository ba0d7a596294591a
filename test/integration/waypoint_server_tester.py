#!/usr/bin/env python3
"""rostest: waypoint_server on Roar Ring publishes its latched topics and answers every service; another on
Roar Hillclimb (in namespace course) publishes a point-to-point course and routes only forwards along it."""
import math
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import Point, Pose, PoseArray
from nav_msgs.msg import Path
from roar_ros.msg import WaypointArray
from roar_ros.srv import GetRoute, GetSpawnPoints, GetWaypoints, ListMaps, ProjectPoint
from visualization_msgs.msg import MarkerArray


def call(name, srv_type):
    rospy.wait_for_service(name, timeout=30)
    return rospy.ServiceProxy(name, srv_type)


def pose(waypoint):
    """The pose at a waypoint's location, unrotated."""
    p = Pose()
    p.position.x, p.position.y = waypoint.location.x, waypoint.location.y
    p.orientation.w = 1.0
    return p


class WaypointServer(unittest.TestCase):
    def test_latched_topics(self):
        waypoints = rospy.wait_for_message("/waypoints", WaypointArray, timeout=30)
        self.assertEqual(waypoints.map_name, "Roar Ring")
        self.assertEqual(waypoints.header.frame_id, "map")
        self.assertTrue(waypoints.closed)
        self.assertGreater(len(waypoints.waypoints), 1000)
        self.assertAlmostEqual(waypoints.waypoints[0].lane_width, 14.0, places=3)
        path = rospy.wait_for_message("/waypoints/path", Path, timeout=30)
        self.assertEqual(len(path.poses), len(waypoints.waypoints) + 1)
        markers = rospy.wait_for_message("/track/markers", MarkerArray, timeout=30)
        namespaces = {m.ns for m in markers.markers}
        self.assertTrue({"road", "kerbs", "edges", "centre_line", "start_finish", "sectors", "barriers"} <= namespaces)
        kerbs = [m for m in markers.markers if m.ns == "kerbs"][0]
        self.assertEqual(len(kerbs.colors), len(kerbs.points), "a colour per kerb vertex")
        self.assertGreater(len({(c.r, c.g) for c in kerbs.colors}), 1, "red and white stripes")
        spawns = rospy.wait_for_message("/spawn_points", PoseArray, timeout=30)
        self.assertEqual(len(spawns.poses), 20)

    def test_get_waypoints_whole_and_window(self):
        get = call("/waypoint_server/get_waypoints", GetWaypoints)
        whole = get(0.0, 0.0).waypoints
        window = get(100.0, 50.0).waypoints
        self.assertGreater(len(whole), 1000)
        self.assertTrue(20 <= len(window) <= 30, len(window))  # 2 m spacing
        self.assertTrue(all(100.0 < w.s <= 150.0 for w in window))
        wrap = get(whole[-1].s, 20.0).waypoints  # across the end of the centre line
        self.assertLess(wrap[-1].s, 30.0)

    def test_spawn_points(self):
        get = call("/waypoint_server/get_spawn_points", GetSpawnPoints)
        even = get("even", 5)
        self.assertTrue(even.success)
        self.assertEqual(len(even.poses), 5)
        bad = get("random", 5)
        self.assertFalse(bad.success)
        self.assertIn("kind must be", bad.message)
        self.assertFalse(get("grid", 0).success)

    def test_project_point(self):
        project = call("/waypoint_server/project_point", ProjectPoint)
        get = call("/waypoint_server/get_waypoints", GetWaypoints)
        w = get(0.0, 0.0).waypoints[100]
        # 3 m to the left of waypoint 100, heading 0.2 rad off the road.
        left = Point(w.location.x - 3 * math.sin(w.yaw), w.location.y + 3 * math.cos(w.yaw), 0.0)
        r = project(left, w.yaw + 0.2)
        self.assertAlmostEqual(r.lateral_offset, 3.0, delta=0.05)
        self.assertAlmostEqual(r.heading_error, 0.2, delta=0.02)
        self.assertAlmostEqual(r.s, w.s, delta=0.5)
        self.assertTrue(r.on_track)
        far = project(Point(w.location.x - 30 * math.sin(w.yaw), w.location.y + 30 * math.cos(w.yaw), 0.0), w.yaw)
        self.assertFalse(far.on_track)
        self.assertTrue(r.success and far.success)
        for point, yaw, field in [(Point(float("nan"), 0.0, 0.0), 0.0, "point"), (Point(1e300, 0.0, 0.0), 0.0, "point"),
                                  (Point(), float("inf"), "yaw")]:
            refused = project(point, yaw)
            self.assertFalse(refused.success, field)
            self.assertIn(field + " must be finite", refused.message)

    def test_route_goes_forward_round_the_circuit(self):
        route = call("/waypoint_server/get_route", GetRoute)
        get = call("/waypoint_server/get_waypoints", GetWaypoints)
        ws = get(0.0, 0.0).waypoints
        forward = route(pose(ws[100]), pose(ws[200]))
        self.assertAlmostEqual(forward.distance, ws[200].s - ws[100].s, delta=0.5)
        around = route(pose(ws[200]), pose(ws[100]))
        self.assertAlmostEqual(forward.distance + around.distance, ws[-1].s + 2.0, delta=3.0)
        self.assertGreater(len(around.waypoints), len(forward.waypoints))
        self.assertTrue(forward.success and around.success)
        # From nowhere near the track there is no route: refused, saying where it is from.
        nowhere = Pose()
        nowhere.position.x = nowhere.position.y = 5000.0
        refused = route(nowhere, pose(ws[100]))
        self.assertFalse(refused.success)
        self.assertIn("start (5000.0, 5000.0) is off the track", refused.message)
        nan_goal = pose(ws[100])
        nan_goal.position.y = float("nan")
        refused = route(pose(ws[100]), nan_goal)
        self.assertFalse(refused.success)
        self.assertIn("goal (", refused.message)
        self.assertIn("must be finite", refused.message)

    def test_a_course_is_published_open_and_routed_one_way(self):
        waypoints = rospy.wait_for_message("/course/waypoints", WaypointArray, timeout=30)
        self.assertEqual(waypoints.map_name, "Roar Hillclimb")
        self.assertFalse(waypoints.closed)
        self.assertEqual((waypoints.start_s, waypoints.finish_s), (170.0, 1527.0))
        path = rospy.wait_for_message("/course/waypoints/path", Path, timeout=30)
        self.assertEqual(len(path.poses), len(waypoints.waypoints), "no way back from the end to the start")
        route = call("/course/waypoint_server/get_route", GetRoute)
        ws = waypoints.waypoints
        forward = route(pose(ws[100]), pose(ws[600]))
        self.assertTrue(forward.success, forward.message)
        self.assertAlmostEqual(forward.distance, ws[600].s - ws[100].s, delta=0.5)
        backward = route(pose(ws[600]), pose(ws[100]))
        self.assertFalse(backward.success)
        self.assertIn("is behind the start", backward.message)
        self.assertIn("driven one way", backward.message)

    def test_bad_waypoint_requests_are_refused_by_name(self):
        get = call("/waypoint_server/get_waypoints", GetWaypoints)
        for from_s, length, field in [(float("nan"), 10.0, "from_s"), (float("inf"), 10.0, "from_s"),
                                      (0.0, float("nan"), "length")]:
            refused = get(from_s, length)
            self.assertFalse(refused.success, field)
            self.assertTrue(refused.message.startswith(field), refused.message)
            self.assertEqual(len(refused.waypoints), 0)
        whole = get(1e300, float("inf"))  # any finite progress wraps; an infinite length is the whole track
        self.assertTrue(whole.success)
        self.assertEqual(len(whole.waypoints), len(get(0.0, 0.0).waypoints))

    def test_list_maps(self):
        maps = call("/waypoint_server/list_maps", ListMaps)()
        self.assertEqual(maps.current, "Roar Ring")
        self.assertTrue({"roar_ring", "roar_sprint", "roar_speedway"} <= set(maps.maps))


if __name__ == "__main__":
    rospy.init_node("waypoint_server_tester")
    rostest.rosrun("roar_ros", "waypoint_server_queries", WaypointServer, sys.argv)
