# The seed paper's impact, end to end (El Mir, Ramesh & Richardson 2019, Icarus 321:1013):
#   fragment (mpm-frag) -> handoff (mpm2spheres) -> reaccumulate (ssdem-grav) -> analyse
#   (ssdem-analyse) -> report (pipelines/report/make_report.py)
# Every stage is one tool run whose inputs and outputs are files in $(RUN); Make reruns only
# what depends on a changed or deleted file. Every physical input is a variable (paper values by
# default); `make -C pipelines impact CELL=500 IMPACT_SPEED=3000` changes them, and each stage's
# scene is echoed into its output files (/provenance/scene).
#
#   make -C pipelines demo          the same impact at demo resolution (minutes on 2 cores)
#   make -C pipelines impact-paper  the published resolution (200 m cells, ~1e6 particles: a cluster job)

IMPACT_DIR := $(ROOT)/pipelines/impact
# ---- scene family (the seed paper's by default; pipelines/impact/dart/ holds the DART-like one) ----
FRAGMENT_SCENE ?= $(IMPACT_DIR)/fragment.toml
NBODY_SCENE    ?= $(IMPACT_DIR)/reaccumulate.toml
# ---- physical inputs (El Mir et al. 2019) ----
TARGET_DIAMETER   ?= 25000
IMPACTOR_DIAMETER ?= 1210
IMPACT_SPEED      ?= 5000
DENSITY           ?= 2700
# ---- resolution and durations ----
CELL          ?= 200
MPM_TIME      ?= 30
SNAP_INTERVAL ?= 5
NBODY_TIME    ?= 16200
NBODY_TIMES   ?= [600.0, 1800.0, 3600.0, 7200.0, 10800.0, 16200.0]
COARSEN       ?= 1
HANDOFF_METHOD ?= paper
# Flaw seed of the Tonge-Ramesh model (mpm-frag run.seed; the scene's 2019 by default).
# impact-ensemble (ensemble.mk) runs the same impact with several.
SEED          ?= 2019
DAMAGE_INC    ?= 0.01
DOMAIN_FACTOR ?= 3.2
# Material that leaves the MPM grid (fast ejecta, rebounding impactor fragments): "remove" takes
# it out of the MPM step and hands it off from fragment/frag_outflow.h5; "stop" ends the run (exit 3).
OUTFLOW       ?= remove
# Fragments faster than HANDOFF_MAX_SPEED [m/s] at the hand-off are dropped (mpm2spheres
# select.max_speed; their mass and momentum are in the audit; 0 keeps every particle). 1 km/s is
# ~65 escape speeds of the 25 km target: they escape for certain and are not in beta or M_LR
# (bound material only; M_PB is taken from the MPM at t = 0). As lone impactor particles they are
# the lightest spheres, whose contacts would set the N-body base step (2 km cells: 3.3x the cost).
HANDOFF_MAX_SPEED ?= 1000
RUN           ?= $(RUNS)/impact-c$(CELL)-v$(IMPACT_SPEED)
MPM_SETS      ?=
NBODY_SETS    ?=

# Derived geometry: cells centred so that the target centre is a cell centre; the impactor
# touches the target's top at t = 0 and moves along -z.
impact_calc = $(shell awk 'BEGIN{printf "%.6f", $(1)}')
R_T   := $(call impact_calc,$(TARGET_DIAMETER)/2)
R_I   := $(call impact_calc,$(IMPACTOR_DIAMETER)/2)
Z_I   := $(call impact_calc,$(TARGET_DIAMETER)/2 + $(IMPACTOR_DIAMETER)/2)
HALF  := $(call impact_calc,(int($(DOMAIN_FACTOR)*$(TARGET_DIAMETER)/2/$(CELL)) + 0.5)*$(CELL))

define FRAGMENT_SETS
--set grid.cell_size=$(CELL) \
--set 'grid.domain_min=[-$(HALF),-$(HALF),-$(HALF)]' --set 'grid.domain_max=[$(HALF),$(HALF),$(HALF)]' \
--set time.end=$(MPM_TIME) --set output.snapshot_interval=$(SNAP_INTERVAL) --set grid.outflow=\"$(OUTFLOW)\" \
--set run.seed=$(SEED) \
--set output.directory=$(RUN)/fragment \
--set material[0].density=$(DENSITY) --set material[0].max_damage_inc=$(DAMAGE_INC) \
--set body[0].radius=$(R_T) --set 'body[1].center=[0,0,$(Z_I)]' --set body[1].radius=$(R_I) \
--set 'body[1].velocity=[0,0,-$(IMPACT_SPEED)]' $(MPM_SETS)
endef

