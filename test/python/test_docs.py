"""The README and doc/ pages are true of the code: doc/ros_api.md names every topic, service and private
parameter each node has (and none it has not), the overtaking options with their defaults, and every
command, launch argument, program option, test and file the pages show exists."""
import glob
import os
import re
import shlex

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
API = os.path.join(REPO, "doc", "ros_api.md")
PAGES = [os.path.join(REPO, "README.md")] + sorted(glob.glob(os.path.join(REPO, "doc", "*.md")))

# Each node's own sources; the shared readers' are everyone's (doc/ros_api.md, "Parameters every node shares").
NODE_SOURCES = {
    "roar_sim": ["src/nodes/roar_sim_node.cpp", "src/ros/sim_node.cpp", "src/ros/sim_parameters.cpp",
                 "src/ros/sim_services.cpp", "src/ros/vehicle_sensors.cpp", "src/ros/agent_interface.cpp"],
    "waypoint_server": ["src/nodes/waypoint_server_node.cpp"],
    "planner": ["src/nodes/planner_node.cpp"],
    "controller": ["src/nodes/controller_node.cpp"],
    "race_control": ["src/nodes/race_control_node.cpp"],
    "car_models": ["src/nodes/car_models_node.cpp"],
    "race_recorder": ["src/nodes/race_recorder_node.cpp"],
    "policy_driver": ["src/nodes/policy_driver_node.cpp"],
}
SHARED_SOURCES = ["src/ros/scenario_params.cpp", "src/ros/param_reading.cpp", "src/ros/sim_map_follower.cpp"]

PARAM_CALL = re.compile(r'\b(?:read[A-Z]\w*|getParam|hasParam|readRule)\(\s*(?:[\w.]+,\s*)?"([a-z_][a-z0-9_/]*)"')
TOPIC_CALL = re.compile(r'\b(?:advertise\w*|subscribe|serve)\s*(?:<[^>]*>)?\(([^;]*?)[,)]', re.S)


def read(path):
    with open(os.path.join(REPO, path), encoding="utf-8") as f:
        return f.read()


def sections(text, level):
    """The page's sections of that heading level: {title: body}."""
    marker = "#" * level + " "
    found, title, body = {}, None, []
    for line in text.splitlines():
        if line.startswith(marker):
            if title:
                found[title] = "\n".join(body)
            title, body = line[len(marker):].strip().strip("`"), []
        elif title and re.match(r"^#{1,%d} " % level, line):
            found[title], title = "\n".join(body), None
        elif title:
            body.append(line)
    if title:
        found[title] = "\n".join(body)
    return found


def params_read(paths):
    return {name for p in paths for name in PARAM_CALL.findall(read(p))}


def documented_params(text):
    return set(re.findall(r"`~([a-z_][a-z0-9_/]*)`", text))


API_TEXT = read("doc/ros_api.md")
NODES = sections(API_TEXT, 2)
SHARED = documented_params(NODES["Parameters every node shares"])


@pytest.mark.parametrize("node", sorted(NODE_SOURCES))
def test_every_parameter_a_node_reads_is_documented_and_no_other(node):
    section = NODES[node]
    own = params_read(NODE_SOURCES[node])
    documented = documented_params(section)
    if node == "planner":  # the overtaking options, read through their table
        own |= {name.replace(".", "/") for name in
                re.findall(r'\{"([a-z_]+\.[a-z_]+)"', read("src/planning/overtaking/option_table.cpp"))}
    missing = own - documented - SHARED
    assert not missing, f"{node} reads {sorted(missing)}, which doc/ros_api.md does not document"
    unknown = documented - own - params_read(SHARED_SOURCES)
    assert not unknown, f"doc/ros_api.md documents {sorted(unknown)} for {node}, which it does not read"


def test_the_shared_parameters_are_the_shared_readers():
    assert SHARED - {"model"} == params_read(SHARED_SOURCES)


