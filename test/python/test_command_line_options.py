"""Options typed on a command line: roar_bench --overtake=name=value sets every OvertakeOptions field (the
README says any) and refuses a misspelt name or a bad value with the option named, before any race runs;
track_tool refuses a number with trailing junk ("--spacing 2x" was read as 2) naming the option."""
import os
import shutil
import subprocess

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BENCH = os.path.join(REPO, "devel", "lib", "roar_ros", "roar_bench")
TRACK_TOOL = os.path.join(REPO, "devel", "lib", "roar_ros", "track_tool")


def run(*args):
    return subprocess.run([BENCH, "--traffic", *args], capture_output=True, text=True, timeout=120)


def test_a_misspelt_option_is_refused_with_the_nearest_name():
    done = run("--overtake=stall_tme=6")
    assert done.returncode == 2, done.stdout + done.stderr
    assert "no option 'stall_tme' (did you mean 'stall_time'?)" in done.stderr, done.stderr
    assert "Traffic:" not in done.stdout  # nothing ran


def test_a_value_that_is_not_a_number_is_refused():
    done = run("--overtake=guard_time=0.2s")
    assert done.returncode == 2 and "guard_time: '0.2s' is not a finite number" in done.stderr, done.stderr
    done = run("--overtake=retry_plans=2.5")
    assert done.returncode == 2 and "retry_plans: '2.5' is not a whole number" in done.stderr, done.stderr


def test_fields_beyond_the_first_ones_and_the_slipstreams_are_settable():
    # One short race: Roar Sprint, the two-car field, one seed, one lap.
    done = run("--map=roar_sprint", "--field=five_percent", "--seeds=1", "--traffic-laps=1",
               "--overtake=stall_time=6", "--overtake=follow_gap=10", "--overtake=slipstream.enabled=0")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "roar_sprint    five_percent      1" in done.stdout, done.stdout


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
    assert done.returncode != 0 and "N must be a whole number of at least 1, got '3x'" in done.stderr, done.stderr
    assert not (tmp_path / "spawns.npz").exists()
