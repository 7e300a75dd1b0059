# Tonge–Ramesh damage studies (issue 4). Targets:
#   damage-rate-curve : single-element peak tensile/compressive strength vs strain rate (1e1..1e6 1/s)
#   damage-brazilian  : dynamic Brazilian disk of basalt in mpm-frag (see pipelines/damage/README.md)
#   damage-bench      : Google Benchmark of the model (label bench)
ROOT ?= $(abspath $(dir $(lastword $(MAKEFILE_LIST)))/../..)
BUILD ?= $(ROOT)/build
RUNS ?= $(ROOT)/runs
PY ?= /usr/bin/python3
DAMAGE_DIR := $(ROOT)/pipelines/damage

.PHONY: damage-rate-curve damage-brazilian damage-bench

damage-rate-curve:
	cmake --build $(BUILD) --target damage_rate_curve -j2
	mkdir -p $(RUNS)/damage-rate-curve
	$(BUILD)/tests/damage/damage_rate_curve $(RUNS)/damage-rate-curve/rate_curve.csv 1e-9 5
	$(PY) $(DAMAGE_DIR)/plot_rate_curve.py $(RUNS)/damage-rate-curve/rate_curve.csv $(RUNS)/damage-rate-curve

damage-bench:
	cmake --build $(BUILD) --target bench_damage -j2
	mkdir -p $(RUNS)/damage-bench
	$(BUILD)/tests/damage/bench_damage --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/damage-bench/bench.json --benchmark_out_format=json
