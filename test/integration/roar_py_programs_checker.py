#!/usr/bin/env python3
"""rostest: ROAR_PY's example programs (test/roar_py_programs/: ROAR_PY's examples with only their CARLA
lines changed) as separate processes against the roar_sim of this launch, their pygame viewers on an Xvfb
display whose keys xdotool holds as a user would, ended by SIGINT (Ctrl-C) as a user ends them. Each test
checks what the program is for: the car goes where its keys or controller send it, the viewer shows the
car (CARLA's chase camera sees the car's own body), the waypoint collector's file, the waypoint plots,
and a remote client driving a car over ROAR_PY's websocket protocol (then clients back to back). Screenshots go to
$ROS_HOME/roar_py_programs/."""
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np
import rospkg
import rospy
import rostest
from PIL import Image

import roar_py_interface
from roar_ros.msg import WaypointArray
from roar_ros.srv import GetWorldInfo, SetStepping, Step

PACKAGE = rospkg.RosPack().get_path("roar_ros")
PROGRAMS = os.path.join(PACKAGE, "test", "roar_py_programs")
VIEWER = "RoarPy Manual Control Viewer"
SHOTS = os.path.join(os.environ.get("ROS_HOME", "/tmp"), "roar_py_programs")


# Clients one after another, each saying goodbye while the next connects (a program that ends as the next
# starts): each finds run_server's spawn point free of the last one's car.
BACK_TO_BACK = """
import asyncio, sys
from roar_py_remote.services.websocket_service import RoarPyWebsocketClientService

async def main(uri, count):
    set_up, goodbyes = 0, []
    for _ in range(count):
        try:
            world = await RoarPyWebsocketClientService.connect_to_server(uri)
            await world.step()
            set_up += 1
            goodbyes.append(asyncio.ensure_future(world.close()))
        except ConnectionError as error:
            print("refused:", error)
    await asyncio.gather(*goodbyes)
    print(f"set up {set_up} of {count}")

asyncio.run(main(sys.argv[1], int(sys.argv[2])))
"""


