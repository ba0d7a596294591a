# Sourced by scripts/race and scripts/test: the built package's ROS environment.
export PATH=/usr/bin:$PATH
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Debian's ROS profile scripts read unset variables: source them without `set -u`.
restore_u=$([[ $- == *u* ]] && echo 1 || true)
set +u
# shellcheck disable=SC1091
source "$root/devel/setup.bash"
[ -n "$restore_u" ] && set -u
export ROS_PACKAGE_PATH="$root${ROS_PACKAGE_PATH:+:$ROS_PACKAGE_PATH}"
export ROS_HOME="$root/build/ros_home"
export ROS_LOG_DIR="$root/build/ros_log"
mkdir -p "$ROS_HOME" "$ROS_LOG_DIR"
# Loopback unless the user asks for a network (ROS_IP or ROS_HOSTNAME of their own): ROS 1 has no
# authentication, and anyone who reaches the master can spawn, step or kill (README, "Security").
# roscpp's XML-RPC servers bind every interface whatever ROS_IP says: the loopback shim
# (src/tools/loopback_bind.cpp) turns those binds into loopback ones.
if [ -z "${ROS_IP:-}" ] && [ -z "${ROS_HOSTNAME:-}" ]; then
  export ROS_IP=127.0.0.1
  export ROS_MASTER_URI="${ROS_MASTER_URI:-http://127.0.0.1:11311}"
  if [ -f "$root/devel/lib/libroar_loopback.so" ]; then
    export LD_PRELOAD="$root/devel/lib/libroar_loopback.so${LD_PRELOAD:+:$LD_PRELOAD}"
  fi
fi
