# ssdem-grav studies (issue 6). Targets:
#   nbody-accuracy : rubble pile + two-body reaccumulation; energy and final-position error against
#                    a reference run (small dt, theta = 0.2, gravity every step) across dt, opening
#                    angle, gravity update interval, the error-controlled cadence and multi-rate
#                    steps, versus wall time (table + PNG)
#   nbody-bench    : Google Benchmark, self-gravitating pile of 5e4 and 2e5 spheres, 1 and 2 threads
#   nbody-collapse : 1e5 spheres collapsing from a cold cloud into one pile; checks exit code,
#                    energy never created, half-mass radius against the cold collapse and shrinking
#                    (exit 1 if a check fails). COLLAPSE_N, COLLAPSE_T (end time in free-fall times)
#   nbody-collapse-smoke : the same at N = 2000 for 0.3 t_ff (a few seconds)
# Included by pipelines/Makefile, which declares ROOT, BUILD, RUNS, PY and JOBS.
NBODY_DIR := $(ROOT)/pipelines/nbody
COLLAPSE_N ?= 100000
COLLAPSE_T ?= 1.3

.PHONY: nbody-accuracy nbody-bench nbody-collapse nbody-collapse-smoke

nbody-accuracy: ## ssdem-grav error vs wall time across dt, theta, gravity interval, cadence, multi-rate (table, PNG)
	cmake --build $(BUILD) --target ssdem-grav -j $(JOBS)
	mkdir -p $(RUNS)/nbody-accuracy
	$(PY) $(NBODY_DIR)/accuracy.py $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-accuracy

nbody-bench: ## ssdem-grav throughput: us per particle-step per core (1, 2 threads), phases, bytes/sphere
	cmake --build $(BUILD) --target bench_nbody -j $(JOBS)
	mkdir -p $(RUNS)/nbody-bench
	$(BUILD)/tests/nbody/bench_nbody --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/nbody-bench/bench.json --benchmark_out_format=json
	$(PY) $(NBODY_DIR)/bench_table.py $(RUNS)/nbody-bench/bench.json $(RUNS)/nbody-bench

nbody-collapse: ## 1e5 spheres collapsing to one region: checked energy, half-mass radius, exit code (table, PNG)
	cmake --build $(BUILD) --target ssdem-grav -j $(JOBS)
	mkdir -p $(RUNS)/nbody-collapse
	$(PY) $(NBODY_DIR)/collapse.py $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-collapse $(COLLAPSE_N) $(COLLAPSE_T)

nbody-collapse-smoke: ## nbody-collapse at N = 2000 for 0.3 free-fall times (seconds)
	cmake --build $(BUILD) --target ssdem-grav -j $(JOBS)
	mkdir -p $(RUNS)/nbody-collapse-smoke
	$(PY) $(NBODY_DIR)/collapse.py $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-collapse-smoke 2000 0.3

# nbody-debris-bench: the neighbour list on debris (us per sphere-step, phase split): the demo's
# hand-off debris (600 s of N-body, the demo's reaccumulate settings), a synthetic cloud of 1e4
# piled + 1e4 flying spheres (1-100 m/s, nbody-debris-cloud) and the static rubble pile. With
# DEBRIS_OLD=<another ssdem-grav> old and new run interleaved (old, new, ...; DEBRIS_ROUNDS rounds);
# nbody-debris-skin: the contact.skin sweep (DEBRIS_SKINS, x max radius) with this build.
# The N-body benches' and the bonds study's fixed input: the impact at the demo's former settings
# (1 km MPM cells, 10 s of MPM; the demo itself now runs the paper's method at 2 km cells).
DEMO1K := $(RUNS)/demo-c1000
DEMO1K_SETTINGS = RUN=$(DEMO1K) CELL=1000 'MPM_SETS=--set body[1].ppc=2' MPM_TIME=10
DEBRIS_OLD    ?=
DEBRIS_ROUNDS ?= 3
DEBRIS_SKINS  ?= 0.05,0.1,0.25,0.5,1
DEBRIS_ENV = ROOT=$(ROOT) DEMO_SPHERES=$(DEMO1K)/spheres.h5 CLOUD=$(RUNS)/nbody-debris/cloud.h5 \
  DEMO_TIME=600 CLOUD_TIME=$(CLOUD_TIME) PILE_TIME=$(PILE_TIME)