TIMED = $(IMPACT_DIR)/timed.sh $(RUN)/timing
# The two long stages continue an interrupted run from its checkpoint (resume.sh): rerunning the
# same `make` after a kill, a full disk or the end of a session picks up where the stage stopped,
# if nothing the stage depends on changed since that run started. The tools publish a run's files
# only when it completes, so no stage directory is deleted first.
RESUME = $(IMPACT_DIR)/resume.sh
# RESUME_ACROSS_BUILDS=1: the tools are order-only prerequisites of the stages, so a rebuilt tool
# (a fix or an update in the middle of a long run) neither reruns a finished stage nor keeps an
# interrupted one from continuing its checkpoint; the scene, the settings and the input files
# still decide. The tool then logs, and ssdem-grav records in run_info.txt, that the checkpoint
# came from another build (another git SHA; builds of uncommitted changes on one commit are not
# told apart): the run continues from the same state with the new build's
# arithmetic, bit-identical to an uninterrupted run only where both builds compute the same.
# Default 0: a rebuilt tool reruns its stage and those after it from the start.
RESUME_ACROSS_BUILDS ?= 0
ifeq ($(filter 0 1,$(RESUME_ACROSS_BUILDS)),)
$(error RESUME_ACROSS_BUILDS=$(RESUME_ACROSS_BUILDS): valid values are 0 and 1)
endif
stage_tool = $(if $(filter 1,$(RESUME_ACROSS_BUILDS)),,$(1))
stage_tool_order = $(if $(filter 1,$(RESUME_ACROSS_BUILDS)),$(1))
# mpm-frag's checkpoint: <output.prefix>_checkpoint.h5 (both scene families use prefix "frag")
FRAGMENT_CHECKPOINT ?= frag_checkpoint.h5
# ---- cluster runs ----
# MPI_RANKS=N runs the fragment (mpm-frag) and reaccumulate (ssdem-grav) stages on N MPI ranks,
# launched by MPI_LAUNCH (mpirun by default; on Slurm MPI_LAUNCH="srun -n"), with the tools of
# BUILD, which must be an MPI build: `make -C pipelines build-mpi`, then BUILD=$(ROOT)/build-mpi
# (its tools are built there on demand). The hand-off and the analysis run as one process. A
# stage's result does not depend on MPI_RANKS beyond mpm-frag's round-off (ssdem-grav's is the
# same bits on any rank count), so changing it reruns nothing; timing/<stage>.json records it.
MPI_RANKS  ?= 0
MPI_LAUNCH ?= mpirun --bind-to none -np
ON_RANKS = $(if $(filter-out 0,$(MPI_RANKS)),$(MPI_LAUNCH) $(MPI_RANKS))
# a stage on ranks: timed.sh records them
TIMED_RANKS = STAGE_MPI_RANKS=$(MPI_RANKS) $(TIMED)
# checked only for the impact goals (other targets, build-mpi among them, run with any MPI_RANKS)
ifneq ($(filter-out 0,$(MPI_RANKS)),)
ifneq ($(filter impact impact-% demo,$(MAKECMDGOALS)),)
ifeq ($(shell grep -s 'SUITE_MPI:BOOL=ON' $(BUILD)/CMakeCache.txt),)
$(error MPI_RANKS=$(MPI_RANKS) needs an MPI build: run `make -C pipelines build-mpi` and pass BUILD=$(ROOT)/build-mpi (BUILD=$(BUILD) is not one))
endif
endif
endif
HANDOFF_SETS  ?=
ANALYSE_SETS  ?=

# Settings stamps: each stage depends on a small file holding its resolved command-line settings,
# rewritten only when they change, so `make ... NBODY_SETS=...` reruns the N-body stage and what
# follows it, and nothing before it.
FRAGMENT_VARS = $(FRAGMENT_SCENE) $(FRAGMENT_SETS)
HANDOFF_VARS  = --method $(HANDOFF_METHOD) --coarsen $(COARSEN) --set select.max_speed=$(HANDOFF_MAX_SPEED) $(HANDOFF_SETS)
NBODY_VARS    = $(NBODY_SCENE) time.end=$(NBODY_TIME) output.times=$(NBODY_TIMES) $(NBODY_SETS)
ANALYSE_VARS  = --set impact.target_radius=$(R_T) $(ANALYSE_SETS)
$(RUN)/.vars/%: FORCE | $(RUN)/.dir
	@mkdir -p $(@D)
	@printf '%s\n' '$(subst ','"'"',$($*_VARS))' | cmp -s - $@ || printf '%s\n' '$(subst ','"'"',$($*_VARS))' > $@
.PHONY: FORCE
FORCE:

