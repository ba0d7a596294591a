#!/usr/bin/env python3
"""rostest (issue 17's property test for service requests): every number of roar_sim's and
waypoint_server's requests set to 0, -1, 1e-30, 1e30, 1e300 (the largest float32 for float32 fields),
NaN and inf in turn, and integers to 0, -1 and the int32 extremes. Each request is refused with a
message naming the field, or succeeds; after each, the car still steps with finite odometry, and roar_sim
and waypoint_server still answer."""
import math
import sys
import threading
import time
import unittest

import rospy
import rostest
from geometry_msgs.msg import Point
from roar_ros.msg import DebugShape, VehicleControl
from std_srvs.srv import Trigger
from roar_ros.srv import (DestroyVehicle, DestroyVehicleRequest, DrawDebug, DrawDebugRequest, GetGeolocation,
                          GetGeolocationRequest, GetRoute, GetWorldInfo, GetRouteRequest, GetSpawnPoints, GetSpawnPointsRequest,
                          GetWaypoints, GetWaypointsRequest, LoadMap, LoadMapRequest, ProjectPoint, ProjectPointRequest, ResetVehicle,
                          ResetVehicleRequest, SetStepping, SetSteppingRequest, SetVehicleVelocity,
                          SetVehicleVelocityRequest, SpawnVehicle, SpawnVehicleRequest, Step, StepRequest)

FLOATS = [0.0, -1.0, 1e-30, 1e30, 1e300, float("nan"), float("inf")]
INTS = [0, -1, 2**31 - 1, -2**31]
FLOAT32_MAX = 3.4e38


def set_field(message, path, value):
    *parents, leaf = path.split(".")
    for part in parents:
        message = message[int(part)] if part.isdigit() else getattr(message, part)
    setattr(message, leaf, value)


def proxy(name, srv_type):
    rospy.wait_for_service(name, timeout=30)
    return rospy.ServiceProxy(name, srv_type)


