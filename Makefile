# The two commands of README.md: `make race` and `make test`. Both set up the machine first (scripts/setup
# installs only what is missing) and build. Debian's ROS needs Debian's python, hence /usr/bin first.
SHELL := /bin/bash
BUILD := build
# The devel space sits beside build/, not in it: rosrun skips every path under <package>/build/, and the
# package is the repository root.
DEVEL := devel
export PATH := /usr/bin:$(PATH)
MAKEFLAGS += --no-print-directory

.PHONY: all setup build race test bench clean
all: build

setup:
	@bash scripts/setup

build: setup
	@# catkin writes the test environment (setup_cached.sh) at configure time with only the folders that
	@# exist then: the generated Python messages' folder must exist before the first configure.
	@mkdir -p $(BUILD) $(DEVEL)/lib/python3/dist-packages
	@cmake -S . -B $(BUILD) -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_DEVEL_PREFIX=$(CURDIR)/$(DEVEL) \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCATKIN_ENABLE_TESTING=ON > $(BUILD)/configure.log 2>&1 \
	  || { cat $(BUILD)/configure.log; exit 1; }
	@# Up-to-date targets are not news: only what is built (and any error) is printed.
	@set -o pipefail; cmake --build $(BUILD) -j2 | sed -u '/Built target/d'

race: build
	@bash scripts/race

test: build
	@bash scripts/test

bench: build
	@$(DEVEL)/lib/roar_ros/roar_bench
	@# ROAR_PY's loop beside the C++ figures: the official runner's set-up against the bare step, one core.
	@bash -c 'source scripts/ros_env.sh > /dev/null && /usr/bin/python3 bench/roar_py_bench.py'

clean:
	rm -rf $(BUILD) $(DEVEL)