# A stage whose listed outputs (its `done` file: one path per line) are not all present is rerun:
# deleting any intermediate snapshot rebuilds it and everything that depends on it.
stage_incomplete = $(if $(wildcard $(1)),$(if $(strip $(foreach f,$(shell cat $(1)),$(if $(wildcard $(f)),,x))),FORCE),)

.PHONY: impact impact-paper demo impact-fragment impact-handoff impact-reaccumulate impact-analyse impact-report impact-print

impact: $(RUN)/report.md ## the full chain with the current variables
	@echo "report: $(RUN)/report.md"

impact-paper: ## the published resolution: 200 m cells, 30 s MPM, 4.5 h N-body (cluster-sized, see README)
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact CELL=200 COARSEN=1

# Demo: the paper's method at a coarse MPM cell. DEMO_CELL = 2 km MPM cells (~1000 particles; the
# impactor, smaller than one cell, as 8 particles of 500 m: body[1].ppc = DEMO_CELL / 500), the
# paper's 30 s of MPM, one sphere per MPM cell (COARSEN = 1), 4.5 h of reaccumulation with every
# contacting pair resolved by >= 20 steps (reaccumulate.toml: multi-rate block steps). The cell is
# what keeps it a few minutes on 2 cores: the N-body cost grows as ~h^-3 to h^-4 (README). The
# paper: 200 m cells, 30 s, 100 m spheres (one per cell), 4.5 h.
DEMO_CELL ?= 2000
DEMO_SETTINGS = CELL=$(DEMO_CELL) MPM_SETS="--set body[1].ppc=$(shell awk 'BEGIN{print int($(DEMO_CELL)/500 + 0.999)}')"
demo: tools ## the paper's method end to end in minutes on 2 cores (2 km cells, one sphere per cell, 4.5 h N-body)
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact RUN=$(RUNS)/demo $(DEMO_SETTINGS)

$(RUN)/.dir:
	mkdir -p $(RUN)/timing && touch $@

# 1. fragment: MPM with the Tonge-Ramesh model; final.h5 links the last snapshot; done lists every
#    file (snapshots frag_<step>.h5 and, when material left the grid, frag_outflow.h5).
$(RUN)/fragment/done: $(FRAGMENT_SCENE) $(RUN)/.vars/FRAGMENT $(call stage_tool,$(BIN_MPM)) $(call stage_incomplete,$(RUN)/fragment/done) | $(RUN)/.dir $(call stage_tool_order,$(BIN_MPM))
	$(TIMED_RANKS) fragment $(RESUME) $(RUN)/fragment $(FRAGMENT_CHECKPOINT) $(filter-out FORCE,$^) -- \
	  $(ON_RANKS) $(BIN_MPM) --scene $(FRAGMENT_SCENE) $(FRAGMENT_SETS)
	cd $(RUN)/fragment && ln -sf $$(ls frag_[0-9]*.h5 | tail -n 1) final.h5
	ls $(RUN)/fragment/frag_*.h5 > $@.tmp && mv $@.tmp $@
impact-fragment: $(RUN)/fragment/done

# 2. hand-off: one sphere per (coarsened) cell, audit JSON beside it.
$(RUN)/spheres.h5: $(RUN)/fragment/done $(RUN)/.vars/HANDOFF $(call stage_tool,$(BIN_HANDOFF)) | $(call stage_tool_order,$(BIN_HANDOFF))
	$(TIMED) handoff $(BIN_HANDOFF) -i $(RUN)/fragment/final.h5 -o $@ $(HANDOFF_VARS) \
	  $$(test -f $(RUN)/fragment/frag_outflow.h5 && echo --outflow $(RUN)/fragment/frag_outflow.h5)
impact-handoff: $(RUN)/spheres.h5

# 3. reaccumulate: self-gravity + soft spheres for NBODY_TIME seconds; done lists the snapshots.
$(RUN)/nbody/done: $(RUN)/spheres.h5 $(NBODY_SCENE) $(RUN)/.vars/NBODY $(call stage_tool,$(BIN_NBODY)) $(call stage_incomplete,$(RUN)/nbody/done) | $(call stage_tool_order,$(BIN_NBODY))
	$(TIMED_RANKS) reaccumulate $(RESUME) $(RUN)/nbody checkpoint.h5 $(filter-out FORCE,$^) -- \
	  $(ON_RANKS) $(BIN_NBODY) --scene $(NBODY_SCENE) \
	  --set initial.file=$(RUN)/spheres.h5 --set time.end=$(NBODY_TIME) --set 'output.times=$(NBODY_TIMES)' \
	  --set output.directory=$(RUN)/nbody $(NBODY_SETS)
	ls $(RUN)/nbody/snap_*.h5 > $@.tmp && mv $@.tmp $@