CLOUD_TIME ?= 0.02
PILE_TIME  ?= 200
.PHONY: nbody-debris-bench nbody-debris-skin nbody-debris-scenes

nbody-debris-scenes:
	cmake --build $(BUILD) --target ssdem-grav nbody-debris-cloud -j $(JOBS)
	test -f $(DEMO1K)/spheres.h5 || $(MAKE) -f $(ROOT)/pipelines/Makefile $(DEMO1K)/spheres.h5 \
	  $(DEMO1K_SETTINGS) COARSEN=3 HANDOFF_MAX_SPEED=0
	mkdir -p $(RUNS)/nbody-debris
	test -f $(RUNS)/nbody-debris/cloud.h5 || $(BUILD)/tests/nbody/nbody-debris-cloud $(RUNS)/nbody-debris/cloud.h5

nbody-debris-bench: nbody-debris-scenes ## neighbour list on debris: us/sphere-step and phases (old vs new with DEBRIS_OLD=)
	$(DEBRIS_ENV) $(PY) $(NBODY_DIR)/debris_bench.py $(if $(DEBRIS_OLD),compare $(DEBRIS_OLD),sweep) \
	  $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-debris $(if $(DEBRIS_OLD),--rounds $(DEBRIS_ROUNDS),--skins 0.1)

nbody-debris-skin: nbody-debris-scenes ## contact.skin sweep on the debris scenes and the static pile
	$(DEBRIS_ENV) $(PY) $(NBODY_DIR)/debris_bench.py sweep $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-debris \
	  --skins $(DEBRIS_SKINS)

# nbody-gravity-bench: issue 15's dense HCP pile (1e4 spheres x 300 steps, 5e4 x 100), gravity every
# step (old and new interleaved with GRAVITY_OLD=<another ssdem-grav>) and with the error-controlled
# cadence; 1 and 2 threads, medians, phase split. nbody-gravity-sweep: force error and cost of one
# tree evaluation across theta, bucket and group size on the 1e4 pile (how the defaults were chosen).
GRAVITY_OLD ?=
GRAVITY_ROUNDS ?= 3
GRAVITY_SIZES ?= 10000:300,50000:100
.PHONY: nbody-gravity-bench nbody-gravity-sweep
nbody-gravity-bench: ## dense-pile gravity benchmark: us/sphere-step, phases, energy error (old vs new with GRAVITY_OLD=)
	cmake --build $(BUILD) --target ssdem-grav nbody-dense-pile -j $(JOBS)
	mkdir -p $(RUNS)/nbody-gravity
	ROOT=$(ROOT) $(PY) $(NBODY_DIR)/gravity_bench.py $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-gravity \
	  --rounds $(GRAVITY_ROUNDS) --sizes $(GRAVITY_SIZES) $(if $(GRAVITY_OLD),--old $(GRAVITY_OLD))

