"""The habits of a ROS user work on the package: rosrun finds every executable (the devel space is not
under <package>/build/, which rosrun skips)."""
import os
import signal
import subprocess
import time

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
    # A normal race is quiet: no warning or error from any node.
    noisy = [line for line in output.splitlines() if "[ WARN]" in line or "[ERROR]" in line or "[FATAL]" in line]
    assert not noisy, noisy


def test_rl_launch_ends_when_its_agent_is_done(tmp_path):
    """rl.launch agent:=true: the example agent ends the launch when its steps are done, as Ctrl-C would."""
    env = {**os.environ, "ROS_MASTER_URI": "http://127.0.0.1:11659", "ROS_LOG_DIR": str(tmp_path / "log")}
    done = subprocess.run(["roslaunch", "-p", "11659", "roar_ros", "rl.launch", "agent:=true", "steps:=40"],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=240)
    output = done.stdout + done.stderr
    assert "rl_random_agent: 40 steps" in output, output[-3000:]
    assert "REQUIRED process" not in output and "has died" not in output, output[-3000:]
    assert done.returncode == 0, output[-3000:]


def test_a_lockstep_race_of_several_cars_runs_the_same_twice(tmp_path):
    """Lockstep with four cars passing and following each other: every lap and sector time the same in
    two runs (the planner plans each tick from every car's odometry of it, lockstep::TickGathering;
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


def devel_only_env():
    """The environment of a user who has only run `source devel/setup.bash` (no ROS_LOG_DIR, no ROS_HOME)."""
    done = subprocess.run(["env", "-i", f"HOME={os.environ['HOME']}", "PATH=/usr/bin:/bin", "bash", "-c",
                           f"source {REPO}/devel/setup.bash && env -0"], capture_output=True, timeout=60)
    assert done.returncode == 0, done.stderr
    env = dict(item.split("=", 1) for item in done.stdout.decode().split("\0") if "=" in item)
    assert "ROS_LOG_DIR" not in env and "ROS_HOME" not in env
    return env


@pytest.mark.parametrize("test_file", sorted(f for f in os.listdir(os.path.join(REPO, "test", "integration"))
                                             if f.endswith(".test")))
def test_every_rostest_resolves_with_only_devel_setup(test_file):
    done = subprocess.run(["roslaunch", "--dump-params", os.path.join(REPO, "test", "integration", test_file)],
                          capture_output=True, text=True, env=devel_only_env(), timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr


def test_a_rostest_runs_by_hand_with_only_devel_setup(tmp_path):
    env = {**devel_only_env(), "HOME": str(tmp_path)}  # its ~/.ros/log is the test's own
    done = subprocess.run(["rostest", "roar_ros", "race.test"], capture_output=True, text=True, env=env, timeout=400)
    assert done.returncode == 0 and "RESULT: SUCCESS" in done.stdout, (done.stdout + done.stderr)[-3000:]
    assert (tmp_path / ".ros" / "log" / "race_test" / "results.yaml").exists()


@pytest.fixture(scope="module")
def master():
    """A master of the test's own, on a port of its own."""
    env = {**os.environ, "ROS_MASTER_URI": "http://127.0.0.1:11712"}
    core = subprocess.Popen(["roscore", "-p", "11712"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    try:
        for _ in range(100):
            if subprocess.run(["rosparam", "list"], capture_output=True, env=env, timeout=10).returncode == 0:
                break
            time.sleep(0.2)
        yield env
    finally:
        core.terminate()
        core.wait(timeout=30)


@pytest.mark.parametrize("node, misspelt, suggested", [
    ("roar_sim", "_real_time_factr:=2", "did you mean '/roar_sim/real_time_factor'?"),
    ("controller", "_lookahead_tme:=3", "did you mean '/controller/lookahead_time'?"),
    ("planner", "_horizn:=3", "unknown parameter /planner/horizn"),
    ("waypoint_server", "_mapp:=monza", "did you mean '/waypoint_server/map'?"),
])
def test_a_misspelt_private_parameter_is_refused(master, node, misspelt, suggested):
    done = subprocess.run(["rosrun", "roar_ros", node, misspelt], capture_output=True, text=True, env=master,
                          timeout=60)
    assert done.returncode != 0, done.stdout + done.stderr
    assert suggested in done.stdout + done.stderr, done.stdout + done.stderr
    subprocess.run(["rosparam", "delete", "/" + node], capture_output=True, env=master, timeout=10)


def test_a_known_dynamic_reconfigure_parameter_is_taken(master):
    """The controller's gains are dynamic_reconfigure parameters: set by hand, they are not unknown."""
    node = subprocess.Popen(["rosrun", "roar_ros", "controller", "_speed_gain:=1.5"], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, env=master)
    try:
        with pytest.raises(subprocess.TimeoutExpired):
            node.wait(timeout=5)
    finally:
        node.terminate()
        output = node.communicate(timeout=30)[0]
    assert "unknown parameter" not in output, output


def test_scripts_race_refuses_an_argument_race_launch_does_not_declare():
    done = subprocess.run(["bash", os.path.join(REPO, "scripts", "race"), "lap:=1"], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 2, done.stdout + done.stderr
    assert "race.launch has no argument 'lap' (did you mean 'laps'?)" in done.stderr, done.stderr
    assert "race report" not in done.stdout and "output" not in done.stdout


def start_race(tmp_path, port, *arguments):
    """race.launch on its own master at `port`, writing to tmp_path/out: (the roslaunch, its env, out)."""
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{port}", "ROS_LOG_DIR": str(tmp_path / "log")}
    out = tmp_path / "out"
    launch = subprocess.Popen(["roslaunch", "-p", str(port), "roar_ros", "race.launch", *arguments,
                               f"output_dir:={out}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                              cwd=tmp_path)
    return launch, env, out


def wait_until(condition, seconds):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and not condition():
        time.sleep(0.1)


@pytest.mark.parametrize("sig, status", [(signal.SIGTERM, "aborted"), (signal.SIGKILL, "running")])
def test_race_control_killed_mid_race_loses_no_lap(tmp_path, sig, status):
    """Results are on disk after every lap (status running); SIGTERM writes them as aborted; even SIGKILL
    loses no lap already timed."""
    launch, _, out = start_race(tmp_path, 11660, "map:=roar_sprint", "laps:=3", "real_time_factor:=0")
    try:
        results = out / "results.yaml"
        wait_until(lambda: results.exists() and "laps_completed: 1" in results.read_text(), 200)
        assert results.exists(), "no results after the first lap"
        pid = int(subprocess.check_output(["pgrep", "-f", f"race_control __name:=race_control.*{tmp_path}"]).split()[0])
        os.kill(pid, sig)
        launch.wait(timeout=60)
    finally:
        launch.terminate()
        launch.wait(timeout=60)
    text = results.read_text()
    assert f"status: {status}" in text, text
    assert "laps_completed: 1" in text or "laps_completed: 2" in text, text


def test_a_recorded_race_stays_lean(tmp_path):
    """record:=true keeps what replay and re-simulation need: every tick's odometry and controls, and the
    planner's windows once a second (record_plans:=true for every tick's, ten times the bag)."""
    env = {**os.environ, "ROS_MASTER_URI": "http://127.0.0.1:11663", "ROS_LOG_DIR": str(tmp_path / "log")}
    out = tmp_path / "out"
    done = subprocess.run(["roslaunch", "-p", "11663", "roar_ros", "race.launch", "scenario:=multi_car", "laps:=1",
                           "record:=true", "real_time_factor:=0", f"output_dir:={out}"], capture_output=True, text=True,
                          env=env, cwd=tmp_path, timeout=400)
    assert (out / "race.bag").exists(), (done.stdout + done.stderr)[-3000:]
    import rosbag
    with rosbag.Bag(str(out / "race.bag")) as bag:
        info = bag.get_type_and_topic_info().topics
    ticks = info["/ego/odom"].message_count
    cars = sum(1 for topic in info if topic.endswith("/odom"))
    assert cars == 4 and ticks > 1000, (cars, ticks)
    # Every control sent is in the bag (the recorder writes what is in flight when it stops): each recorded
    # tick's control, but the finishing tick's, which may never be sent (the launch ends as soon as
    # race_control sees the finish; re-simulation to the finish needs only the ones before it: record_resim).
    # A loaded machine may start the recorder after the first tick's odometry, never after its control.
    with rosbag.Bag(str(out / "race.bag")) as bag:
        stamps = {topic: [m.header.stamp.to_nsec() for _, m, _ in bag.read_messages(topics=[topic])]
                  for topic in ("/ego/odom", "/ego/control")}
    unanswered = sorted(set(stamps["/ego/odom"][:-1]) - set(stamps["/ego/control"]))
    assert not unanswered, f"every tick's control: re-simulation needs them; missing at {unanswered[:5]} ns"
    assert ticks - 1 <= info["/ego/control"].message_count <= ticks + 1
    plans = info["/ego/local_trajectory"].message_count
    assert ticks / 25 < plans < ticks / 15, f"{plans} windows in {ticks} ticks: one a second is one in 20"
    car_minutes = cars * ticks * 0.05 / 60
    size_mb = (out / "race.bag").stat().st_size / 1e6
    assert size_mb / car_minutes < 5.0, f"{size_mb:.1f} MB for {car_minutes:.1f} car-minutes"
    # A replay shows the timing: race_control's text rides with each car, in the car's frame.
    with rosbag.Bag(str(out / "race.bag")) as bag:
        _, timing, _ = next(bag.read_messages(topics=["/race_status/markers"], start_time=None))
    assert sorted(m.header.frame_id for m in timing.markers) == [f"{car}/base_link" for car in
                                                                 ("ego", "pace", "rival", "third")], timing
    assert "recording:\n  complete: true" in (out / "results.yaml").read_text()


def test_a_killed_recorders_bag_replays(tmp_path):
    """A recorder killed mid-race: the race goes on, results.yaml says how far the bag got, and replay.launch
    rebuilds the .active bag's index and plays it, with car_models leaving the bag's wheel frames alone."""
    launch, env, out = start_race(tmp_path, 11664, "scenario:=multi_car", "laps:=1", "record:=true")
    try:
        active = out / "race.bag.active"
        wait_until(lambda: active.exists() and active.stat().st_size > 2e6, 200)
        pid = int(subprocess.check_output(["pgrep", "-f", f"race_recorder __name:=recorder.*{tmp_path}"]).split()[0])
        os.kill(pid, signal.SIGKILL)
        launch.wait(timeout=300)
    finally:
        launch.terminate()
        launch.wait(timeout=60)
    results = (out / "results.yaml").read_text()
    assert "status: finished" in results and "recording:\n  complete: false" in results, results
    assert active.exists() and not (out / "race.bag").exists()
    replay = subprocess.Popen(["roslaunch", "-p", "11664", "roar_ros", "replay.launch", f"bag:={out}",
                               "scenario:=multi_car", "rviz:=false", "rate:=0.3"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, env=env, cwd=tmp_path)
    try:
        import rosgraph
        deadline = time.monotonic() + 60
        subscribers = None
        while time.monotonic() < deadline:
            try:
                state = rosgraph.Master("/check", master_uri=env["ROS_MASTER_URI"]).getSystemState()
            except Exception:
                time.sleep(0.2)
                continue
            publishers = dict(state[0])
            if "/ego/joint_states" in publishers and "/car_models" in sum((nodes for _, nodes in state[0]), []):
                subscribers = dict(state[1]).get("/ego/joint_states", [])
                break
            time.sleep(0.2)
        assert subscribers == [], f"car_models must not turn the bag's joint states into frames again: {subscribers}"
        output, _ = replay.communicate(timeout=120)
    finally:
        replay.kill()
        replay.wait()
    assert (out / "race.bag").exists() and not active.exists(), output[-2000:]
    assert "rebuilding its index" in output, output[-2000:]
    import rosbag
    with rosbag.Bag(str(out / "race.bag")) as bag:
        assert bag.get_message_count(topic_filters=["/ego/odom"]) > 20, "the ticks before the kill"
