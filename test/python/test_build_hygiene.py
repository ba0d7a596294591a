"""scripts/setup installs what the build uses: every header the compiler read and every library the
programs link comes from a package scripts/setup names or from one of their dependencies (as dpkg has
them installed), so a fresh machine builds with what setup installs."""
import glob
import os
import re
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def setup_packages():
    with open(os.path.join(REPO, "scripts", "setup")) as f:
        block = re.search(r"^packages=\((.*?)^\)", f.read(), re.S | re.M).group(1)
    return {word for line in block.splitlines() for word in line.split("#")[0].split()}


def installed_closure(packages):
    """The packages and everything they depend on (Depends, Pre-Depends), as installed."""
    seen, todo = set(), list(packages)
    while todo:
        batch = [p for p in set(todo) if p not in seen]
        todo = []
        seen.update(batch)
        if not batch:
            break
        out = subprocess.run(["dpkg-query", "-W", "-f", "${Package}\t${Depends}, ${Pre-Depends}\t${Provides}\n"] + batch,
                             capture_output=True, text=True).stdout
        for line in out.splitlines():
            _, depends, provides = (line.split("\t") + ["", ""])[:3]
            for alternative in depends.split(","):
                for name in alternative.split("|"):
                    name = name.strip().split(" ")[0].split(":")[0]
                    if name and name not in seen:
                        todo.append(name)
    # Virtual packages are satisfied by what provides them: add the providers that are installed.
    out = subprocess.run(["dpkg-query", "-W", "-f", "${Package}\t${Provides}\n"], capture_output=True, text=True).stdout
    for line in out.splitlines():
        package, provides = (line.split("\t") + [""])[:2]
        names = {p.strip().split(" ")[0] for p in provides.split(",") if p.strip()}
        if names & seen:
            seen.add(package)
    return seen


def owners(paths):
    """The Debian packages that own these files (files of none are left out)."""
    found = set()
    paths = sorted({os.path.realpath(p) for p in paths if os.path.exists(p)})
    for i in range(0, len(paths), 200):
        out = subprocess.run(["dpkg", "-S"] + paths[i:i + 200], capture_output=True, text=True).stdout
        for line in out.splitlines():
            for name in line.split(": ")[0].split(","):
                found.add(name.strip().split(":")[0])
    return found


def test_every_header_and_library_the_build_uses_comes_from_what_setup_installs():
    depfiles = glob.glob(os.path.join(REPO, "build", "CMakeFiles", "*", "**", "*.o.d"), recursive=True)
    assert depfiles, "no compiler dependency files: build first (make build)"
    headers = set()
    for path in depfiles:
        with open(path) as f:
            headers.update(w for w in f.read().replace("\\\n", " ").split() if w.startswith("/usr/"))
    programs = glob.glob(os.path.join(REPO, "devel", "lib", "roar_ros", "*")) + glob.glob(os.path.join(REPO, "devel", "lib", "*.so"))
    libraries = set()
    for program in programs:
        out = subprocess.run(["ldd", program], capture_output=True, text=True).stdout
        libraries.update(re.findall(r"=> (/\S+)", out))
    used = owners(headers) | owners(libraries)
    assert len(used) > 20, used
    missing = used - installed_closure(setup_packages())
    assert not missing, "used by the build but not installed by scripts/setup (nor a dependency): %s" % sorted(missing)


# The stack may drive a real car or another simulator: what it is built from never reaches the simulator.
STACK_LIBRARIES = {"roar_planning": "planning", "roar_control": "control", "roar_race": "race", "roar_vehicle": "vehicle"}


def cmake_links(target):
    with open(os.path.join(REPO, "CMakeLists.txt")) as f:
        text = f.read()
    match = re.search(r"target_link_libraries\(%s\s([^)]*)\)" % re.escape(target), text)
    assert match, f"no target_link_libraries for {target} in CMakeLists.txt"
    return set(match.group(1).split())


def test_the_stack_libraries_neither_link_nor_include_the_simulator():
    for target, module in STACK_LIBRARIES.items():
        assert "roar_sim_core" not in cmake_links(target), f"{target} links the simulator library"
        for folder in (os.path.join(REPO, "include", "roar", module), os.path.join(REPO, "src", module)):
            for path in glob.glob(os.path.join(folder, "**", "*.*"), recursive=True):
                with open(path) as f:
                    included = re.findall(r'#include "roar/(sim|sensors)/', f.read())
                assert not included, f"{os.path.relpath(path, REPO)} includes the simulator's headers"