impact-reaccumulate: $(RUN)/nbody/done

# 4. analyse: largest remnant, bound mass, beta, damage profiles over the N-body snapshots.
$(RUN)/analysis.json: $(RUN)/nbody/done $(RUN)/.vars/ANALYSE $(call stage_tool,$(BIN_ANALYSE)) | $(call stage_tool_order,$(BIN_ANALYSE))
	$(TIMED) analyse $(BIN_ANALYSE) $(RUN)/spheres.h5 $$(cat $(RUN)/nbody/done) \
	  --mpm $(RUN)/fragment/final.h5 --mpm-initial $$(head -n 1 $(RUN)/fragment/done) \
	  $(ANALYSE_VARS) -o $(RUN)/analysis
impact-analyse: $(RUN)/analysis.json

# 5. report: Markdown page with pictures, the paper's numbers beside ours.
$(RUN)/report.md: $(RUN)/analysis.json $(ROOT)/pipelines/report/make_report.py
	$(PY) $(ROOT)/pipelines/report/make_report.py $(RUN) --out $(RUN)
impact-report: $(RUN)/report.md

impact-print: ## print the stage commands without running them
	@$(MAKE) -n -f $(firstword $(MAKEFILE_LIST)) impact

# ---- second scene family: DART-like kinetic impact on a monolithic moonlet (dart/README.md) ----
# Dimorphos-sized basalt target (160 m), impactor at DART's 6.145 km/s. The impactor is a basalt
# sphere larger than DART (its mass is a variable; see the README for why and what it changes).
# Fragments faster than 1 km/s (10^4 escape speeds; impactor remnants) are dropped at the hand-off
# (mass and momentum in the audit): they escape for certain, and as light spheres they would set
# a contact time step 20x shorter. beta and M_LR/M_PB count bound material only, so they are unchanged.
DART_SETTINGS = FRAGMENT_SCENE=$(IMPACT_DIR)/dart/fragment.toml NBODY_SCENE=$(IMPACT_DIR)/dart/reaccumulate.toml \
  TARGET_DIAMETER=160 IMPACT_SPEED=6145 DOMAIN_FACTOR=2 'MPM_SETS=--set body[1].ppc=8' \
  HANDOFF_MAX_SPEED=1000
dart: tools ## DART-like impact on a 160 m moonlet, impactor resolved: 1 m cells, 2 m impactor, 0.2 s MPM (~2e6 particles, ~8 core-hours)
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact $(DART_SETTINGS) RUN=$(RUNS)/dart \
	  CELL=1 IMPACTOR_DIAMETER=2 MPM_TIME=0.2 SNAP_INTERVAL=0.04 COARSEN=4 NBODY_TIME=7200 \
	  'NBODY_TIMES=[600.0, 1800.0, 3600.0, 7200.0]' 'MPM_SETS=--set body[1].ppc=4'
dart-demo: tools ## DART-like impact at demo resolution: 5 m cells, 2 m impactor, 0.1 s MPM, 30 min N-body (minutes)
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact $(DART_SETTINGS) RUN=$(RUNS)/dart-demo \
	  CELL=5 IMPACTOR_DIAMETER=2 MPM_TIME=0.1 SNAP_INTERVAL=0.02 COARSEN=2 NBODY_TIME=1800 \
	  'NBODY_TIMES=[300.0, 900.0, 1800.0]' \
	  NBODY_SETS="--set time.steps_per_contact=4 --set time.min_steps_per_contact=4"

# ---- studies of the whole chain ----
# Resolution and flaw seeds, for both readings of the impactor: convergence.mk (impact-convergence).

# Extreme speeds through every stage (demo settings): 20 km/s and 100 m/s. Each stage must end with
# exit 0 and finite outputs (or a clean exit 3 with a diagnosis, which fails this target).
impact-extremes: tools ## 20 km/s and 100 m/s impacts through all stages, checked for exit codes and NaN
	for v in 20000 100; do \
	  $(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact IMPACT_SPEED=$$v RUN=$(RUNS)/impact-extremes/v$$v \
	    $(DEMO_SETTINGS) || exit $$?; \
	done
	$(PY) $(IMPACT_DIR)/check_runs.py $(RUNS)/impact-extremes/v20000 $(RUNS)/impact-extremes/v100 \
	  --out $(RUNS)/impact-extremes

# Flaw-seed ensembles (impact-ensemble), the resolution study (impact-convergence) and the
# ParaView figures (impact-figures).
include $(IMPACT_DIR)/ensemble.mk
include $(IMPACT_DIR)/convergence.mk
include $(IMPACT_DIR)/figures.mk
