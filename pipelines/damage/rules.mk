# Tonge–Ramesh damage studies (issue 4). Targets:
#   damage-rate-curve : single-element peak tensile/compressive strength vs strain rate (1e1..1e6 1/s)
#   damage-brazilian  : dynamic Brazilian disk of basalt, a user scene of mpm-frag (brazilian.toml)
#   damage-compression: uniaxial compression cylinder scene (compression.toml)
#   damage-bench      : Google Benchmark of the model (label bench)
# Included by pipelines/Makefile, which declares ROOT, BUILD, RUNS, PY and JOBS.
DAMAGE_DIR := $(ROOT)/pipelines/damage

.PHONY: damage-rate-curve damage-brazilian damage-compression damage-brazilian-convergence \
        damage-brazilian-sampling damage-bench

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

# Brazilian disk as a user scene (pipelines/damage/brazilian.toml) run by mpm-frag; the strength,
# the nominal rate 2v/D and the effective rates are read from its snapshots (lab_strength.py).
# Default flaw sampling scale_aware (issue 16). DAMAGE_BZ_CELL = 1e-4 is the issue's 0.1 mm
# (~78k disk particles; ~10 min per run on 2 cores); 4e-4 (~3 s per run) is the default here.
DAMAGE_BZ_CELL ?= 4e-4
DAMAGE_BZ_RATES ?= 100 200 400 800
DAMAGE_BZ_SEEDS ?= 1 2 3 4 5
DAMAGE_BZ_SAMPLING ?= scale_aware
MPM_FRAG = $(BUILD)/mpm/mpm-frag
damage-brazilian: ## dynamic Brazilian disk scene (mpm-frag) vs rate, seeds as error bars
	cmake --build $(BUILD) --target mpm-frag -j $(JOBS)
	rm -f $(RUNS)/damage-brazilian/scene_summary.csv
	for s in $(DAMAGE_BZ_SEEDS); do SEED=$$s SAMPLING=$(DAMAGE_BZ_SAMPLING) $(DAMAGE_DIR)/run_scene.sh $(MPM_FRAG) \
	  $(RUNS)/damage-brazilian $(DAMAGE_BZ_CELL) $(DAMAGE_BZ_RATES) || exit $$?; done
	$(PY) $(DAMAGE_DIR)/plot_study.py $(RUNS)/damage-brazilian $(RUNS)/damage-brazilian/scene_summary.csv --name brazilian
	$(PY) $(DAMAGE_DIR)/plot_damage_field.py $(RUNS)/damage-brazilian/$(DAMAGE_BZ_SAMPLING)_h$(DAMAGE_BZ_CELL)_r$(lastword $(DAMAGE_BZ_RATES))_s$(firstword $(DAMAGE_BZ_SEEDS)) \
	  $(RUNS)/damage-brazilian/damage_field.png

# Uniaxial compression of a 5 mm x 10 mm cylinder (pipelines/damage/compression.toml).
DAMAGE_UCS_CELL ?= 4e-4
DAMAGE_UCS_RATES ?= 100 300 1000
DAMAGE_UCS_SEEDS ?= 1 2 3
damage-compression: ## uniaxial compression cylinder scene (mpm-frag): compressive strength vs rate
	cmake --build $(BUILD) --target mpm-frag -j $(JOBS)
	rm -f $(RUNS)/damage-compression/scene_summary.csv
	for s in $(DAMAGE_UCS_SEEDS); do SEED=$$s SCENE=$(DAMAGE_DIR)/compression.toml $(DAMAGE_DIR)/run_scene.sh $(MPM_FRAG) \
	  $(RUNS)/damage-compression $(DAMAGE_UCS_CELL) $(DAMAGE_UCS_RATES) || exit $$?; done
	$(PY) $(DAMAGE_DIR)/plot_study.py $(RUNS)/damage-compression $(RUNS)/damage-compression/scene_summary.csv --name compression