class ServiceInputs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.step = proxy("/roar_sim/step", Step)
        cls.destroy = proxy("/roar_sim/destroy_vehicle", DestroyVehicle)
        cls.tally = {"refused": 0, "accepted": 0}

    def still_alive(self, what):
        """The car steps, its odometry finite; and waypoint_server answers."""
        answer = self.step(ticks=1, vehicle_names=["ego"], controls=[VehicleControl(throttle=0.3)])
        self.assertTrue(answer.success, what + ": " + answer.message)
        odom = answer.vehicles[0].odometry
        p, v = odom.pose.pose, odom.twist.twist
        numbers = [p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z,
                   p.orientation.w, v.linear.x, v.linear.y, v.linear.z, v.angular.x, v.angular.y, v.angular.z]
        self.assertTrue(all(math.isfinite(x) for x in numbers), what + ": odometry not finite")

    def probe(self, service, make, fields, values, named, cleanup=None):
        """Each field of a request from make() at each value: refused naming named(field), or accepted."""
        for field in fields:
            for value in values:
                request = make()
                set_field(request, field, value)
                what = "%s %s = %r" % (service.resolved_name, field, value)
                try:
                    reply = service(request)
                except Exception as e:  # a float32 field cannot carry 1e300: rospy refuses to send it
                    if "pack" not in str(e) and "too large" not in str(e):
                        raise
                    value = math.copysign(FLOAT32_MAX, value)  # a float32 field: its largest value
                    request = make()
                    set_field(request, field, value)
                    what = "%s %s = %r" % (service.resolved_name, field, value)
                    reply = service(request)
                if reply.success:
                    self.tally["accepted"] += 1
                    if cleanup:
                        cleanup()
                else:
                    self.tally["refused"] += 1
                    self.assertIn(named(field), reply.message, what)
                self.still_alive(what)

    def test_1_spawn_and_reset_poses(self):
        spawn = proxy("/roar_sim/spawn_vehicle", SpawnVehicle)

        def at_origin():
            r = SpawnVehicleRequest(name="probe", spawn_point=-1)
            r.pose.orientation.w = 1.0
            return r
        gone = lambda: self.destroy(DestroyVehicleRequest(name="probe"))
        pose_fields = ["pose.position.x", "pose.position.y", "pose.position.z", "pose.orientation.x",
                       "pose.orientation.z", "pose.orientation.w"]
        self.probe(spawn, at_origin, pose_fields, FLOATS, lambda f: "pose", gone)
        self.probe(spawn, at_origin, ["colour.r", "colour.a"], FLOATS, lambda f: "colour", gone)
        self.probe(spawn, lambda: SpawnVehicleRequest(name="probe", spawn_point=5), ["spawn_point"], INTS,
                   lambda f: "spawn_point", gone)
        # A pose that is not a number is refused whichever number it is, the orientation's too.
        for field in pose_fields:
            request = at_origin()
            set_field(request, field, float("nan"))
            self.assertFalse(spawn(request).success, field + " = nan")
        reset = proxy("/roar_sim/reset_vehicle", ResetVehicle)

        def ego_at_origin():
            r = ResetVehicleRequest(name="ego", spawn_point=-1)
            r.pose.orientation.w = 1.0
            return r
        self.probe(reset, ego_at_origin, pose_fields, FLOATS, lambda f: "pose")
        self.probe(reset, lambda: ResetVehicleRequest(name="ego", spawn_point=0), ["spawn_point"], INTS,
                   lambda f: "spawn_point")

    def test_2_velocities_controls_and_stepping(self):
        velocity = proxy("/roar_sim/set_vehicle_velocity", SetVehicleVelocity)
        self.probe(velocity, lambda: SetVehicleVelocityRequest(name="ego"), ["linear.x", "linear.z", "angular.z"],
                   FLOATS, lambda f: f.split(".")[0])
        velocity(SetVehicleVelocityRequest(name="ego"))
        control = lambda: StepRequest(ticks=1, vehicle_names=["ego"], controls=[VehicleControl()])
        self.probe(self.step, control, ["controls.0.throttle", "controls.0.steer", "controls.0.brake"], FLOATS,
                   lambda f: f.split(".")[-1])
        self.probe(self.step, control, ["controls.0.gear"], INTS, lambda f: "gear")
        stepping = proxy("/roar_sim/set_stepping", SetStepping)
        keep = lambda: SetSteppingRequest(mode="step", control_dt=0.05, physics_dt=0.005, real_time_factor=-1.0)
        self.probe(stepping, keep, ["control_dt", "physics_dt", "real_time_factor"], FLOATS, lambda f: f,
                   lambda: stepping(keep()))
        for field in ["control_dt", "physics_dt", "real_time_factor"]:
            request = keep()
            set_field(request, field, float("nan"))
            self.assertFalse(stepping(request).success, field + " = nan is no value to keep")
        request = keep()
        request.real_time_factor = 1e-30
        self.assertFalse(stepping(request).success, "a real_time_factor of 1e-30 stands the simulation still")

    def test_3_geolocation_and_drawing(self):
        geolocation = proxy("/roar_sim/get_geolocation", GetGeolocation)
        self.probe(geolocation, lambda: GetGeolocationRequest(points=[Point()]), ["points.0.x", "points.0.z"], FLOATS,
                   lambda f: "points")
        draw = proxy("/roar_sim/draw_debug", DrawDebug)
        line = lambda: DrawDebugRequest(shapes=[DebugShape(kind="line", points=[Point(), Point(x=1.0)], size=0.1,
                                                            life_time=0.5)])
        self.probe(draw, line, ["shapes.0.points.0.x", "shapes.0.size", "shapes.0.arrow_size", "shapes.0.life_time",
                                "shapes.0.color.r"], FLOATS, lambda f: f.split(".")[-1] if "points" not in f else "points")
        draw(DrawDebugRequest(clear=True))

    def test_4_waypoint_server(self):
        waypoints = proxy("/waypoint_server/get_waypoints", GetWaypoints)
        self.probe(waypoints, lambda: GetWaypointsRequest(from_s=10.0, length=50.0), ["from_s", "length"], FLOATS,
                   lambda f: f)
        spawn_points = proxy("/waypoint_server/get_spawn_points", GetSpawnPoints)
        self.probe(spawn_points, lambda: GetSpawnPointsRequest(kind="grid", count=5), ["count"], INTS, lambda f: f)
        project = proxy("/waypoint_server/project_point", ProjectPoint)
        self.probe(project, lambda: ProjectPointRequest(point=Point(), yaw=0.0), ["point.x", "point.y", "yaw"], FLOATS,
                   lambda f: f.split(".")[0])
        route = proxy("/waypoint_server/get_route", GetRoute)

        def start_to_goal():
            r = GetRouteRequest()
            r.start.orientation.w = r.goal.orientation.w = 1.0
            r.goal.position.x = 50.0
            return r
        self.probe(route, start_to_goal, ["start.position.x", "goal.position.y"], FLOATS, lambda f: f.split(".")[0])

    @classmethod
    def tearDownClass(cls):
        print("service property test: %(refused)d requests refused by name, %(accepted)d accepted, the car "
              "finite after every one" % cls.tally)


    def test_5_no_file_is_read_on_a_callers_say_so(self):
        """A caller names a sensor set in roar_sim's folder; a path is refused with the same answer whether the
        file exists or not, and nothing of a file is echoed."""
        spawn = proxy("/roar_sim/spawn_vehicle", SpawnVehicle)
        replies = {}
        for asked in ["/etc/passwd", "/etc/no_such_file", "../../../../etc/passwd", "default.yaml"]:
            reply = spawn(SpawnVehicleRequest(name="leak", sensor_set=asked, spawn_point=12))
            self.assertFalse(reply.success, asked)
            self.assertNotIn("root", reply.message, asked)
            replies[asked] = reply.message.replace(asked, "<asked>")
        self.assertEqual(len(set(replies.values())), 1, replies)
        self.assertIn("sensor_set: no sensor set", replies["/etc/passwd"])
        # A map is a folder holding a track.yaml: any other path is refused alike, reading nothing.
        load = proxy("/roar_sim/load_map", LoadMap)
        for asked in ["/etc", "/etc/passwd", "/no/such"]:
            reply = load(LoadMapRequest(map=asked))
            self.assertFalse(reply.success, asked)
            self.assertIn("unknown map '%s': not a map folder" % asked, reply.message)
        self.still_alive("after the refused paths")

    def test_6_a_long_step_stays_answerable(self):
        """Between the ticks of a long step the services answer: reading ones as usual, those that change the
        world refused as busy; /roar_sim/cancel_step ends it early. More than an hour at 20 Hz is refused."""
        too_long = self.step(StepRequest(ticks=72001, vehicle_names=["ego"], controls=[VehicleControl()]))
        self.assertFalse(too_long.success)
        self.assertIn("ticks must be in [0, 72000]", too_long.message)
        long_step = rospy.ServiceProxy("/roar_sim/step", Step)
        replies = []
        worker = threading.Thread(target=lambda: replies.append(
            long_step(StepRequest(ticks=72000, vehicle_names=["ego"], controls=[VehicleControl(brake=1.0)]))))
        info = proxy("/roar_sim/get_world_info", GetWorldInfo)
        before = info().tick
        worker.start()
        time.sleep(1.0)
        started = time.monotonic()
        answer = info()
        self.assertLess(time.monotonic() - started, 5.0, "get_world_info waited for the step")
        self.assertTrue(worker.is_alive(), "the step is still running")
        self.assertGreater(answer.tick, before, "answered between the step's ticks")
        spawn = proxy("/roar_sim/spawn_vehicle", SpawnVehicle)
        busy = spawn(SpawnVehicleRequest(name="second", spawn_point=3))
        self.assertFalse(busy.success)
        self.assertIn("a step of 72000 ticks is running", busy.message)
        self.assertIn("/roar_sim/cancel_step", busy.message)
        cancel = proxy("/roar_sim/cancel_step", Trigger)
        self.assertTrue(cancel().success)
        worker.join(timeout=30)
        self.assertFalse(worker.is_alive(), "cancel_step ended the step")
        self.assertTrue(replies[0].success, replies[0].message)
        self.assertIn("cancelled after", replies[0].message)
        self.assertLess(replies[0].tick - before, 72000)
        self.assertFalse(cancel().success, "no step is running")
        self.still_alive("after a cancelled step")


if __name__ == "__main__":
    rospy.init_node("service_inputs_checker")
    rostest.rosrun("roar_ros", "service_inputs", ServiceInputs, sys.argv)
