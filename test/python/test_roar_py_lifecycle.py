"""Nothing a ROAR_PY program started is left behind when it ends, however it ends: a program that makes
a RoarPyRosInstance with no ROS master about starts its own stack (roslaunch, rosmaster, rosout, roar_sim,
waypoint_server); after a normal exit, an exception, SIGINT, SIGTERM or SIGKILL every one of those
processes is gone and its log folder removed."""
import os
import signal
import subprocess
import sys
import time

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "python", "roar_py_ros"))
import watchdog  # noqa: E402

PROGRAM = """
import sys, time
import roar_py_ros
instance = roar_py_ros.RoarPyRosInstance(map_name="roar_sprint")
if sys.argv[1] == "forked child":
    import multiprocessing
    child = multiprocessing.get_context("fork").Process(target=time.sleep, args=(120,), daemon=False)
    child.start()
    print(child.pid, end=" ")
print(instance._private.roslaunch_pid, instance._private.log_dir, flush=True)
sys.stdin.readline()
if sys.argv[1] == "exception":
    raise RuntimeError("the program failed")
if sys.argv[1] == "exit":
    sys.exit(0)
time.sleep(600)
"""


def start_program(how: str):
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME")}
    program = subprocess.Popen([sys.executable, "-c", PROGRAM, how], env=env, stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = program.stdout.readline().split()
    assert len(line) == (3 if how == "forked child" else 2), \
        f"the program did not start its stack: {program.stderr.read() if program.poll() else ''}"
    return program, int(line[-2]), line[-1], (int(line[0]) if len(line) == 3 else None)


def stack_of(roslaunch_pid: int) -> list:
    """roslaunch and its processes, once its five nodes are up."""
    deadline = time.time() + 30
    tree = []
    while time.time() < deadline:
        tree = [roslaunch_pid] + watchdog.descendants(roslaunch_pid)
        if len(tree) >= 5:
            break
        time.sleep(0.2)
    return tree


@pytest.mark.parametrize("how", ["exit", "exception", "SIGINT", "SIGTERM", "SIGKILL", "forked child"])
def test_a_program_leaves_nothing_running_however_it_ends(how):
    """"forked child": the program has a multiprocessing child (which inherits its pipes) and is SIGKILLed;
    the stack ends while the child still runs."""
    program, roslaunch_pid, log_dir, child = start_program(how)
    tree = stack_of(roslaunch_pid)
    names = sorted(open(f"/proc/{p}/comm").read().strip() for p in tree if watchdog.alive(p))
    assert any("roar_sim" in n for n in names) and any("rosmaster" in n or "python" in n for n in names), names
    if how in ("exit", "exception"):
        program.stdin.write("go\n")
        program.stdin.flush()
    else:
        program.send_signal(signal.SIGKILL if how == "forked child" else getattr(signal, how))
    program.wait(timeout=60)
    try:
        deadline = time.time() + 30
        while time.time() < deadline and (any(watchdog.alive(p) for p in tree) or os.path.exists(log_dir)):
            time.sleep(0.2)
        left = [p for p in tree if watchdog.alive(p)]
        assert left == [], f"after {how}: still running {left}"
        assert not os.path.exists(log_dir), f"after {how}: {log_dir} is left"
        if child is not None:
            assert watchdog.alive(child), "the forked child ended early: the test proves nothing"
    finally:
        if child is not None and watchdog.alive(child):
            os.kill(child, signal.SIGKILL)


def marked_processes(mark: str) -> list:
    """The processes whose environment holds ROAR_TEST_MARK=mark: whatever a program started inherits it."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/environ", "rb") as f:
                    if f"ROAR_TEST_MARK={mark}".encode() in f.read().split(b"\0") and watchdog.alive(int(entry)):
                        found.append(int(entry))
            except OSError:
                continue
    return found


def started_by(pid: int, name: str) -> bool:
    """Whether a process named `name` (in its command line) runs below pid."""
    for p in watchdog.descendants(pid):
        try:
            with open(f"/proc/{p}/cmdline") as f:
                if name in f.read():
                    return True
        except OSError:
            continue
    return False


@pytest.mark.parametrize("moment", ["watchdog started", "roslaunch started", "0.05 s", "0.3 s", "1 s"])
def test_a_program_killed_during_start_up_leaves_nothing_running(moment, tmp_path):
    """SIGKILL at each moment of start-up, the first two as soon as the process appears: nothing the
    program started runs 30 s later and no log folder is left."""
    mark = f"{os.getpid()}-{moment}"
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME")}
    env.update(ROAR_TEST_MARK=mark, TMPDIR=str(tmp_path))
    program = subprocess.Popen([sys.executable, "-c", PROGRAM, "exit"], env=env, stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    if moment.endswith(" s"):
        time.sleep(float(moment.split()[0]))
    else:
        wanted = "watchdog.py" if moment == "watchdog started" else "roslaunch"
        while time.time() < deadline and not started_by(program.pid, wanted):
            pass
        assert time.time() < deadline, f"{wanted} never started"
    program.kill()
    program.wait(timeout=10)
    deadline = time.time() + 30
    while time.time() < deadline and (marked_processes(mark) or os.listdir(tmp_path)):
        time.sleep(0.2)
    assert marked_processes(mark) == [], f"killed at {moment}: still running"
    assert os.listdir(tmp_path) == [], f"killed at {moment}: left {os.listdir(tmp_path)}"


STEPPING_PROGRAM = """
import asyncio, sys, time
import roar_py_ros

async def main():
    instance = roar_py_ros.RoarPyRosInstance(map_name="roar_sprint")
    world = instance.world
    world.set_asynchronous(sys.argv[1] == "async")
    try:
        print("stepping", flush=True)
        while True:
            await world.step()
            time.sleep(0.08)  # slower than roar_sim's clock: in asynchronous mode the next tick is always there
    finally:
        instance.close()
        print("closed", flush=True)

asyncio.run(main())
"""


@pytest.mark.parametrize("mode", ["sync", "async"])
def test_ctrl_c_ends_a_program_whose_steps_never_wait(mode):
    # asyncio delivers Ctrl-C by cancelling the main task where it next waits; ROAR_PY's CARLA backend
    # waits in every step, so one Ctrl-C ends its programs (and their finally blocks run).
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME")}
    program = subprocess.Popen([sys.executable, "-c", STEPPING_PROGRAM, mode], env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    assert program.stdout.readline().strip() == "stepping", program.stderr.read() if program.poll() else ""
    time.sleep(1.0)
    program.send_signal(signal.SIGINT)
    out, err = program.communicate(timeout=30)
    assert "closed" in out, err[-2000:]
    assert "KeyboardInterrupt" in err


def listening_addresses(pids) -> set:
    """The local addresses the processes listen on (TCP, IPv4 and IPv6), from /proc."""
    inodes = set()
    for pid in pids:
        try:
            for fd in os.listdir(f"/proc/{pid}/fd"):
                target = os.readlink(f"/proc/{pid}/fd/{fd}")
                if target.startswith("socket:["):
                    inodes.add(target[8:-1])
        except OSError:
            continue
    addresses = set()
    for table, width in (("/proc/net/tcp", 8), ("/proc/net/tcp6", 32)):
        with open(table) as f:
            for line in f.readlines()[1:]:
                fields = line.split()
                if fields[3] == "0A" and fields[9] in inodes:  # 0A: LISTEN
                    addresses.add(fields[1].split(":")[0][:width])
    return addresses


LOOPBACK = {"0100007F", "00000000000000000000000001000000"}  # 127.0.0.1, ::1 as /proc writes them


def test_a_private_stack_listens_on_loopback_only():
    """With no ROS_IP, no shim preloaded and no master: every socket of the program's own stack (rosmaster,
    roslaunch, rosout, roar_sim, waypoint_server) and of the program itself listens on loopback only."""
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME", "LD_PRELOAD")}
    program = subprocess.Popen([sys.executable, "-c", PROGRAM, "exit"], env=env, stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        roslaunch_pid = int(program.stdout.readline().split()[0])
        tree = stack_of(roslaunch_pid)
        addresses = listening_addresses(tree + [program.pid])
        assert addresses, "no listening socket found: the check would pass on anything"
        assert addresses <= LOOPBACK, addresses
    finally:
        program.stdin.write("go\n")
        program.stdin.flush()
        program.wait(timeout=60)


def test_a_misspelt_map_is_one_clear_error():
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME")}
    done = subprocess.run([sys.executable, "-c", "import roar_py_ros; roar_py_ros.RoarPyRosInstance(map_name='monzza')"],
                          env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode != 0
    error = done.stderr[done.stderr.index("RoarSimError"):]
    assert "unknown map 'monzza'" in error and "(did you mean 'monza'?)" in error, error
    assert "\x1b[" not in error and len(error.splitlines()) <= 4, error


def test_the_watchdog_finds_an_orphan_left_in_roslaunchs_session():
    # A node roslaunch starts just before it dies is the orphan of init by then: still in its session, so
    # stop_tree still kills it.
    leader = subprocess.Popen([sys.executable, "-c", "import subprocess, sys; p = subprocess.Popen(['sleep', '60']); "
                               "print(p.pid, flush=True)"], stdout=subprocess.PIPE, text=True, start_new_session=True)
    orphan = int(leader.stdout.readline())
    leader.wait(timeout=10)
    try:
        assert orphan in watchdog.descendants(leader.pid), "the orphan is in the dead leader's session"
    finally:
        os.kill(orphan, signal.SIGKILL)


THREADS_PROGRAM = """
import asyncio, os, threading
import roar_py_ros

