"""An installed roar_ros runs as the devel space does: `cmake --install build` (staged with DESTDIR), then,
in an environment that knows only the installed copy (no source tree, no devel space), roslaunch races a
lap of Roar Sprint and writes its report, and the Python modules import and find the maps."""
import os
import subprocess

import yaml

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def installed_prefix(stage):
    done = subprocess.run(["cmake", "--install", os.path.join(REPO, "build")], capture_output=True, text=True,
                          env={**os.environ, "DESTDIR": str(stage)}, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    prefixes = [os.path.join(root, "share", "roar_ros") for root, dirs, _ in os.walk(stage) if "share" in dirs]
    found = [p for p in prefixes if os.path.isfile(os.path.join(p, "package.xml"))]
    assert len(found) == 1, prefixes
    return os.path.dirname(os.path.dirname(found[0]))


def test_an_installed_package_races_and_its_python_modules_import(tmp_path):
    prefix = installed_prefix(tmp_path / "stage")
    env = {
        "HOME": str(tmp_path), "PATH": f"{prefix}/bin:/usr/bin:/bin", "ROS_PACKAGE_PATH": f"{prefix}/share:/usr/share",
        "ROS_ROOT": "/usr/share/ros", "ROS_PYTHON_VERSION": "3", "ROS_IP": "127.0.0.1",
        "ROS_MASTER_URI": "http://127.0.0.1:11634", "ROS_LOG_DIR": str(tmp_path / "log"),
        "ROS_HOME": str(tmp_path / "home"), "LD_LIBRARY_PATH": f"{prefix}/lib", "CMAKE_PREFIX_PATH": f"{prefix}:/usr",
        "PYTHONPATH": f"{prefix}/lib/python3/dist-packages",
    }
    found = subprocess.run(["rospack", "find", "roar_ros"], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert found.stdout.strip() == f"{prefix}/share/roar_ros", found.stdout + found.stderr
    out = tmp_path / "out"
    race = subprocess.run(["roslaunch", "-p", "11634", "roar_ros", "race.launch", "map:=roar_sprint", "laps:=1",
                           "real_time_factor:=0", f"output_dir:={out}"], capture_output=True, text=True, env=env,
                          cwd=tmp_path, timeout=240)
    assert (out / "results.yaml").exists(), race.stdout[-3000:] + race.stderr[-3000:]
    results = yaml.safe_load((out / "results.yaml").read_text())
    assert results["status"] == "finished"
    assert results["cars"][0]["laps_completed"] == 1
    assert (out / "trajectories.png").exists()
    python = subprocess.run(["/usr/bin/python3", "-c", "import roar_rl, roar_py_ros; print(roar_rl.__file__); "
                             "print(roar_rl.vector_env.ROOT); print(roar_rl.available_maps())"],
                            capture_output=True, text=True, env=env, cwd=tmp_path, timeout=60)
    lines = python.stdout.splitlines()
    assert python.returncode == 0 and len(lines) == 3, python.stdout + python.stderr
    assert lines[0].startswith(prefix) and lines[1] == f"{prefix}/share/roar_ros", lines
    assert "roar_sprint" in lines[2]