# nbody-large-bench: issue 15's large benchmarks, old and new interleaved (LARGE_OLD=<another
# ssdem-grav>), 1 and 2 threads, medians of LARGE_ROUNDS, phase split: the dense HCP pile of
# LARGE_N spheres for LARGE_STEPS steps (gravity every step and the controlled cadence), and
# "impact debris, large": a pile of LARGE_N with LARGE_N fragments flying out at 1-100 m/s
# (nbody-debris-cloud) under the reaccumulation scene for LARGE_T simulated seconds.
LARGE_N      ?= 50000
LARGE_STEPS  ?= 100
LARGE_T      ?= 0.002
LARGE_ROUNDS ?= 3
LARGE_OLD    ?=
.PHONY: nbody-large-bench
nbody-large-bench: ## 5e4 dense pile and 1e5-sphere debris (pile + flying): us/sphere-step, phases (old vs new with LARGE_OLD=)
	cmake --build $(BUILD) --target ssdem-grav nbody-dense-pile nbody-debris-cloud -j $(JOBS)
	mkdir -p $(RUNS)/nbody-large
	test -f $(RUNS)/nbody-large/cloud_$(LARGE_N).h5 || $(BUILD)/tests/nbody/nbody-debris-cloud \
	  $(RUNS)/nbody-large/cloud_$(LARGE_N).h5 $(LARGE_N) $(LARGE_N)
	ROOT=$(ROOT) $(PY) $(NBODY_DIR)/gravity_bench.py $(BUILD)/nbody/ssdem-grav $(RUNS)/nbody-large \
	  --rounds $(LARGE_ROUNDS) --sizes $(LARGE_N):$(LARGE_STEPS) \
	  --debris $(RUNS)/nbody-large/cloud_$(LARGE_N).h5:$(LARGE_T) $(if $(LARGE_OLD),--old $(LARGE_OLD))

nbody-gravity-sweep: ## tree force error and cost vs theta, bucket, group (dense pile of 1e4)
	cmake --build $(BUILD) --target nbody-dense-pile nbody-gravity-sweep -j $(JOBS)
	mkdir -p $(RUNS)/nbody-gravity
	$(BUILD)/tests/nbody/nbody-dense-pile $(RUNS)/nbody-gravity/pile_10000.h5 10000
	OMP_NUM_THREADS=1 $(BUILD)/tests/nbody/nbody-gravity-sweep $(RUNS)/nbody-gravity/pile_10000.h5 \
	  0.25,0.3,0.35,0.4,0.5 8,16 32,64,128 | tee $(RUNS)/nbody-gravity/sweep.md

# nbody-bonds-study (issue 18): bonds from the hand-off and cohesion on/off on the demo impact's
# MPM output (BONDS_RUN, default $(DEMO1K): the impact at the former demo settings, 1 km cells, 10 s;
# `make nbody-debris-scenes` first) and, with nbody-bonds-study-dart,
# on the DART-like family (BONDS_DART_RUN, `make dart-demo` first): M_LR/M_PB, beta, escaping mass
# against time, bonds broken against time, released bond energy, cost per sphere-step (bonds off
# and on interleaved). Writes runs/nbody-bonds-study/<family>/bonds_study.{md,json,png}.
BONDS_RUN ?= $(DEMO1K)
BONDS_DART_RUN ?= $(RUNS)/dart-demo
# BONDS_OLD: a previous ssdem-grav, whose bonds-off cost and peak memory are measured interleaved
# with the new binary's ("no bonds, no cost").
BONDS_OLD ?=
BONDS_VARIANTS ?= base,bonds-Dc0.125-hi,bonds-Dc1-lo,bonds-Dc1-hi,coh,bonds-Dc1-hi+coh
# BONDS_METHOD: paper (default: reaccumulate.toml as the pipeline runs it, multi-rate, fragments
# > 1 km/s dropped at the hand-off) or single-rate (the study's former settings: single rate,
# gravity every 10 steps, 4 steps per contact). BONDS_COARSEN: hand-off coarsening (3 for the 1 km
# run; 1 for the 2 km demo, `BONDS_RUN=$(RUNS)/demo BONDS_COARSEN=1`). The DART family keeps its
# scene's single-rate settings (dart/reaccumulate.toml has no multi-rate yet).
BONDS_METHOD ?= paper
BONDS_OUT ?= $(RUNS)/nbody-bonds-study/paper$(if $(filter single-rate,$(BONDS_METHOD)),-single-rate)
BONDS_COARSEN ?= 3
# BONDS_ARGS: more bonds_study.py options, e.g. "--end 600 --cost-rounds 3 --cost-time 300"
BONDS_ARGS ?=
.PHONY: nbody-bonds-study nbody-bonds-study-dart
nbody-bonds-study: tools ## bonds and cohesion on/off on the demo impact with the paper's method (multi-rate): M_LR/M_PB, beta, ejecta and broken bonds vs time, cost
	@test -f $(BONDS_RUN)/fragment/final.h5 || { echo "no $(BONDS_RUN)/fragment/final.h5: run make -C pipelines nbody-debris-scenes first"; exit 1; }
	$(PY) $(NBODY_DIR)/bonds_study.py paper $(BONDS_RUN) $(BONDS_OUT) $(BUILD) --variants $(BONDS_VARIANTS) \
	  --method $(BONDS_METHOD) --coarsen $(BONDS_COARSEN) $(BONDS_ARGS) $(if $(BONDS_OLD),--old-exe $(BONDS_OLD))
