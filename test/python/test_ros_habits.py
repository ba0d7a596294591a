"""The habits of a ROS user work on the package: rosrun finds every executable (the devel space is not
under <package>/build/, which rosrun skips)."""
import os
import subprocess

import pytest

EXECUTABLES = ["roar_sim", "waypoint_server", "planner", "controller", "race_control", "car_models", "policy_driver",
               "rl_train", "track_tool", "roar_bench"]


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