async def main():
    instance = roar_py_ros.RoarPyRosInstance(map_name="roar_sprint")
    world = instance.world
    world.set_asynchronous(True)
    vehicle = world.spawn_vehicle("vehicle.tesla.model3", *world.spawn_points[0], auto_gear=True)
    vehicle.attach_location_in_world_sensor()
    await world.step()
    world.set_asynchronous(False)
    await world.step()
    main_tid = threading.main_thread().native_id
    for tid in sorted(os.listdir("/proc/self/task")):
        try:
            with open(f"/proc/self/task/{tid}/status") as f:
                blocked = int(next(l for l in f if l.startswith("SigBlk:")).split()[1], 16)
        except FileNotFoundError:
            continue  # a thread that ended since the listing (rospy's short-lived ones) takes no signal
        print(tid, int(tid) == main_tid, blocked, flush=True)
    instance.close()

asyncio.run(main())
"""


def test_rospys_threads_leave_ctrl_c_to_the_main_thread():
    """The kernel gives a process's SIGINT to any thread that does not block it; a thread of rospy's that
    took it would leave the main thread asleep in its read or sleep, and Ctrl-C would not end the program.
    Every thread but the main one blocks SIGINT and SIGTERM (connection.ros_threads), the main one neither."""
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME")}
    out = subprocess.run([sys.executable, "-c", THREADS_PROGRAM], env=env, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr[-3000:]
    rows = [line.split() for line in out.stdout.splitlines()]
    wanted = (1 << (signal.SIGINT - 1)) | (1 << (signal.SIGTERM - 1))
    main = [int(mask) for _, is_main, mask in rows if is_main == "True"]
    others = {tid: int(mask) for tid, is_main, mask in rows if is_main == "False"}
    assert len(main) == 1 and main[0] & wanted == 0, rows
    assert len(others) >= 3, f"rospy's threads were not there to check: {rows}"
    open_to_ctrl_c = [tid for tid, mask in others.items() if mask & wanted != wanted]
    assert open_to_ctrl_c == [], f"threads that can take SIGINT or SIGTERM: {open_to_ctrl_c} of {rows}"
