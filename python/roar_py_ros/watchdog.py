"""Starts a private ROS stack (roslaunch with its master and nodes) for the program that runs this, and ends
it when that program ends, however it ends: normal exit, exception, SIGINT, SIGTERM or SIGKILL, with or
without children of its own.

    python3 watchdog.py <program pid> -- <roslaunch command ...>

This process is the program's child. It makes the stack's log folder (ROS_LOG_DIR, roslaunch's output in
it), starts roslaunch, and writes "<roslaunch pid> <log folder>" as its first line of output; when
roslaunch ends it writes "exited <code>". It stops the stack when a line comes on its standard input or it
closes (the program's stop) or when the program itself ends: that is watched through a pidfd of the program, which a forked
child of the program cannot hold open as it could a pipe. It starts nothing when the program is already
gone, so no moment of start-up leaves a stack behind. Then roslaunch gets SIGINT (it stops its nodes and
master), whatever of its process tree is left after SHUTDOWN_WAIT seconds is killed, and the log folder is
removed. Standard library only: it runs with no ROS environment. test_roar_py_lifecycle.py pins it for each
way a program ends, a program with a forked child and a program killed during start-up.
"""
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

SHUTDOWN_WAIT = 15.0  # s roslaunch gets to stop its nodes
LOG_PREFIX = "roar_py_ros_"


def _processes() -> dict:
    """Each process's parent and session: {pid: (ppid, sid)}."""
    processes = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        # The command name is in parentheses and may hold spaces: the fields after its last ')' are fixed.
        fields = stat[stat.rfind(")") + 2:].split()
        processes[int(entry)] = (int(fields[1]), int(fields[3]))
    return processes


def descendants(pid: int) -> list:
    """The process's descendants, and the members of its session (a node roslaunch started just before it
    died is an orphan of init by then, but still in roslaunch's session)."""
    processes = _processes()
    found, frontier = set(), [pid]
    while frontier:
        parent = frontier.pop()
        children = [p for p, (ppid, _) in processes.items() if ppid == parent and p not in found]
        found.update(children)
        frontier.extend(children)
    found.update(p for p, (_, sid) in processes.items() if sid == pid and p != pid)
    return sorted(found)


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def stop_tree(process: subprocess.Popen, wait: float = SHUTDOWN_WAIT) -> None:
    """SIGINT to roslaunch, then SIGKILL to whatever of its tree (its session too) outlives `wait`."""
    tree = descendants(process.pid)
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    deadline = time.time() + wait
    while time.time() < deadline and (process.poll() is None or any(alive(p) for p in tree)):
        tree = sorted(set(tree) | set(descendants(process.pid)))
        time.sleep(0.1)
    for p in tree:
        if alive(p):
            try:
                os.kill(p, signal.SIGKILL)
            except ProcessLookupError:
                pass
    if process.poll() is None:
        process.kill()
    process.wait()


def watch_program(program_pid: int):
    """A pidfd of the program, or None when the program is already gone (this process then has another
    parent). The parent is checked after the pidfd is opened, so the pidfd is the program's and not a
    process that took its pid."""
    try:
        pidfd = os.pidfd_open(program_pid)
    except ProcessLookupError:
        return None
    if os.getppid() != program_pid:
        os.close(pidfd)
        return None
    return pidfd


def start_roslaunch(command: list, log_dir: str) -> subprocess.Popen:
    env = dict(os.environ)
    env["ROS_LOG_DIR"] = log_dir
    with open(os.path.join(log_dir, "roslaunch.out"), "w") as output:
        return subprocess.Popen(command, env=env, stdout=output, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, start_new_session=True)


def wait_for_the_end(pidfd: int, roslaunch: subprocess.Popen) -> None:
    """Returns when the program ends or closes this process's standard input; says when roslaunch ends."""
    launch_fd = os.pidfd_open(roslaunch.pid)
    watched = [pidfd, sys.stdin.fileno(), launch_fd]
    while True:
        ready, _, _ = select.select(watched, [], [])
        if pidfd in ready:
            return
        if sys.stdin.fileno() in ready:
            return  # a line or the end of input: a forked child may still hold the pipe open, so both stop
        if launch_fd in ready:
            print("exited", roslaunch.wait(), flush=True)
            watched.remove(launch_fd)
            os.close(launch_fd)


def main(argv) -> int:
    if len(argv) < 4 or not argv[1].isdigit() or argv[2] != "--":
        print("usage: watchdog.py <program pid> -- <roslaunch command ...>", file=sys.stderr)
        return 2
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a terminal's Ctrl-C is for the program, not for this
    pidfd = watch_program(int(argv[1]))
    if pidfd is None:
        return 0
    log_dir = tempfile.mkdtemp(prefix=LOG_PREFIX)
    try:
        roslaunch = start_roslaunch(argv[3:], log_dir)
        try:
            print(roslaunch.pid, log_dir, flush=True)
            wait_for_the_end(pidfd, roslaunch)
        except BrokenPipeError:
            pass  # the program is gone before reading the first line: stop all the same
        finally:
            stop_tree(roslaunch)
    finally:
        shutil.rmtree(log_dir, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