@pytest.mark.parametrize("node", sorted(NODE_SOURCES))
def test_every_topic_and_service_of_a_node_is_documented(node):
    section = NODES[node]
    for path in NODE_SOURCES[node]:
        for args in TOPIC_CALL.findall(read(path)):
            for literal in re.findall(r'"([A-Za-z_/][A-Za-z0-9_/]*)"', args):
                name = literal.strip("/")
                if name:
                    assert name in section, f"{path}: '{literal}' is not in doc/ros_api.md's section on {node}"


def test_the_overtaking_defaults_shown_are_the_codes():
    header = read("include/roar/planning/overtaking/options.h") + read("include/roar/vehicle/slipstream.h")
    defaults = {}
    for struct, body in re.findall(r"struct (\w+) \{(.*?)\n {0,2}\}", header, re.S):
        for name, value in re.findall(r"(?:double|int|bool) (\w+) = ([\w.:]+);", body):
            defaults[(struct.lower(), name)] = value
    groups = {"margins": "margins", "prediction": "prediction", "moves": "moves", "passing": "passing",
              "guard": "guard", "blue_flags": "blueflags", "defence": "defence", "slipstream": "slipstreamoptions"}
    shown = re.findall(r"`~([a-z_]+)/([a-z_]+)` \(([^)]+)\)", NODES["planner"])
    assert len(shown) >= 30
    for group, name, said in shown:
        code = defaults[(groups[group], name)]
        first = said.split(";")[0].split()[0]
        if code in ("true", "false"):
            assert first == code, (group, name, said, code)
        elif re.match(r"^[0-9.]+$", code):
            assert float(first) == float(code), (group, name, said, code)


# ---- commands the pages show ----

def code_text(text):
    """Inline code spans and fenced blocks of a page."""
    blocks = re.findall(r"```[a-z]*\n(.*?)```", text, re.S)
    inline = re.findall(r"`([^`\n]+)`", re.sub(r"```.*?```", "", text, flags=re.S))
    return blocks + inline


def command_lines():
    for page in PAGES:
        for chunk in code_text(read(page)):
            for line in chunk.splitlines():
                line = line.split(" #")[0].strip()
                if line:
                    yield os.path.relpath(page, REPO), line


def launch_args(launch):
    return set(re.findall(r'<arg name="([^"]+)"', read(os.path.join("launch", launch))))


def words(line):
    try:
        return shlex.split(line)
    except ValueError:
        return line.split()


def test_every_launch_argument_shown_is_declared():
    checked = 0
    for page, line in command_lines():
        w = words(line)
        if "roslaunch" in w and "roar_ros" in w:
            i = w.index("roslaunch")
            launch = w[i + 2] if len(w) > i + 2 else ""
            assert os.path.exists(os.path.join(REPO, "launch", launch)), (page, line)
            args = w[i + 3:]
        elif w and w[0] in ("scripts/race", "bash") and "scripts/race" in w:
            launch, args = "race.launch", w[w.index("scripts/race") + 1:]
        else:
            continue
        for arg in args:
            if ":=" in arg:
                name = arg.split(":=")[0]
                assert name in launch_args(launch), f"{page}: `{line}`: {launch} declares no argument '{name}'"
                checked += 1
    assert checked >= 10


def test_every_program_and_option_shown_exists():
    sources = {
        "roar_bench": read("bench/roar_bench.cpp") + read("bench/traffic_table.cpp"),
        "track_tool": read("src/tools/track_tool.cpp"),
        "rl_train": read("src/tools/rl_train.cpp"),
    }
    checked = 0
    for page, line in command_lines():
        w = words(line)
        for i, word in enumerate(w):
            program = os.path.basename(word)
            if program in sources and (word == program or word.endswith("/" + program) or word == "$T"):
                for option in w[i + 1:]:
                    if option.startswith("--") and not option.startswith("--benchmark"):
                        flag = option.split("=")[0]
                        assert f'"{flag}' in sources[program], f"{page}: `{line}`: {program} has no {flag}"
                        checked += 1
        if w[:1] == ["$T"] and len(w) > 1:
            assert f'"{w[1]}"' in sources["track_tool"], f"{page}: `{line}`: track_tool has no {w[1]}"
    assert checked >= 5


