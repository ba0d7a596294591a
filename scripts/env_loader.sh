#!/usr/bin/env bash
# roslaunch's env-loader for a machine of a multi-machine launch (launch/two_machines.launch): the built
# package's ROS environment on that machine, then the command roslaunch asks for. Each machine needs its
# own checkout built with `make build` at the path the <machine env-loader="..."> attribute names.
source "$(dirname "${BASH_SOURCE[0]}")/ros_env.sh"
exec "$@"