nbody-bonds-study-dart: tools ## the same on the DART-like family (dart-demo's MPM output; ~15 min)
	@test -f $(BONDS_DART_RUN)/fragment/final.h5 || { echo "no $(BONDS_DART_RUN)/fragment/final.h5: run make -C pipelines dart-demo first"; exit 1; }
	$(PY) $(NBODY_DIR)/bonds_study.py dart $(BONDS_DART_RUN) $(RUNS)/nbody-bonds-study/dart $(BUILD) --variants $(BONDS_VARIANTS) \
	  --method single-rate $(if $(BONDS_OLD),--old-exe $(BONDS_OLD))

# nbody-bonds-momentum (issue 18): where the beta of a bonded remnant comes from (bonds_momentum.py,
# seconds; after nbody-bonds-study-dart): the bonded components of the study's bonds-Dc1-hi variant
# and their momenta at hand-off and later, the MPM momentum partition of BONDS_DART_RUN (the top cap
# that breaks away against the rest), and the dt rule's bond modes against a bonded lattice's highest
# mode. Writes runs/nbody-bonds-study/dart/momentum.md.
.PHONY: nbody-bonds-momentum
nbody-bonds-momentum: ## beta of a bonded remnant: bonded components, MPM momentum partition, lattice stability of the bond dt rule (seconds)
	@test -d $(RUNS)/nbody-bonds-study/dart/bonds-Dc1-hi || { echo "run make -C pipelines nbody-bonds-study-dart first"; exit 1; }
	{ $(PY) $(NBODY_DIR)/bonds_momentum.py components $(RUNS)/nbody-bonds-study/dart/bonds-Dc1-hi && echo && \
	  $(PY) $(NBODY_DIR)/bonds_momentum.py partition $(BONDS_DART_RUN) $(RUNS)/nbody-bonds-study/dart/bonds-Dc1-hi && echo && \
	  $(PY) $(NBODY_DIR)/bonds_momentum.py lattice; } > $(RUNS)/nbody-bonds-study/dart/momentum.md
	cat $(RUNS)/nbody-bonds-study/dart/momentum.md

