"""Where the roar_ros package is (its maps, configs, launch files): the one answer every Python module of
roar_ros takes, with or without ROS."""
from pathlib import Path


def package_root() -> Path:
    """The source tree these modules are in (run from the devel space), else ROS's own answer: an
    installed package's share folder."""
    here = Path(__file__).resolve().parents[2]
    if (here / "package.xml").exists():
        return here
    import rospkg  # only installed: rospkg finds the share folder through ROS_PACKAGE_PATH
    return Path(rospkg.RosPack().get_path("roar_ros"))