# Resolution / time-step study at one nominal rate with the scene: h = 0.4, 0.2, 0.1 mm at
# Courant 0.3 and 0.15 (0.1 mm at 0.3 only unless DAMAGE_BZ_CONV_FINE_C15 = 1), seeds as spread;
# strength, wall and CPU time in convergence.md; damage_field_finest.png: crack onset, peak and
# post-peak damage of the first seed at the last (finest) cell size. The 0.1 mm runs take ~5 min
# each on 2 quiet cores (~500 CPU s).
# Nominal 200 1/s: ~100 1/s effective with the exact platen drive.
DAMAGE_BZ_CONV_RATE ?= 200
DAMAGE_BZ_CONV_SEEDS ?= 1 2 3 4 5
DAMAGE_BZ_CONV_CELLS ?= 4e-4 2e-4 1e-4
damage-brazilian-convergence: ## Brazilian scene strength vs resolution / Courant vs wall time (new default sampling)
	cmake --build $(BUILD) --target mpm-frag -j $(JOBS)
	rm -f $(RUNS)/damage-brazilian-convergence/scene_summary.csv
	for h in $(DAMAGE_BZ_CONV_CELLS); do for s in $(DAMAGE_BZ_CONV_SEEDS); do \
	  SEED=$$s $(DAMAGE_DIR)/run_scene.sh $(MPM_FRAG) $(RUNS)/damage-brazilian-convergence $$h $(DAMAGE_BZ_CONV_RATE) || exit $$?; \
	  if [ $$h != 1e-4 ] || [ "$(DAMAGE_BZ_CONV_FINE_C15)" = 1 ]; then SEED=$$s TAG=_c0.15 EXTRA="--set solver.courant=0.15" \
	    $(DAMAGE_DIR)/run_scene.sh $(MPM_FRAG) $(RUNS)/damage-brazilian-convergence $$h $(DAMAGE_BZ_CONV_RATE) || exit $$?; fi; \
	done; done
	$(PY) $(DAMAGE_DIR)/plot_study.py $(RUNS)/damage-brazilian-convergence $(RUNS)/damage-brazilian-convergence/scene_summary.csv --name convergence
	$(PY) $(DAMAGE_DIR)/plot_damage_field.py \
	  $(RUNS)/damage-brazilian-convergence/scale_aware_h$(lastword $(DAMAGE_BZ_CONV_CELLS))_r$(DAMAGE_BZ_CONV_RATE)_s$(firstword $(DAMAGE_BZ_CONV_SEEDS)) \
	  $(RUNS)/damage-brazilian-convergence/damage_field_finest.png

# Flaw sampling (test driver): scale-aware (default), per-particle Poisson draws (El Mir) and the
# expected bin densities (flaw_sampling = "expected"), at each cell size of DAMAGE_BZ_SAMPLING_CELLS (add 1e-4 for the
# 0.1 mm runs: about an hour each sampling on 2 cores). Table + plot in runs/damage-brazilian-sampling.
DAMAGE_BZ_SAMPLING_CELLS ?= 4e-4 2e-4
DAMAGE_BZ_SAMPLING_RATES ?= 100 200 350 600 1000
damage-brazilian-sampling: ## Brazilian strength vs rate with Poisson and expected flaw sampling, several cell sizes
	cmake --build $(BUILD) --target damage_brazilian -j $(JOBS)
	for s in scale_aware poisson expected; do rm -f $(RUNS)/damage-brazilian-sampling/$$s/summary.csv; \
	  for h in $(DAMAGE_BZ_SAMPLING_CELLS); do SAMPLING=$$s $(DAMAGE_DIR)/run_brazilian.sh $(BUILD)/tests/damage/damage_brazilian \
	    $(RUNS)/damage-brazilian-sampling/$$s $$h 0.3 $(DAMAGE_BZ_SAMPLING_RATES) || exit $$?; done; done
	$(PY) $(DAMAGE_DIR)/plot_sampling.py $(RUNS)/damage-brazilian-sampling \
	  scale_aware=$(RUNS)/damage-brazilian-sampling/scale_aware poisson=$(RUNS)/damage-brazilian-sampling/poisson \
	  expected=$(RUNS)/damage-brazilian-sampling/expected
