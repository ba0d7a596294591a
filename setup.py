# Built and installed by catkin (catkin_python_setup in CMakeLists.txt), not by pip.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["roar_py_interface", "roar_py_ros", "roar_rl"], package_dir={"": "python"}))
