# mpm-frag studies (issue 3). Targets:
#   mpm-convergence : MMS (uGIMP USL/MUSL/USF, linear USL; N = 4..32) and the planar Tillotson shock
#                     (25..400 cells per plate): table + PNG of error vs wall time with observed orders
#   mpm-bench       : Google Benchmark (elastic sphere 2.3e5 particles, Tillotson impact; 1 and 2 threads)
#   mpm-scenes      : run the example scenes in mpm/scenes
# Included by pipelines/Makefile, which declares ROOT, BUILD, RUNS, PY and JOBS.
MPM_DIR := $(ROOT)/pipelines/mpm
# Largest MMS grid (N = 32 takes a few minutes per variant on one core) and shock resolution.
MPM_MMS_MAX_N ?= 32
MPM_SHOCK_MAX_CELLS ?= 400

.PHONY: mpm-convergence mpm-bench mpm-scenes

mpm-convergence: ## MMS + Tillotson shock at 4+ resolutions: error vs wall time (table, PNG)
	cmake --build $(BUILD) --target mpm_convergence -j $(JOBS)
	mkdir -p $(RUNS)/mpm-convergence
	OMP_NUM_THREADS=1 $(BUILD)/tests/mpm/mpm_convergence $(RUNS)/mpm-convergence/convergence.csv $(MPM_MMS_MAX_N) $(MPM_SHOCK_MAX_CELLS)
	$(PY) $(MPM_DIR)/plot_convergence.py $(RUNS)/mpm-convergence/convergence.csv $(RUNS)/mpm-convergence

# OMP_WAIT_POLICY=passive by default: on a shared, oversubscribed machine spinning OpenMP threads
# distort the 2-thread timings badly; override with OMP_WAIT_POLICY=active on a quiet machine.
mpm-bench: ## mpm-frag throughput: us per particle-step per core, 1 and 2 threads, bytes/particle
	cmake --build $(BUILD) --target mpm_bench -j $(JOBS)
	mkdir -p $(RUNS)/mpm-bench
	OMP_WAIT_POLICY=$${OMP_WAIT_POLICY:-passive} $(BUILD)/tests/mpm/mpm_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/mpm-bench/bench.json --benchmark_out_format=json
	$(PY) $(MPM_DIR)/bench_table.py $(RUNS)/mpm-bench/bench.json $(RUNS)/mpm-bench

mpm-scenes: ## run the example scenes (elastic sphere, two spheres, basalt impact)
	cmake --build $(BUILD) --target mpm-frag -j $(JOBS)
	mkdir -p $(RUNS)/mpm-scenes
	cd $(RUNS)/mpm-scenes && for s in elastic_sphere two_spheres basalt_impact; do \
	  $(BUILD)/mpm/mpm-frag --scene $(ROOT)/mpm/scenes/$$s.toml --set output.directory=\"$(RUNS)/mpm-scenes/$$s\" || exit $$?; done
