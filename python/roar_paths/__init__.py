"""Where the roar_ros package is (its maps, configs, launch files): the one answer every Python module of
roar_ros takes, with or without ROS; its folders and default model and map are the C++ side's
(config::PackageLayout, through roar_core)."""
import functools
import typing
from pathlib import Path


def package_root() -> Path:
    """The source tree these modules are in (run from the devel space), else ROS's own answer: an
    installed package's share folder."""
    here = Path(__file__).resolve().parents[2]
    if (here / "package.xml").exists():
        return here
    import rospkg  # only installed: rospkg finds the share folder through ROS_PACKAGE_PATH
    return Path(rospkg.RosPack().get_path("roar_ros"))


@functools.lru_cache(maxsize=None)
def layout() -> typing.Dict[str, Path]:
    """The package's folders: maps, urdf, vehicles (car models), sensors, scenarios, rl, policies."""
    import roar_core  # the C++ side's answer (a compiled module: imported when first asked)
    return {kind: Path(folder) for kind, folder in roar_core.package_layout(str(package_root())).items()}


def default_model() -> str:
    import roar_core
    return roar_core.DEFAULT_MODEL


def default_map() -> str:
    import roar_core
    return roar_core.DEFAULT_MAP