# nbody-paper-bench: issue 15's "impact debris, the paper's method": the demo impact's last MPM
# snapshot handed off with one sphere per cell (COARSEN=1, 8 225 spheres of 1 km), every contact
# resolved by >= 20 steps, PAPER_TIME simulated seconds on 2 threads; new = multi-rate
# (time.multirate = true, error-controlled gravity cadence up to PAPER_MAX_EVERY steps), old =
# PAPER_OLD (e.g. main's ssdem-grav: single rate, gravity every 10), interleaved. Reports wall time,
# phases, us per sphere-step, the level histogram over time and a linear 4.5 h extrapolation.
PAPER_OLD       ?=
PAPER_TIME      ?= 60
PAPER_ROUNDS    ?= 1
PAPER_MAX_EVERY ?= 4096
PAPER_SPHERES    = $(RUNS)/nbody-paper/spheres_c1.h5
.PHONY: nbody-paper-bench
nbody-paper-bench: ## paper-method debris (8 225 spheres, 20 steps/contact): wall, phases, levels (old vs new with PAPER_OLD=)
	cmake --build $(BUILD) --target ssdem-grav mpm2spheres -j $(JOBS)
	test -f $(DEMO1K)/fragment/done || $(MAKE) -f $(ROOT)/pipelines/Makefile $(DEMO1K)/fragment/done $(DEMO1K_SETTINGS)
	mkdir -p $(RUNS)/nbody-paper
	test -f $(PAPER_SPHERES) || $(BIN_HANDOFF) -i $(DEMO1K)/fragment/final.h5 -o $(PAPER_SPHERES) \
	  --method paper --coarsen 1 $$(test -f $(DEMO1K)/fragment/frag_outflow.h5 && echo --outflow $(DEMO1K)/fragment/frag_outflow.h5)
	ROOT=$(ROOT) $(PY) $(NBODY_DIR)/paper_bench.py $(or $(PAPER_OLD),-) $(BIN_NBODY) $(PAPER_SPHERES) \
	  $(RUNS)/nbody-paper --time $(PAPER_TIME) --rounds $(PAPER_ROUNDS) --max-every $(PAPER_MAX_EVERY)

# nbody-multirate-bench: multi-rate stepping's stiff and extreme cases (all in one pile: overhead
# vs single rate, MR_OLD=<old ssdem-grav> too; 10^4 isolated spheres: gravity only; 10^5 spheres:
# phase split and the serial level bookkeeping's share).
MR_OLD    ?=
MR_ROUNDS ?= 2
MR_CASES  ?= pile,isolated,large
.PHONY: nbody-multirate-bench
nbody-multirate-bench: ## multi-rate: one-pile overhead, 1e4 isolated spheres, 1e5 phase split (MR_OLD= to compare)
	cmake --build $(BUILD) --target ssdem-grav nbody-dense-pile -j $(JOBS)
	mkdir -p $(RUNS)/nbody-multirate
	ROOT=$(ROOT) $(PY) $(NBODY_DIR)/multirate_bench.py $(BUILD) $(RUNS)/nbody-multirate --rounds $(MR_ROUNDS) \
	  --cases $(MR_CASES) $(if $(MR_OLD),--old $(MR_OLD))

# nbody-late-bench: the reaccumulated remnant, where a paper-method run spends most of its wall
# time: LATE_TIME simulated seconds from the last N-body snapshot of LATE_RUN (or from LATE_SNAP,
# another snapshot file, e.g. the young debris; default the demo;
# `make -C pipelines demo` first), the pipeline's scene, LATE_THREADS threads; with LATE_OLD=<another
# ssdem-grav> old and new interleaved over LATE_ROUNDS rounds (medians); LATE_SETS="k=v;k=v" adds
# --set overrides to the new binary's runs (e.g. 'gravity.max_every=1024', or
# 'gravity.inner_steps="impulse"' for the impulse scheme), LATE_OLD_SETS likewise to the old one's.
LATE_RUN     ?= $(RUNS)/demo
LATE_OLD     ?=
LATE_TIME    ?= 300
LATE_ROUNDS  ?= 3
LATE_THREADS ?= 1
LATE_SETS    ?=
LATE_OLD_SETS ?=
LATE_SNAP    ?=
.PHONY: nbody-late-bench
nbody-late-bench: ## reaccumulated remnant (demo's last snapshot): us per sphere evaluation, phases (LATE_OLD= to compare)
	cmake --build $(BUILD) --target ssdem-grav -j $(JOBS)
	test -d $(LATE_RUN)/nbody || { echo "no $(LATE_RUN)/nbody: run make -C pipelines demo first" >&2; exit 2; }
	mkdir -p $(RUNS)/nbody-late
	ROOT=$(ROOT) $(PY) $(NBODY_DIR)/late_pile_bench.py $(or $(LATE_OLD),-) $(BIN_NBODY) \
	  $(or $(LATE_SNAP),$$(ls $(LATE_RUN)/nbody/snap_*.h5 | tail -n 1)) $(RUNS)/nbody-late --time $(LATE_TIME) \
	  --rounds $(LATE_ROUNDS) --threads $(LATE_THREADS) --sets '$(LATE_SETS)' --old-sets '$(LATE_OLD_SETS)'

