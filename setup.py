# Built and installed by catkin (catkin_python_setup in CMakeLists.txt), not by pip.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import find_packages, setup

setup(**generate_distutils_setup(packages=find_packages("python"), package_dir={"": "python"}))