def test_every_rosrun_rostest_and_make_target_shown_exists():
    makefile = read("Makefile")
    executables = set(os.listdir(os.path.join(REPO, "devel", "lib", "roar_ros"))) | set(os.listdir(
        os.path.join(REPO, "scripts")))
    checked = 0
    for page, line in command_lines():
        w = words(line)
        if w[:2] == ["rosrun", "roar_ros"] and len(w) > 2 and "<" not in w[2]:
            assert w[2] in executables, f"{page}: `{line}`: no executable {w[2]}"
            checked += 1
        if w[:2] == ["rostest", "roar_ros"] and len(w) > 2:
            assert os.path.exists(os.path.join(REPO, "test", "integration", w[2])), f"{page}: `{line}`"
            checked += 1
        if w[:1] == ["make"] and len(w) > 1:
            assert re.search(rf"^{re.escape(w[1])}:", makefile, re.M), f"{page}: `{line}`: no make target {w[1]}"
            checked += 1
    assert checked >= 5


def test_every_file_and_folder_named_exists():
    missing = []
    for page in PAGES:
        text = read(page)
        for path in re.findall(r"`((?:scripts|launch|config|maps|urdf|test|bench|include|src|python|doc|msg|srv|cfg)"
                               r"/[A-Za-z0-9_./-]+)`", text):
            if "<" in path or "*" in path:
                continue
            if not os.path.exists(os.path.join(REPO, path.rstrip("/"))):
                missing.append((os.path.relpath(page, REPO), path))
        for link in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", text):
            target = os.path.normpath(os.path.join(os.path.dirname(page), link))
            if not os.path.exists(target):
                missing.append((os.path.relpath(page, REPO), link))
    assert not missing, missing


def anchor(heading):
    return re.sub(r"[^a-z0-9_ -]", "", heading.strip().lower()).replace(" ", "-")


def test_every_link_to_a_section_finds_it():
    broken = []
    for page in PAGES:
        for link, section in re.findall(r"\]\(([^)#:]*)#([^)]+)\)", read(page)):
            target = os.path.normpath(os.path.join(os.path.dirname(page), link)) if link else page
            headings = {anchor(h) for h in re.findall(r"^#+ (.*)$", read(target), re.M)}
            if section not in headings:
                broken.append((os.path.relpath(page, REPO), f"{link}#{section}"))
    assert not broken, broken


def test_every_named_test_exists():
    cases, tests = {}, set()
    for path in glob.glob(os.path.join(REPO, "test", "unit", "*_test.cpp")):
        name = os.path.basename(path)[:-4]
        tests.add(name)
        cases[name] = set(re.findall(r"^TEST(?:_F|_P)?\(\w+, (\w+)\)", read(path), re.M))
    for path in glob.glob(os.path.join(REPO, "test", "integration", "*.test")):
        tests.add(os.path.basename(path)[:-5])
    for path in glob.glob(os.path.join(REPO, "test", "python", "*.py")):
        tests |= {os.path.basename(path), os.path.basename(path)[:-3]}
        tests |= set(re.findall(r"^def (test_\w+)", read(path), re.M))
    unknown = []
    for page in PAGES:
        text = read(page)
        for name in re.findall(r"`([a-z_]+_test|test_[a-z0-9_]+(?:\.py)?)`", text):
            if name not in tests:
                unknown.append((os.path.relpath(page, REPO), name))
        for test, case in re.findall(r"`([a-z_]+_test)`\s+`([A-Z]\w+)`", text):
            if case not in cases.get(test, ()):
                unknown.append((os.path.relpath(page, REPO), f"{test} {case}"))
    assert not unknown, unknown