# nbody-teams-bench: ssdem-grav under each run.teams rule (size, one-thread, every-pass, auto =
# measured while the run goes; nbody/include/ssdem/team_tuner.hpp) and auto on one thread, TEAMS_ROUNDS
# rounds interleaved, TEAMS_THREADS threads, medians; TEAMS_OLD=<another ssdem-grav> adds it. TEAMS_CASES
# is a list of NAME=SNAPSHOT:SECONDS (default: the demo's hand-off for 3 000 s and its remnant, the
# last snapshot, for 3 000 s: `make -C pipelines demo` first). README "Thread teams chosen by measurement"
# used the 1 km remnant and the disrupted 1 500 m debris of the convergence study too.
TEAMS_CASES   ?= demo-debris=$(RUNS)/demo/spheres.h5:3000 demo-remnant=$$(ls $(RUNS)/demo/nbody/snap_*.h5 | tail -n 1):3000
TEAMS_ROUNDS  ?= 3
TEAMS_THREADS ?= 2
TEAMS_OLD     ?=
.PHONY: nbody-teams-bench
nbody-teams-bench: ## each run.teams rule and the measured choice on debris and remnants (TEAMS_OLD= to compare)
	cmake --build $(BUILD) --target ssdem-grav -j $(JOBS)
	mkdir -p $(RUNS)/nbody-teams
	ROOT=$(ROOT) $(PY) $(NBODY_DIR)/teams_bench.py $(BIN_NBODY) $(RUNS)/nbody-teams $(TEAMS_CASES) \
	  --rounds $(TEAMS_ROUNDS) --threads $(TEAMS_THREADS) $(if $(TEAMS_OLD),--old $(TEAMS_OLD))

# nbody-chaos-floor: multi-rate against single-rate stepping on one hand-off (CHAOS_RUN, default
# the demo: `make -C pipelines demo` first), each also with one position perturbed by 1e-12: M_LR/M_PB
# and beta at 1 h and at CHAOS_END, the multi-rate difference against the chaos floor.
# CHAOS_CASES=core: only those four runs (no impulse variants), e.g. for the 1 km paper-method hand-off.
CHAOS_RUN ?= $(RUNS)/demo
CHAOS_END ?= 16200
CHAOS_CASES ?= all
CHAOS_OUT ?= $(RUNS)/nbody-chaos
.PHONY: nbody-chaos-floor
nbody-chaos-floor: ## multi-rate vs single rate within the chaos floor (1e-12 perturbation) on the demo's hand-off
	cmake --build $(BUILD) --target ssdem-grav ssdem-analyse -j $(JOBS)
	test -f $(CHAOS_RUN)/spheres.h5 || { echo "no $(CHAOS_RUN)/spheres.h5: run make -C pipelines demo first" >&2; exit 2; }
	mkdir -p $(CHAOS_OUT)
	ROOT=$(ROOT) $(PY) $(NBODY_DIR)/chaos_floor.py $(BIN_NBODY) $(BIN_ANALYSE) $(CHAOS_RUN) $(CHAOS_OUT) \
	  --end $(CHAOS_END) --threads $(JOBS) --target-radius $(R_T) --cases $(CHAOS_CASES)
