# ssdem-grav studies (issue 6). Targets:
#   nbody-accuracy : rubble pile + two-body reaccumulation; energy and final-position error against
#                    a reference run (small dt, theta = 0.2, gravity every step) across dt, opening
#                    angle and gravity update interval, versus wall time (table + PNG)
#   nbody-bench    : Google Benchmark, self-gravitating pile of 5e4 and 2e5 spheres, 1 and 2 threads
#   nbody-collapse : 1e5 spheres collapsing from a cold cloud into one pile (tree sanity, energy)
ROOT ?= $(abspath $(dir $(lastword $(MAKEFILE_LIST)))/../..)
BUILD ?= $(ROOT)/build
RUNS ?= $(ROOT)/runs
PY ?= /usr/bin/python3
NBODY_DIR := $(ROOT)/pipelines/nbody

.PHONY: nbody-accuracy nbody-bench nbody-collapse

nbody-accuracy: ## ssdem-grav error vs wall time across dt, theta, gravity interval (table, PNG)
	cmake --build $(BUILD) --target ssdem-grav -j2
	mkdir -p $(RUNS)/nbody-accuracy
	$(PY) $(NBODY_DIR)/accuracy.py $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-accuracy

nbody-bench: ## ssdem-grav throughput: us per particle-step per core (1, 2 threads), phases, bytes/sphere
	cmake --build $(BUILD) --target bench_nbody -j2
	mkdir -p $(RUNS)/nbody-bench
	$(BUILD)/tests/nbody/bench_nbody --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/nbody-bench/bench.json --benchmark_out_format=json
	$(PY) $(NBODY_DIR)/bench_table.py $(RUNS)/nbody-bench/bench.json $(RUNS)/nbody-bench

nbody-collapse: ## 1e5 spheres collapsing to one region: tree sanity and energy (table, PNG)
	cmake --build $(BUILD) --target ssdem-grav -j2
	mkdir -p $(RUNS)/nbody-collapse
	$(PY) $(NBODY_DIR)/collapse.py $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-collapse
