"""Options typed on a command line: roar_bench --overtake=<group>.<name>=value sets every option of
planning::overtakeOptionTable and refuses a misspelt name or a bad value with the option named, before any race runs;
roar_bench's, track_tool's and rl_train's numbers are refused with trailing junk ("--spacing 2x" was read
as 2), naming the option."""
import os
import shutil
import subprocess

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCH = os.path.join(REPO, "devel", "lib", "roar_ros", "roar_bench")
TRACK_TOOL = os.path.join(REPO, "devel", "lib", "roar_ros", "track_tool")


def run(*args):
    return subprocess.run([BENCH, "--traffic", *args], capture_output=True, text=True, timeout=120)


def test_a_misspelt_option_is_refused_with_the_nearest_name():
    done = run("--overtake=passing.stall_tme=6")
    assert done.returncode == 2, done.stdout + done.stderr
    assert "no option 'passing.stall_tme' (did you mean 'passing.stall_time'?)" in done.stderr, done.stderr
    assert "Traffic:" not in done.stdout  # nothing ran


def test_a_value_that_is_not_a_number_is_refused():
    done = run("--overtake=guard.time=0.2s")
    assert done.returncode == 2 and "--overtake guard.time '0.2s' is not a number" in done.stderr, done.stderr
    done = run("--overtake=passing.retry_plans=2.5")
    assert done.returncode == 2 and "--overtake passing.retry_plans '2.5' is not a whole number" in done.stderr, done.stderr
    # roar_bench's own options likewise (--seeds=0 used to become 1, --seeds=3x 3)
    for bad, said in (("--seeds=3x", "--seeds '3x' is not a whole number of at least 1"),
                      ("--seeds=0", "--seeds '0' is not a whole number of at least 1"),
                      ("--seconds=2s", "--seconds '2s' is not a number"),
                      ("--repeats=0", "--repeats '0' is not a whole number of at least 1"),
                      ("--envs-per-thread=2.5", "--envs-per-thread '2.5' is not a whole number of at least 1")):
        done = run(bad)
        assert done.returncode == 2 and said in done.stderr, (bad, done.stderr)


def test_fields_beyond_the_first_ones_and_the_slipstreams_are_settable():
    # One short race: Roar Sprint, the two-car field, one seed, one lap.
    done = run("--map=roar_sprint", "--field=five_percent", "--seeds=1", "--traffic-laps=1",
               "--overtake=passing.stall_time=6", "--overtake=margins.follow_gap=10", "--overtake=slipstream.enabled=0")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "roar_sprint    five_percent      1" in done.stdout, done.stdout


def test_the_follow_gap_set_is_the_one_raced_to_and_the_cars_size_is_the_vehicles():
    # The field's planner keeps to the follow gap the planner's options set.
    def table_row(gap):
        done = run("--map=roar_sprint", "--field=pace_car", "--seeds=1", "--traffic-laps=1",
                   f"--overtake=margins.follow_gap={gap}")
        assert done.returncode == 0, done.stdout + done.stderr
        return [line for line in done.stdout.splitlines() if line.startswith("roar_sprint    pace_car")]
    assert table_row(12) != table_row(40)
    for size in ("car.length", "car.width"):
        done = run(f"--overtake={size}=3")
        assert done.returncode == 2 and f"no option '{size}'" in done.stderr, done.stderr


def test_a_value_outside_the_options_range_is_refused_with_the_range():
    done = run("--overtake=margins.lateral=9")
    assert done.returncode == 2 and "--overtake margins.lateral 9 is outside [0.2, 5]" in done.stderr, done.stderr
    done = run("--overtake=defence.enabled=2")
    assert done.returncode == 2 and "--overtake defence.enabled '2' is not 0 or 1" in done.stderr, done.stderr


