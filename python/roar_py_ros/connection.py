"""The ROS side of roar_py_ros: finds (or starts) roar_sim, and calls its services with errors in Python's
terms."""
import atexit
import contextlib
import os
import re
import select
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
import typing

import rosgraph
import rospy

from roar_paths import default_map, package_root  # noqa: F401 - also roar_py_ros.connection.package_root

from .watchdog import SHUTDOWN_WAIT

SIM = "/roar_sim"
WAYPOINT_SERVER = "/waypoint_server"
_node_lock = threading.Lock()
_private_port: typing.Optional[int] = None


@contextlib.contextmanager
def ros_threads():
    """Around a rospy call that may start threads (a node, a subscriber, a publisher, a service proxy):
    SIGINT and SIGTERM blocked in the calling thread meanwhile, so the threads it starts are born blocking
    them and the kernel delivers them to the program's main thread, where they interrupt a sleep or a read
    as Ctrl-C should (test_roar_py_lifecycle test_rospys_threads_leave_ctrl_c_to_the_main_thread)."""
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


class RoarSimError(RuntimeError):
    """roar_sim refused a request, or is not there to answer it."""


def master_online(uri: str) -> bool:
    try:
        return rosgraph.is_master_online(master_uri=uri)
    except Exception:  # noqa: BLE001 - any failure to reach it means: not online
        return False


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class PrivateSim:
    """roslaunch of launch/roar_py.launch (with its own master when `port` is given), started and stopped by
    watchdog.py, which also stops it when this program ends however it ends."""

    def __init__(self, map_name: str, port: typing.Optional[int]):
        roslaunch = shutil.which("roslaunch") or "/usr/bin/roslaunch"
        env = dict(os.environ)
        if env.get("ROS_IP") == "127.0.0.1":
            # roscpp binds its XML-RPC server to every interface whatever ROS_IP says: the loopback shim
            # (src/tools/loopback_bind.cpp) turns that into loopback, as scripts/ros_env.sh does.
            shim = package_root() / "devel" / "lib" / "libroar_loopback.so"
            if shim.exists() and str(shim) not in env.get("LD_PRELOAD", ""):
                env["LD_PRELOAD"] = str(shim) + (":" + env["LD_PRELOAD"] if env.get("LD_PRELOAD") else "")
        root = str(package_root())
        if root not in env.get("ROS_PACKAGE_PATH", "").split(":"):
            env["ROS_PACKAGE_PATH"] = root + (":" + env["ROS_PACKAGE_PATH"] if env.get("ROS_PACKAGE_PATH") else "")
        cmd = [roslaunch] + (["-p", str(port)] if port is not None else ["--wait"])
        cmd += [str(package_root() / "launch" / "roar_py.launch"), f"map:={map_name}"]
        self._watchdog = subprocess.Popen(
            [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "watchdog.py"),
             str(os.getpid()), "--"] + cmd,
            env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
            start_new_session=True, text=True)
        atexit.register(self.stop)
        first = self._watchdog.stdout.readline().split()
        if len(first) != 2 or not first[0].isdigit():
            self.stop()
            raise RoarSimError(f"could not start roslaunch ({' '.join(cmd)})")
        self.roslaunch_pid, self.log_dir = int(first[0]), first[1]
        self.output_path = os.path.join(self.log_dir, "roslaunch.out")
        self._exited = False

    def alive(self) -> bool:
        """Whether roslaunch still runs: the watchdog writes a line when it ends (or ends itself)."""
        if not self._exited and (self._watchdog.stdout.closed
                                 or select.select([self._watchdog.stdout], [], [], 0)[0]):
            self._exited = True
        return not self._exited

    def output_tail(self, lines: int = 30) -> str:
        try:
            with open(self.output_path) as f:
                return "".join(f.readlines()[-lines:])
        except (OSError, AttributeError):
            return ""

    def failure(self) -> str:
        """What went wrong, from roslaunch's output: its error lines (roar_sim's FATAL, roslaunch's own
        errors), else its last lines."""
        tail = [re.sub(r"\x1b\[[0-9;]*m", "", line).strip() for line in self.output_tail(200).splitlines()]
        errors = []
        for line in tail:
            if any(mark in line for mark in ("FATAL", "ERROR", "RLException", "error:", "Error:")):
                # "[FATAL] [1795903476.406]: roar_sim: ..." -> "roar_sim: ..."; the same refusal by two nodes once.
                message = re.sub(r"^\[ *[A-Z]+\] \[[0-9.]+\]: ", "", line)
                if not any(message.split(": ", 1)[-1] == e.split(": ", 1)[-1] for e in errors):
                    errors.append(message)
        return "\n".join(errors[:5] if errors else tail[-5:])

    def stop(self):
        """The watchdog stops roslaunch (SIGINT, then SIGKILL to what is left), removes the log folder and
        ends; a line rather than a closed pipe, as a forked child of this program may hold the pipe too."""
        if self._watchdog.poll() is None:
            try:
                self._watchdog.stdin.write("stop\n")
                self._watchdog.stdin.flush()
            except (BrokenPipeError, ValueError):
                pass
            try:
                self._watchdog.wait(timeout=SHUTDOWN_WAIT + 10)
            except subprocess.TimeoutExpired:
                self._watchdog.kill()
                self._watchdog.wait()
        for stream in (self._watchdog.stdin, self._watchdog.stdout):
            try:
                stream.close()
            except (BrokenPipeError, OSError):
                pass


