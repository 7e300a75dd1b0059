# Tonge–Ramesh damage studies (issue 4). Targets:
#   damage-rate-curve : single-element peak tensile/compressive strength vs strain rate (1e1..1e6 1/s)
#   damage-brazilian  : dynamic Brazilian disk of basalt in mpm-frag (see pipelines/damage/README.md)
#   damage-bench      : Google Benchmark of the model (label bench)
# Included by pipelines/Makefile, which declares ROOT, BUILD, RUNS, PY and JOBS.
DAMAGE_DIR := $(ROOT)/pipelines/damage

.PHONY: damage-rate-curve damage-brazilian damage-bench

damage-rate-curve: ## TR single-element strength vs strain rate 1e1..1e6 1/s (table + PNG)
	cmake --build $(BUILD) --target damage_rate_curve -j $(JOBS)
	mkdir -p $(RUNS)/damage-rate-curve
	$(BUILD)/tests/damage/damage_rate_curve $(RUNS)/damage-rate-curve/rate_curve.csv 1e-9 5
	$(PY) $(DAMAGE_DIR)/plot_rate_curve.py $(RUNS)/damage-rate-curve/rate_curve.csv $(RUNS)/damage-rate-curve

damage-bench: ## TR model benchmark (us per particle-step, model share of a step)
	cmake --build $(BUILD) --target bench_damage -j $(JOBS)
	mkdir -p $(RUNS)/damage-bench
	$(BUILD)/tests/damage/bench_damage --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/damage-bench/bench.json --benchmark_out_format=json

# Brazilian disk: DAMAGE_BZ_CELL = 1e-4 is the issue's 0.1 mm resolution (~95k particles in the
# half-thickness model; ~1 h per low rate on 2 shared cores); 4e-4 is the affordable default
# here. Nominal platen rates 2v/D chosen so that the effective rate (d sigma_t/dt)/E spans
# ~20..300 1/s.
DAMAGE_BZ_CELL ?= 4e-4
DAMAGE_BZ_RATES ?= 60 100 200 350 600
damage-brazilian: ## dynamic Brazilian disk of basalt vs strain rate + damage field (mpm-frag)
	cmake --build $(BUILD) --target damage_brazilian -j $(JOBS)
	rm -f $(RUNS)/damage-brazilian/summary.csv
	$(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian $(RUNS)/damage-brazilian $(DAMAGE_BZ_CELL) 0.3 $(DAMAGE_BZ_RATES)
	$(PY) $(DAMAGE_DIR)/plot_brazilian.py $(RUNS)/damage-brazilian $(DAMAGE_BZ_CELL) 0.3

# Resolution / time-step study at one rate: h = 0.4, 0.2, 0.1 mm (Courant 0.3) and Courant 0.15 at 0.4 and 0.2 mm.
damage-brazilian-convergence: ## Brazilian strength vs resolution / Courant vs wall time
	cmake --build $(BUILD) --target damage_brazilian -j $(JOBS)
	rm -f $(RUNS)/damage-brazilian-convergence/summary.csv
	$(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian $(RUNS)/damage-brazilian-convergence 4e-4 0.3 1000
	$(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian $(RUNS)/damage-brazilian-convergence 4e-4 0.15 1000
	$(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian $(RUNS)/damage-brazilian-convergence 2e-4 0.3 1000
	$(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian $(RUNS)/damage-brazilian-convergence 2e-4 0.15 1000
	$(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian $(RUNS)/damage-brazilian-convergence 1e-4 0.3 1000
	$(PY) $(DAMAGE_DIR)/plot_convergence.py $(RUNS)/damage-brazilian-convergence

# Flaw sampling: per-particle Poisson draws (El Mir, default) against the expected bin densities
# (flaw_sampling = "expected"), at each cell size of DAMAGE_BZ_SAMPLING_CELLS (add 1e-4 for the
# 0.1 mm runs: about an hour each sampling on 2 cores). Table + plot in runs/damage-brazilian-sampling.
DAMAGE_BZ_SAMPLING_CELLS ?= 4e-4 2e-4
DAMAGE_BZ_SAMPLING_RATES ?= 100 200 350 600 1000
damage-brazilian-sampling: ## Brazilian strength vs rate with Poisson and expected flaw sampling, several cell sizes
	cmake --build $(BUILD) --target damage_brazilian -j $(JOBS)
	for s in poisson expected; do rm -f $(RUNS)/damage-brazilian-sampling/$$s/summary.csv; \
	  for h in $(DAMAGE_BZ_SAMPLING_CELLS); do SAMPLING=$$s $(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian \
	    $(RUNS)/damage-brazilian-sampling/$$s $$h 0.3 $(DAMAGE_BZ_SAMPLING_RATES) || exit $$?; done; done
	$(PY) $(DAMAGE_DIR)/plot_sampling.py $(RUNS)/damage-brazilian-sampling \
	  poisson=$(RUNS)/damage-brazilian-sampling/poisson expected=$(RUNS)/damage-brazilian-sampling/expected
