"""Ends a private ROS stack (roslaunch with its master and nodes) when the program that started it ends,
however it ends: normal exit, exception, SIGINT, SIGTERM or SIGKILL.

    python3 watchdog.py <roslaunch pid> [<folder to remove afterwards>]

The program holds the write end of this process's standard input and never writes to it: when the
program is gone, by any death, the kernel closes it and the read here returns. Then roslaunch gets SIGINT
(it stops its nodes and master), and whatever of its process tree is left after SHUTDOWN_WAIT seconds is
killed. Standard library only: it runs with no ROS environment. test_roar_py_ros.py
test_a_killed_program_leaves_nothing_running pins it for each way a program ends.
"""
import os
import shutil
import signal
import sys
import time

SHUTDOWN_WAIT = 15.0  # s roslaunch gets to stop its nodes


def _parents() -> dict:
    parents = {}
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
        parents[int(entry)] = int(fields[1])
    return parents


def descendants(pid: int) -> list:
    parents = _parents()
    found, frontier = [], [pid]
    while frontier:
        parent = frontier.pop()
        children = [p for p, pp in parents.items() if pp == parent]
        found.extend(children)
        frontier.extend(children)
    return found


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


def stop_tree(pid: int, wait: float = SHUTDOWN_WAIT) -> None:
    tree = [pid] + descendants(pid)
    try:
        os.kill(pid, signal.SIGINT)
    except ProcessLookupError:
        pass
    deadline = time.time() + wait
    while time.time() < deadline and any(alive(p) for p in tree):
        time.sleep(0.1)
    for p in tree:
        if alive(p):
            try:
                os.kill(p, signal.SIGKILL)
            except ProcessLookupError:
                pass


def main(argv) -> int:
    if len(argv) not in (2, 3) or not argv[1].isdigit():
        print("usage: watchdog.py <roslaunch pid> [<folder to remove afterwards>]", file=sys.stderr)
        return 2
    pid = int(argv[1])
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a terminal's Ctrl-C is for the program, not for this
    while sys.stdin.buffer.read(4096):
        pass
    if alive(pid):
        stop_tree(pid)
    if len(argv) == 3 and os.path.basename(argv[2]).startswith("roar_py_ros_"):
        shutil.rmtree(argv[2], ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
