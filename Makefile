# jaka_driver — every target sets up what is missing first (scripts/setup.sh is idempotent).
SHELL := /bin/bash
ENV   := source devel/setup.bash &&
MODEL ?= zu5
BACKEND ?= sim
PYTEST_ARGS ?=
# make test's worker processes (pytest-xdist), measured on 2 cores shared with other sessions:
# 3 workers 304-308 s (2201 tests, load 1-2), 370 s with both cores kept busy by two other
# programs, green in both; 4 workers 255 s, but a roscpp call of the C++ client failed once.
# The tests mostly wait on real-time motion: ~1.1 cores busy on average with 3
TEST_WORKERS ?= 3

.PHONY: setup run test unit fuzz bench emulator clean

setup:
	@scripts/setup.sh

## Start rosmaster (if none is running) and the driver on the MuJoCo twin.
run: setup
	@$(ENV) roslaunch jaka_driver jaka_driver.launch backend:=$(BACKEND) model:=$(MODEL)

## The whole suite: test/unit, test/integration (MuJoCo, TCP, no ROS), test/ros (rosmaster, node),
## on TEST_WORKERS processes (a module's tests stay on one: test/conftest.py; 0 runs in this one).
test: setup
	@$(ENV) python -m pytest test -n $(TEST_WORKERS) $(PYTEST_ARGS)

## The unit layer only: no rosmaster, no subprocess, seconds.
unit: setup
	@$(ENV) python -m pytest test/unit $(PYTEST_ARGS)

## 10 000 random requests per service (the suite runs 200).
fuzz: setup
	@$(ENV) JAKA_FUZZ_EXAMPLES=10000 python -m pytest test -m fuzz $(PYTEST_ARGS)

## Benchmarks with targets; writes bench/results/latest.{json,md}. Arguments of python -m bench
## pass through ARGS (make bench ARGS="--only controller --quick"), or RUNS / ONLY:
## make bench RUNS=3 ONLY=sim,streams,controller = python -m bench --runs 3 --only sim,...
RUNS ?=
ONLY ?=
ARGS ?=
bench: setup
	@$(ENV) python -m bench $(if $(RUNS),--runs $(RUNS)) $(if $(ONLY),--only $(ONLY)) $(ARGS)

## The controller emulator (JAKA TCP protocol on 127.0.0.1:10001/10000) serving the twin.
emulator: setup
	@$(ENV) python -m jaka_driver.emulator --model $(MODEL)

clean:
	rm -rf devel build .pytest_cache