def test_track_tool_refuses_a_spacing_that_is_not_a_number(tmp_path):
    folder = tmp_path / "ring"
    shutil.copytree(os.path.join(REPO, "maps", "roar_ring"), folder)
    before = (folder / "centerline.csv").read_bytes()
    for bad in ("2x", "abc", "nan"):
        done = subprocess.run([TRACK_TOOL, "resample", str(folder), "--spacing", bad], capture_output=True,
                              text=True, timeout=60)
        assert done.returncode != 0, done.stdout + done.stderr
        assert f"--spacing '{bad}' is not a number" in done.stderr, done.stderr
    assert (folder / "centerline.csv").read_bytes() == before  # nothing written
    done = subprocess.run([TRACK_TOOL, "resample", str(folder), "--spacing", "3"], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr


def test_track_tool_refuses_a_spawn_count_that_is_not_a_whole_number(tmp_path):
    done = subprocess.run([TRACK_TOOL, "spawn", os.path.join(REPO, "maps", "roar_ring"), "3x",
                           str(tmp_path / "spawns.npz")], capture_output=True, text=True, timeout=60)
    assert done.returncode != 0 and "spawn: N '3x' is not a whole number from 1 to 100000" in done.stderr, done.stderr
    assert not (tmp_path / "spawns.npz").exists()


def test_rl_train_refuses_a_value_that_is_not_a_number(tmp_path):
    rl_train = os.path.join(REPO, "devel", "lib", "roar_ros", "rl_train")
    for args, said in ((["--minutes", "1m"], "--minutes '1m' is not a number"),
                       (["--threads", "2x"], "--threads '2x' is not a whole number of at least 1"),
                       (["--hidden", "32,x"], "--hidden 'x' is not a whole number of at least 1")):
        done = subprocess.run([rl_train, *args, "--out", str(tmp_path / "out")], capture_output=True, text=True,
                              timeout=60)
        assert done.returncode == 2 and said in done.stderr, (args, done.stderr)
    assert not (tmp_path / "out").exists()  # nothing ran


def test_the_reverse_grids_pace_step_sets_its_paces_and_is_refused_out_of_range():
    def paces(step):
        done = run("--map=roar_sprint", "--field=reverse_grid", "--seeds=1", "--traffic-laps=1", "--verbose",
                   f"--pace-step={step}")
        assert done.returncode == 0, done.stdout + done.stderr
        grid = next(line for line in done.stdout.splitlines() if "seed 0 reverse_grid:" in line)
        return [float(word) for before, word in zip(grid.split(), grid.split()[1:]) if before == "pace"]
    for step in (0.05, 0.08):
        got = paces(step)
        assert len(got) == 6
        for k, pace in enumerate(got):  # the fastest at full pace, each jittered by up to 1%
            assert abs(pace - (1.0 - step * (5 - k))) <= 0.01 + 1e-12, (step, got)
    for bad, said in (("0.5", "--pace-step=0.5: expected 0.01 to 0.15"), ("0", "--pace-step=0: expected"),
                      ("5%", "--pace-step '5%' is not a number")):
        done = run(f"--pace-step={bad}")
        assert done.returncode == 2 and said in done.stderr, (bad, done.stderr)
        assert "Traffic:" not in done.stdout


def test_an_unknown_field_is_refused_not_aborted_on():
    done = run("--field=reverse")  # once an uncaught exception: abort, exit 134
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert "--field=reverse: expected pace_car, reverse_grid or five_percent" in done.stderr, done.stderr


def test_every_tool_and_script_says_its_usage_on_help_and_exits_0():
    lib = os.path.join(REPO, "devel", "lib", "roar_ros")
    commands = [[os.path.join(lib, "track_tool"), "--help"], [os.path.join(lib, "rl_train"), "--help"],
                [BENCH, "--help"], ["bash", os.path.join(REPO, "scripts", "race"), "--help"],
                ["bash", os.path.join(REPO, "scripts", "play_race"), "--help"],
                [os.path.join(REPO, "scripts", "race_rviz"), "--help"]]
    commands += [["/usr/bin/python3", os.path.join(REPO, "scripts", name), "--help"]
                 for name in ("roar_py_competition.py", "roar_rl_ppo.py", "rl_random_agent.py")]
    for command in commands:
        done = subprocess.run(command, capture_output=True, text=True, timeout=60)
        assert done.returncode == 0, (command, done.stderr)
        assert "usage" in (done.stdout + done.stderr).lower() or len(done.stdout.splitlines()) >= 2, command


def test_race_rviz_reads_a_scenarios_cars_as_the_nodes_do(tmp_path):
    # Bare names are cars as scenario::readCars reads them (race_rviz once read c["name"] itself and failed).
    scenario = tmp_path / "bare.yaml"
    scenario.write_text("map: roar_ring\nlaps: 1\ncars: [ego, {name: rival, sensors: default}]\n")
    out = tmp_path / "bare.rviz"
    done = subprocess.run([os.path.join(REPO, "scripts", "race_rviz"), str(scenario), "--output", str(out)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    text = out.read_text()
    assert text.count("rviz/RobotModel") == 2 and "ego/robot_description" in text and "rival/robot_description" in text
    done = subprocess.run([os.path.join(REPO, "scripts", "race_rviz"), str(scenario), "--follow", "nobody",
                           "--output", str(out)], capture_output=True, text=True, timeout=60)
    assert done.returncode != 0 and "no such car" in done.stderr
    scenario.write_text("map: roar_ring\ncars: [{name: ego, sensors: no_such_set}]\n")
    done = subprocess.run([os.path.join(REPO, "scripts", "race_rviz"), str(scenario), "--output", str(out)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode != 0 and "cars[0].sensors" in done.stderr and "no_such_set" in done.stderr, done.stderr