def ensure_node():
    """rospy's node of this process (one per process), started once."""
    with _node_lock:
        if not rospy.core.is_initialized():
            with ros_threads():
                rospy.init_node("roar_py", anonymous=True, disable_signals=True, disable_rosout=False)


def connect(map_name: typing.Optional[str], timeout: float) -> typing.Optional[PrivateSim]:
    """Makes sure a roar_sim answers on ROS_MASTER_URI: the one there, or one started here (with a private
    master when none is reachable). Returns what was started, to stop on close."""
    global _private_port
    uri = os.environ.get("ROS_MASTER_URI", "")
    started = None
    if not uri or not master_online(uri):
        if rospy.core.is_initialized() and _private_port is None:
            raise RoarSimError(f"the ROS master at {uri or '(ROS_MASTER_URI unset)'} has gone away")
        _private_port = _private_port or free_port()
        os.environ["ROS_MASTER_URI"] = f"http://127.0.0.1:{_private_port}"
        if not os.environ.get("ROS_IP") and not os.environ.get("ROS_HOSTNAME"):
            # A private stack serves this program only: every node of it, this one too, on loopback.
            os.environ["ROS_IP"] = "127.0.0.1"
        started = PrivateSim(map_name or default_map(), _private_port)
        deadline = time.time() + timeout
        while not master_online(os.environ["ROS_MASTER_URI"]):
            if not started.alive() or time.time() > deadline:
                failure = started.failure()
                started.stop()
                raise RoarSimError("could not start a private ROS master and roar_sim:\n" + failure)
            time.sleep(0.05)
    elif not sim_registered():
        started = PrivateSim(map_name or default_map(), None)
    ensure_node()
    deadline = time.time() + timeout
    while not (sim_registered() and service_registered(WAYPOINT_SERVER + "/get_waypoints")):
        if started is not None and not started.alive():
            failure = started.failure()
            started.stop()
            raise RoarSimError("roar_sim did not start:\n" + failure)
        if time.time() > deadline:
            if started is not None:
                started.stop()
            raise RoarSimError(f"no roar_sim and waypoint_server answered on {os.environ['ROS_MASTER_URI']} within "
                               f"{timeout:.0f} s (start them with `roslaunch roar_ros roar_py.launch`)")
        time.sleep(0.05)
    return started


def service_registered(name: str) -> bool:
    try:
        return rosgraph.Master("/roar_py").lookupService(name) is not None
    except Exception:  # noqa: BLE001 - not registered (or no master): not there
        return False


_node_uris: typing.Dict[str, str] = {}


def publisher_connected(node: str, topic: str, subscriber: str) -> bool:
    """Whether node reports (getBusInfo, as rosnode info reads it) an outbound connection of topic to
    subscriber."""
    import xmlrpc.client

    try:
        if node not in _node_uris:
            _node_uris[node] = rosgraph.Master("/roar_py").lookupNode(node)
        code, _, bus = xmlrpc.client.ServerProxy(_node_uris[node]).getBusInfo("/roar_py")
    except Exception:  # noqa: BLE001 - not reachable (yet, or any more): not connected
        _node_uris.pop(node, None)
        return False
    return code == 1 and any(len(c) >= 5 and c[1] == subscriber and c[2] == "o" and c[4] == topic for c in bus)


def sim_registered() -> bool:
    return service_registered(SIM + "/get_world_info")


class Services:
    """Persistent proxies of roar_sim's and waypoint_server's services; errors as RoarSimError."""

    def __init__(self):
        self._proxies: typing.Dict[str, rospy.ServiceProxy] = {}
        self._lock = threading.Lock()

    def call(self, name: str, srv_class, /, check: bool = True, **fields):
        with self._lock:
            proxy = self._proxies.get(name)
            fresh = proxy is None
            if fresh:
                proxy = rospy.ServiceProxy(name, srv_class, persistent=True)
                self._proxies[name] = proxy
            try:
                # A new proxy connects on its first call; later calls reuse the connection, and skip the
                # signal masks' cost (5 us, of a step's 400-1000).
                with ros_threads() if fresh else contextlib.nullcontext():
                    response = proxy.call(srv_class._request_class(**fields))
            except (rospy.ServiceException, rospy.ROSException, OSError) as e:
                self._proxies.pop(name, None)
                proxy.close()
                if not service_registered(name):
                    raise RoarSimError(f"{name}: roar_sim has gone away ({e})") from None
                raise RoarSimError(f"{name} failed: {e}") from None
        if check and hasattr(response, "success") and not response.success:
            raise RoarSimError(f"{name} refused: {response.message}")
        return response

    def close(self):
        with self._lock:
            for proxy in self._proxies.values():
                proxy.close()
            self._proxies.clear()