class Display:
    """An Xvfb display of its own (1280x1024), keys held with xdotool, screenshots with ImageMagick."""

    def __init__(self):
        for number in range(90, 130):
            if not os.path.exists(f"/tmp/.X11-unix/X{number}") and not os.path.exists(f"/tmp/.X{number}-lock"):
                break
        self.name = f":{number}"
        self.process = subprocess.Popen(["Xvfb", self.name, "-screen", "0", "1280x1024x24", "-nolisten", "tcp"],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + 20
        while not os.path.exists(f"/tmp/.X11-unix/X{number}"):
            if time.time() > deadline or self.process.poll() is not None:
                raise RuntimeError(f"Xvfb {self.name} did not start")
            time.sleep(0.1)

    def run(self, *args: str) -> str:
        return subprocess.run(list(args), env={**os.environ, "DISPLAY": self.name}, capture_output=True, text=True,
                              timeout=30).stdout

    def window(self, title: str, timeout: float = 60.0):
        """(x, y, width, height) of the window of a title, once it is there."""
        deadline = time.time() + timeout
        while time.time() < deadline:
            for line in self.run("xwininfo", "-root", "-tree").splitlines():
                if f'"{title}"' in line:
                    size, x, y = line.split()[-2].split("+")
                    width, height = size.split("x")
                    return int(x), int(y), int(width), int(height)
            time.sleep(0.2)
        raise AssertionError(f"no window '{title}' within {timeout:.0f} s")

    def hold(self, window, *keys: str):
        """Holds keys down in a window (the pointer on it: with no window manager, focus follows it)."""
        x, y, width, height = window
        self.run("xdotool", "mousemove", str(x + width // 2), str(y + height // 2))
        for key in keys:
            self.run("xdotool", "keydown", key)

    def release(self, *keys: str):
        for key in keys:
            self.run("xdotool", "keyup", key)

    def screenshot(self, window, path: str) -> np.ndarray:
        self.run("import", "-window", "root", path)
        x, y, width, height = window
        return np.asarray(Image.open(path).convert("RGB"))[y:y + height, x:x + width]

    def close(self):
        self.process.terminate()
        self.process.wait(10)


class Program:
    """A program of test/roar_py_programs run in a folder of its own, its output in out.log there."""

    def __init__(self, name: str, display: Display, **env: str):
        self.name = name
        self.folder = tempfile.mkdtemp(prefix=f"roar_py_{name}_")
        self.log = open(os.path.join(self.folder, "out.log"), "w")
        self.process = subprocess.Popen(
            [sys.executable, os.path.join(PROGRAMS, f"{name}.py")], cwd=self.folder, stdout=self.log,
            stderr=subprocess.STDOUT,
            env={**os.environ, "DISPLAY": display.name, "SDL_AUDIODRIVER": "dummy", "PYTHONUNBUFFERED": "1",
                 "PYTHONPATH": PROGRAMS + os.pathsep + os.environ.get("PYTHONPATH", ""), **env})

    def output(self) -> str:
        with open(os.path.join(self.folder, "out.log")) as f:
            return f.read()

    def interrupt(self, timeout: float = 30.0) -> str:
        """Ctrl-C; the program's output once it has ended."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            raise AssertionError(f"{self.name} did not end within {timeout:.0f} s of Ctrl-C:\n{self.output()}")
        self.log.close()
        return self.output()


def observe(name: str):
    """(position, yaw) of a car of roar_sim now."""
    car = rospy.ServiceProxy("/roar_sim/step", Step)(ticks=0, observe=[name]).vehicles[0]
    p, q = car.odometry.pose.pose.position, car.odometry.pose.pose.orientation
    return np.array([p.x, p.y, p.z]), float(np.arctan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y ** 2 + q.z ** 2)))


def accepts_connections(port: int) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=0.5).close()
        return True
    except OSError:
        return False


def cars() -> list:
    return [v.name for v in rospy.ServiceProxy("/roar_sim/get_world_info", GetWorldInfo)().vehicles]


def wait_for_car(name: str, timeout: float = 60.0):
    deadline = time.time() + timeout
    while name not in cars():
        if time.time() > deadline:
            raise AssertionError(f"no car '{name}' within {timeout:.0f} s (cars: {cars()})")
        time.sleep(0.2)


def saturated_share(pixels: np.ndarray) -> float:
    """The share of strongly coloured pixels (the cars' paint; not the road, barriers' grey or the sky)."""
    spread = pixels.max(axis=2).astype(int) - pixels.min(axis=2).astype(int)
    return float(np.mean(spread > 80))


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class RoarPyPrograms(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("roar_py_programs_checker")
        rospy.wait_for_service("/roar_sim/step", 60)
        cls.display = Display()
        os.makedirs(SHOTS, exist_ok=True)

    @classmethod
    def tearDownClass(cls):
        cls.display.close()

    def tearDown(self):
        # Each program leaves roar_sim in asynchronous mode; the next one sets it as it needs.
        rospy.ServiceProxy("/roar_sim/set_stepping", SetStepping)(mode="step", real_time_factor=-1)

    def drive(self, name: str, keys=("Up",), seconds: float = 6.0, car: str = "carla_vehicle", server=None, **env):
        """Runs a viewer program with keys held; returns the program, the car's (start, end) poses, the
        viewer's pixels and the program's output after Ctrl-C. A viewer that never opens fails with the
        program's output so far (and its server's, for a remote client)."""
        program = Program(name, self.display, **env)
        try:
            try:
                window = self.display.window(VIEWER)
            except AssertionError as missing:
                outputs = [f"{name}:\n{program.output()[-3000:]}"]
                if server is not None:
                    outputs.append(f"{server.name}:\n{server.output()[-3000:]}")
                raise AssertionError("\n".join([str(missing)] + outputs)) from None
            wait_for_car(car)
            start = observe(car)
            self.display.hold(window, *keys)
            time.sleep(seconds)
            end = observe(car)
            pixels = self.display.screenshot(window, os.path.join(SHOTS, f"{name}.png"))
        finally:
            self.display.release(*keys)
            # Where the car is once the keys are up (before Ctrl-C takes it away): a program that acts while
            # a key is held has acted between `end` and here, however long the screenshot took.
            try:
                self.released = observe(car)
            except (rospy.ServiceException, IndexError):
                self.released = None
            output = program.interrupt()
        return program, (start, end), pixels, output

    def assertDroveForward(self, poses, at_least: float):
        (p0, yaw0), (p1, _) = poses
        forward = float(np.dot(p1[:2] - p0[:2], [np.cos(yaw0), np.sin(yaw0)]))
        self.assertGreater(forward, at_least, f"the car went {forward:.1f} m forward")

    def assertShowsTheCar(self, pixels: np.ndarray):
        h, w = pixels.shape[:2]
        behind = pixels[int(0.55 * h):int(0.8 * h), int(0.35 * w):int(0.65 * w)]
        self.assertGreater(saturated_share(behind), 0.5, "the chase camera sees the car's body, as in CARLA")

    def test_manual_control_drives_on_the_up_key_and_shows_the_car(self):
        _, poses, pixels, output = self.drive("manual_control")
        self.assertIn("Spawning vehicle at", output)
        self.assertDroveForward(poses, 5.0)
        self.assertEqual(pixels.shape[:2], (600, 800))
        self.assertShowsTheCar(pixels)
        self.assertNotIn("carla_vehicle", cars(), "Ctrl-C closed the instance, and the car with it")

    def test_the_occupancy_map_viewer_draws_the_road_beside_the_camera(self):
        _, poses, pixels, _ = self.drive("manual_control_occupancy_map", seconds=3.0)
        self.assertEqual(pixels.shape[:2], (600, 900), "camera 800 wide and the 100 x 100 map right of it")
        # 5 m x 5 m around the car: road all over on the 12 m wide track, and black below it.
        occupancy = pixels[:, 800:900].mean(axis=2)
        self.assertGreater(np.mean(occupancy[:100] > 200), 0.9, "the road around the car")
        self.assertLess(np.mean(occupancy[100:] > 50), 0.01, "nothing below the 100 x 100 map")
        self.assertDroveForward(poses, 1.0)

    def test_waypoint_collect_records_the_path_driven_with_space_held(self):
        program, poses, _, output = self.drive("waypoint_collect", keys=("Up", "space"), seconds=8.0)
        self.assertIn("Start collecting waypoints", output)
        waypoints = roar_py_interface.RoarPyWaypoint.load_waypoint_list(
            np.load(os.path.join(program.folder, "waypoints.npz")))
        self.assertGreaterEqual(len(waypoints), 5, output[-2000:])
        spacing = [np.linalg.norm(b.location[:2] - a.location[:2]) for a, b in zip(waypoints[1:], waypoints[2:])]
        self.assertTrue(all(s > 2.0 for s in spacing), spacing)
        # Before space is held the program adds the map's nearest waypoints (their own widths); held, it
        # records where the car is, with its WAYPOINT_LANE_WIDTH: how many of each depends on the keys' timing.
        self.assertGreaterEqual(sum(w.lane_width == 12.0 for w in waypoints), 3, [w.lane_width for w in waypoints])
        # The last one was recorded while space was held: on the road driven between the pose taken with
        # the keys held and the one once they were released, give or take the recording's spacing.
        (_, _), (p1, _) = poses
        self.assertIsNotNone(self.released, "the car was there when the keys were released")
        p2 = self.released[0]
        along = np.clip(np.dot(waypoints[-1].location[:2] - p1[:2], p2[:2] - p1[:2]) /
                        max(np.dot(p2[:2] - p1[:2], p2[:2] - p1[:2]), 1e-9), 0.0, 1.0)
        nearest = p1[:2] + along * (p2[:2] - p1[:2])
        self.assertLess(np.linalg.norm(waypoints[-1].location[:2] - nearest), 10.0, "the last one near the car")

    def test_the_example_controller_follows_the_waypoints(self):
        program = Program("example_controller", self.display)
        try:
            self.display.window(VIEWER)
            wait_for_car("carla_vehicle")
            start, _ = observe("carla_vehicle")
            time.sleep(12.0)
            end, _ = observe("carla_vehicle")
        finally:
            output = program.interrupt()
        self.assertGreater(np.linalg.norm(end[:2] - start[:2]), 40.0, "about 20 m/s after its start")
        self.assertRegex(output, r"Total time: [1-9][0-9.]* seconds")
        line = rospy.wait_for_message("/waypoints", WaypointArray, 10).waypoints
        centre = np.array([[w.location.x, w.location.y] for w in line])
        self.assertLess(min(np.linalg.norm(centre - end[:2], axis=1)), 3.0, "on the waypoints' line")

    def plot(self, name: str):
        folder = tempfile.mkdtemp(prefix="roar_py_figures_")
        program = Program(name, self.display, MPLBACKEND="module://roar_py_figure_backend",
                          ROAR_PY_FIGURE_DIR=folder,
                          PYTHONPATH=os.pathsep.join([os.path.dirname(os.path.abspath(__file__)), PROGRAMS,
                                                      os.environ.get("PYTHONPATH", "")]))
        program.process.wait(300)
        self.assertEqual(program.process.returncode, 0, program.output())
        shutil.copy(os.path.join(folder, "figure_1.png"), os.path.join(SHOTS, f"{name}.png"))
        return np.asarray(Image.open(os.path.join(folder, "figure_1.png")).convert("RGB")), program.output()

    def test_draw_waypoints_plots_the_track(self):
        pixels, output = self.plot("draw_waypoints")
        self.assertIn("Map Name Roar Ring", output)
        ink = pixels.sum(axis=2) < 600
        self.assertGreater(ink.mean(), 0.02, "the track's waypoints drawn across it")
        red = (pixels[:, :, 0] > 200) & (pixels[:, :, 1] < 80) & (pixels[:, :, 2] < 80)
        self.assertGreater(red.sum(), 20, "the spawn points' red arrows")

    def test_draw_comprehensive_waypoints_plots_both_lanes(self):
        pixels, _ = self.plot("draw_comprehensive_waypoints")
        blue = (pixels[:, :, 2] > 150) & (pixels[:, :, 0] < 80)
        self.assertGreater(blue.mean(), 0.001, "lane 0 in blue")

    def test_a_remote_client_drives_a_car_and_sees_its_camera(self):
        port = str(free_port())
        server = Program("run_server", self.display, ROAR_PY_REMOTE_PORT=port)
        try:
            deadline = time.time() + 60
            while "starting websocket server" not in server.output():
                self.assertLess(time.time(), deadline, server.output())
                self.assertIsNone(server.process.poll(), server.output())
                time.sleep(0.2)
            # The program says so before it listens: the client starts once the port takes a connection.
            while not accepts_connections(int(port)):
                self.assertLess(time.time(), deadline, server.output())
                self.assertIsNone(server.process.poll(), server.output())
                time.sleep(0.2)
            _, poses, pixels, client_output = self.drive("client_manual_control", car="roar_py_remote_vehicle",
                                                         server=server, ROAR_PY_REMOTE_URI=f"ws://127.0.0.1:{port}")
            self.assertDroveForward(poses, 5.0)
            self.assertEqual(pixels.shape[:2], (400, 600), "the server's 600 x 400 camera")
            self.assertShowsTheCar(pixels)
            deadline = time.time() + 10
            while "roar_py_remote_vehicle" in cars():
                self.assertLess(time.time(), deadline, "the car of a client that left stays")
                time.sleep(0.2)
            back_to_back = subprocess.run([sys.executable, "-c", BACK_TO_BACK, f"ws://127.0.0.1:{port}", "8"],
                                          capture_output=True, text=True, timeout=240)
            self.assertIn("set up 8 of 8", back_to_back.stdout, back_to_back.stdout + back_to_back.stderr[-2000:])
        finally:
            server_output = server.interrupt()
        for failure in ("ConnectionError", "WireFormatError", "PermissionError"):
            self.assertNotIn(failure, client_output)
        self.assertIn("Initialized, starting websocket server", server_output)


if __name__ == "__main__":
    rostest.rosrun("roar_ros", "roar_py_programs", RoarPyPrograms)