# The racing stack's programs, as a real car would run them: none links the simulator, its sensors, the RL
# environment or Bullet, nor compiles a header that reaches them.
STACK_PROGRAMS = ("planner", "controller", "race_control", "waypoint_server")
SIMULATOR_LIBRARIES = re.compile(r"lib(roar_sim_core|roar_sensors|roar_rl|roar_harness|roar_ros_sim_bridge|Bullet[\w-]*|"
                                 r"LinearMath[\w-]*|embree\d*)\.so")
SIMULATOR_HEADERS = re.compile(r"include/roar/(sim/world|sim/vehicle_dynamics|sensors/ray_scene|rl/racing_env|stack/\w+)\.h"
                               r"|/bullet/|/embree\d*/")


def test_the_stack_programs_neither_link_nor_compile_the_simulator():
    for program in STACK_PROGRAMS:
        path = os.path.join(REPO, "devel", "lib", "roar_ros", program)
        assert os.path.exists(path), f"{program} is not built: build first (make build)"
        ldd = subprocess.run(["ldd", path], capture_output=True, text=True).stdout
        linked = {m.group(0) for m in SIMULATOR_LIBRARIES.finditer(ldd)}
        assert not linked, f"{program} links {sorted(linked)}"
        objects = glob.glob(os.path.join(REPO, "build", "CMakeFiles", f"{program}.dir", "**", "*.o.d"), recursive=True)
        assert objects, f"no compiler dependency files for {program}"
        for depfile in objects:
            with open(depfile) as f:
                reached = {m.group(0) for m in SIMULATOR_HEADERS.finditer(f.read())}
            assert not reached, f"{program} compiles the simulator's headers: {sorted(reached)}"
    # The bridge those programs link is the stack's part alone.
    assert not {"roar_sim_core", "roar_sensors", "roar_rl", "roar_harness"} & cmake_links("roar_ros_bridge")


def test_the_roar_py_modules_do_not_pull_in_the_rl_extension():
    # roar_py_ros found the package through roar_rl; roar_paths is the one answer of where it is.
    out = subprocess.run([sys.executable, "-c", "import sys, roar_py_ros, roar_py_remote; "
                          "print(sorted(m for m in sys.modules if m.split('.')[0] in ('roar_rl', 'roar_rl_core', 'torch')))"],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"


def test_the_package_layout_is_written_once():
    """The package's folders and its default model and map have one owner, include/roar/config/package_layout.h
    (roar_core.package_layout, DEFAULT_MODEL and DEFAULT_MAP on the Python side): no other file builds such a
    path or names such a default, and the launch files' defaults are the same."""
    import xml.etree.ElementTree as ET

    import roar_core

    owner = os.path.join("include", "roar", "config", "package_layout.h")
    forms = re.compile(r'"/config/|"config", "|/ "config"|"/urdf"|"/maps"|"sedan"|"roar_ring"')
    written = []
    for folder in ("src", "include", "bench", "python", "scripts"):
        for path in glob.glob(os.path.join(REPO, folder, "**", "*"), recursive=True):
            if not path.endswith((".cpp", ".h", ".py")) or os.path.relpath(path, REPO) == owner:
                continue
            with open(path) as f:
                for number, line in enumerate(f, 1):
                    # A benchmark of a named circuit names it.
                    if forms.search(line) and "BENCHMARK_CAPTURE" not in line:
                        written.append(f"{os.path.relpath(path, REPO)}:{number}: {line.strip()}")
    assert written == [], "the package's layout or defaults written again:\n" + "\n".join(written)
    for launch in glob.glob(os.path.join(REPO, "launch", "*.launch")):
        for arg in ET.parse(launch).getroot().iter("arg"):
            default = arg.get("default")
            if arg.get("name") == "model" and default:
                assert default == roar_core.DEFAULT_MODEL, f"{launch}: model defaults to {default}"
            if arg.get("name") == "map" and default:
                assert default == roar_core.DEFAULT_MAP, f"{launch}: map defaults to {default}"


def test_every_pytest_suite_runs_in_make_test():
    with open(os.path.join(REPO, "CMakeLists.txt")) as f:
        suites = set(re.search(r"foreach\(suite ([^)]*)\)", f.read()).group(1).split())
    files = {os.path.basename(p)[len("test_"):-len(".py")] for p in glob.glob(os.path.join(REPO, "test", "python",
                                                                                          "test_*.py"))}
    assert files - suites == set(), "pytest suites that make test does not run (CMakeLists.txt's foreach(suite ...))"
