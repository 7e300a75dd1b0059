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
DAMAGE_INC    ?= 0.01
DOMAIN_FACTOR ?= 3.2
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
--set time.end=$(MPM_TIME) --set output.snapshot_interval=$(SNAP_INTERVAL) \
--set output.directory=$(RUN)/fragment \
--set material[0].density=$(DENSITY) --set material[0].max_damage_inc=$(DAMAGE_INC) \
--set body[0].radius=$(R_T) --set 'body[1].center=[0,0,$(Z_I)]' --set body[1].radius=$(R_I) \
--set 'body[1].velocity=[0,0,-$(IMPACT_SPEED)]' $(MPM_SETS)
endef

TIMED = $(IMPACT_DIR)/timed.sh $(RUN)/timing

.PHONY: impact impact-paper demo impact-fragment impact-handoff impact-reaccumulate impact-analyse impact-report impact-print

impact: $(RUN)/report.md ## the full chain with the current variables
	@echo "report: $(RUN)/report.md"

impact-paper: ## the published resolution: 200 m cells, 30 s MPM, 4.5 h N-body (cluster-sized, see README)
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact CELL=200 COARSEN=1

# Demo: 1 km MPM cells (8 particles across the impactor, ~8200 in all), 10 s of MPM (the
# impactor's rebounding fragments leave an 80 km grid at ~12 s), 3 km spheres, 1 h of
# reaccumulation with dt set so that the lightest pair (a lone impactor particle against a full
# sphere) gets 4 steps per contact and a full pair ~40. The paper: 200 m, 30 s, 100 m spheres, 4.5 h.
demo: tools ## small impact end to end in minutes on 2 cores (1 km cells, 3 km spheres, 1 h N-body)
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact CELL=1000 COARSEN=3 RUN=$(RUNS)/demo \
	  MPM_TIME=10 NBODY_TIME=3600 'NBODY_TIMES=[600.0, 1200.0, 1800.0, 2700.0, 3600.0]' \
	  MPM_SETS="--set body[1].ppc=2" \
	  NBODY_SETS="--set time.steps_per_contact=4 --set time.min_steps_per_contact=4"

$(RUN)/.dir:
	mkdir -p $(RUN)/timing && touch $@

# 1. fragment: MPM with the Tonge-Ramesh model; final.h5 links the last snapshot.
$(RUN)/fragment/final.h5: $(IMPACT_DIR)/fragment.toml $(BIN_MPM) | $(RUN)/.dir
	rm -rf $(RUN)/fragment
	$(TIMED) fragment $(BIN_MPM) --scene $< $(FRAGMENT_SETS)
	cd $(RUN)/fragment && ln -sf $$(ls frag_[0-9]*.h5 | tail -n 1) final.h5
impact-fragment: $(RUN)/fragment/final.h5

# 2. hand-off: one sphere per (coarsened) cell, audit JSON beside it.
$(RUN)/spheres.h5: $(RUN)/fragment/final.h5 $(BIN_HANDOFF)
	$(TIMED) handoff $(BIN_HANDOFF) -i $< -o $@ --method $(HANDOFF_METHOD) --coarsen $(COARSEN)
impact-handoff: $(RUN)/spheres.h5

# 3. reaccumulate: self-gravity + soft spheres for NBODY_TIME seconds.
$(RUN)/nbody/done: $(RUN)/spheres.h5 $(IMPACT_DIR)/reaccumulate.toml $(BIN_NBODY)
	rm -rf $(RUN)/nbody
	$(TIMED) reaccumulate $(BIN_NBODY) --scene $(IMPACT_DIR)/reaccumulate.toml \
	  --set initial.file=$< --set time.end=$(NBODY_TIME) --set 'output.times=$(NBODY_TIMES)' \
	  --set output.dir=$(RUN)/nbody $(NBODY_SETS)
	touch $@
impact-reaccumulate: $(RUN)/nbody/done

# 4. analyse: largest remnant, bound mass, beta, damage profiles over the N-body snapshots.
$(RUN)/analysis.json: $(RUN)/nbody/done $(BIN_ANALYSE)
	$(TIMED) analyse $(BIN_ANALYSE) $(RUN)/spheres.h5 $$(ls $(RUN)/nbody/snap_*.h5) \
	  --mpm $(RUN)/fragment/final.h5 --mpm-initial $(RUN)/fragment/frag_000000.h5 \
	  --set impact.target_radius=$(R_T) -o $(RUN)/analysis
impact-analyse: $(RUN)/analysis.json

# 5. report: Markdown page with pictures, the paper's numbers beside ours.
$(RUN)/report.md: $(RUN)/analysis.json $(ROOT)/pipelines/report/make_report.py
	$(PY) $(ROOT)/pipelines/report/make_report.py $(RUN) --out $(RUN)
impact-report: $(RUN)/report.md

impact-print: ## print the stage commands without running them
	@$(MAKE) -n -f $(firstword $(MAKEFILE_LIST)) impact
