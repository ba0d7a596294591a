"""The habits of a ROS user work on the package: rosrun finds every executable (the devel space is not
under <package>/build/, which rosrun skips)."""
import os
import subprocess

import pytest

EXECUTABLES = ["roar_sim", "waypoint_server", "planner", "controller", "race_control", "car_models", "policy_driver",
               "race_recorder", "rl_train", "track_tool", "roar_bench"]
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHIM = os.path.join(REPO, "devel", "lib", "libroar_loopback.so")


@pytest.mark.parametrize("executable", EXECUTABLES)
def test_rosrun_finds_every_executable(executable):
    # --help-like runs would start nodes; `rosrun --prefix echo` resolves the path and prints it instead.
    done = subprocess.run(["rosrun", "--prefix", "echo", "roar_ros", executable], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.strip().endswith(f"/devel/lib/roar_ros/{executable}"), done.stdout


def test_rosrun_finds_the_python_programs():
    done = subprocess.run(["rosrun", "--prefix", "echo", "roar_ros", "roar_py_competition.py"], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0 and done.stdout.strip().endswith("roar_py_competition.py"), done.stdout + done.stderr


def test_a_relative_output_dir_is_where_roslaunch_runs(tmp_path):
    """race.launch output_dir:=res/../x writes to <where roslaunch ran>/x (results and bag), not under the
    nodes' working folder."""
    done = subprocess.run(["roslaunch", "--dump-params", "roar_ros", "race.launch", "output_dir:=res/../x", "record:=true"],
                          capture_output=True, text=True, cwd=tmp_path, env={**os.environ, "PWD": str(tmp_path)},
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert f"/race_control/output_dir: {tmp_path}/res/../x" in done.stdout, done.stdout
    assert f"/recorder/bag: {tmp_path}/res/../x/race.bag" in done.stdout, done.stdout


BIND_EVERY_INTERFACE = """
import socket
s = socket.socket()
s.bind(("0.0.0.0", 0))
print(s.getsockname()[0])
s6 = socket.socket(socket.AF_INET6)
s6.bind(("::", 0))
print(s6.getsockname()[0])
"""


def test_the_loopback_shim_turns_binds_to_every_interface_into_loopback_ones():
    """roscpp's XML-RPC servers bind INADDR_ANY whatever ROS_IP says; the shim scripts/ros_env.sh preloads
    keeps them (and every other listening socket) on the loopback, unless ROAR_BIND_ANY=1."""
    env = {k: v for k, v in os.environ.items() if k != "ROAR_BIND_ANY"}
    env["LD_PRELOAD"] = SHIM
    done = subprocess.run(["/usr/bin/python3", "-c", BIND_EVERY_INTERFACE], capture_output=True, text=True, env=env,
                          timeout=30)
    assert done.stdout.split() == ["127.0.0.1", "::1"], done.stdout + done.stderr
    env["ROAR_BIND_ANY"] = "1"
    done = subprocess.run(["/usr/bin/python3", "-c", BIND_EVERY_INTERFACE], capture_output=True, text=True, env=env,
                          timeout=30)
    assert done.stdout.split() == ["0.0.0.0", "::"], done.stdout + done.stderr


@pytest.mark.parametrize("network, expected", [("", f"127.0.0.1|{SHIM}"), ("ROS_IP=10.1.2.3", "10.1.2.3|")])
def test_ros_env_preloads_the_shim_unless_a_network_is_asked_for(network, expected):
    script = (f"unset ROS_IP ROS_HOSTNAME LD_PRELOAD; {'export ' + network + ';' if network else ''} "
              f"source {REPO}/scripts/ros_env.sh; echo \"$ROS_IP|${{LD_PRELOAD:-}}\"")
    done = subprocess.run(["bash", "-c", script], capture_output=True, text=True, timeout=60)
    assert done.stdout.strip().splitlines()[-1] == expected, done.stdout + done.stderr


def test_a_finished_race_ends_roslaunch_as_ctrl_c_would(tmp_path):
    """`roslaunch roar_ros race.launch` on its own: when the race is over, race_control ends the launch
    as Ctrl-C does, not by dying as a required node (roslaunch's red "REQUIRED process has died")."""
    env = {**os.environ, "ROS_MASTER_URI": "http://127.0.0.1:11657", "ROS_LOG_DIR": str(tmp_path / "log")}
    done = subprocess.run(["roslaunch", "-p", "11657", "roar_ros", "race.launch", "map:=roar_sprint", "laps:=1",
                           "real_time_factor:=0", f"output_dir:={tmp_path / 'out'}"], capture_output=True, text=True,
                          env=env, cwd=tmp_path, timeout=240)
    output = done.stdout + done.stderr
    assert "race finished" in output, output[-3000:]
    assert "REQUIRED process" not in output and "has died" not in output, output[-3000:]
    assert done.returncode == 0, output[-3000:]


def test_a_lockstep_race_of_several_cars_runs_the_same_twice(tmp_path):
    """Lockstep with four cars passing and following each other: every lap and sector time the same in
    two runs (the planner plans each tick from every car's odometry of it, planning::TickGathering;
    planned as each message came, the multi_car scenario's lap times differed from the 5th digit on)."""
    laps = []
    for run in range(2):
        env = {**os.environ, "ROS_MASTER_URI": "http://127.0.0.1:11658", "ROS_LOG_DIR": str(tmp_path / "log")}
        out = tmp_path / f"out{run}"
        done = subprocess.run(["roslaunch", "-p", "11658", "roar_ros", "race.launch", "scenario:=multi_car", "laps:=1",
                               f"output_dir:={out}"], capture_output=True, text=True, env=env, cwd=tmp_path,
                              timeout=240)
        assert done.returncode == 0 and (out / "laps.csv").exists(), (done.stdout + done.stderr)[-3000:]
        laps.append((out / "laps.csv").read_text())
    assert len(laps[0].splitlines()) == 5, laps[0]
    assert laps[0] == laps[1]
