# Resolution study of the whole chain with flaw-seed scatter (issue 17, item 5, as far as 2 cores go).
# Included by rules.mk.
#
#   make -C pipelines impact-convergence                               every reading, cell and seed below
#   make -C pipelines impact-convergence IMPACT_CONV_IMPACTORS=2420 IMPACT_CONV_CELLS=500   one run
#
# For each impactor diameter in IMPACT_CONV_IMPACTORS (the paper's stated 1.21 km, and 2.42 km, the
# diameter its Q = 1.13e8 erg/g needs) and each MPM cell in IMPACT_CONV_CELLS, one run of the impact
# (seed 2019) in $(IMPACT_CONV_DIR)/d<D>/cells/c<cell>; at IMPACT_CONV_SEED_CELL the same run again for
# each of IMPACT_CONV_SEEDS in d<D>/seeds-c<cell>/s<seed>. Every run is the paper's method (the
# pipeline's defaults): 30 s of MPM, one sphere per MPM cell (COARSEN = 1), fragments faster than
# 1 km/s dropped at the hand-off, 4.5 h of reaccumulation with every contacting pair resolved by
# >= 20 steps (multi-rate, reaccumulate.toml); the impactor's particle spacing is <= 500 m
# (body[1].ppc). The N-body cost grows as ~h^-4 (README, measured on 2 cores: 82 s at 2000 m, 194 s
# at 1500 m, 547 s at 1000 m, 53 min at 750 m; ~4-5 h at 500 m and ~15 h at 375 m by that scaling),
# so on a small machine give e.g. IMPACT_CONV_CELLS="2000 1500 1000 750".
# Each run stops after the analysis (no report); every stage is rerun only when its inputs change.
# Then for each reading convergence.py writes d<D>/convergence.{md,csv,png} over the cell runs that
# exist (Richardson from the three finest, the seed scatter from every d<D>/ensemble-c<cell>) and
# ensemble.py d<D>/ensemble-c<cell>/ensemble.{md,csv} over the seed-2019 run at IMPACT_CONV_SEED_CELL
# and the seed runs. Seeds at a second cell: IMPACT_CONV_SEED_CELL=500 IMPACT_CONV_CELLS=500.
IMPACT_CONV_IMPACTORS ?= 1210 2420
IMPACT_CONV_CELLS     ?= 1000 750 500 375
IMPACT_CONV_SEED_CELL ?= 1000
IMPACT_CONV_SEEDS     ?= 1 2
IMPACT_CONV_DIR       ?= $(RUNS)/impact-convergence
# N-body snapshots at 3 s, 30 s and 2 h after the hand-off too (damage profiles, cf. paper Fig. 6)
CONV_TIMES = 'NBODY_TIMES=[3.0, 30.0, 600.0, 1800.0, 3600.0, 7200.0, 10800.0, 16200.0]'
# one run: $(call conv_run,impactor diameter,cell,run directory,seed)
conv_ppc = $$(awk "BEGIN{p = int($(1)/500 + 0.999); print (p < 2 ? 2 : p)}")
conv_run = $(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact-analyse IMPACTOR_DIAMETER=$(1) CELL=$(2) RUN=$(3) SEED=$(4) \
  MPM_SETS="--set body[1].ppc=$(call conv_ppc,$(2))" $(CONV_TIMES)

.PHONY: impact-convergence
impact-convergence: tools ## both impactor readings at 1000/750/500/375 m cells + seeds at 1000 m: table, Richardson, seed scatter
	for d in $(IMPACT_CONV_IMPACTORS); do \
	  for c in $(IMPACT_CONV_CELLS); do \
	    $(call conv_run,$$d,$$c,$(IMPACT_CONV_DIR)/d$$d/cells/c$$c,2019) || exit $$?; \
	  done; \
	  if [ -n "$(strip $(IMPACT_CONV_SEEDS))" ]; then \
	    $(call conv_run,$$d,$(IMPACT_CONV_SEED_CELL),$(IMPACT_CONV_DIR)/d$$d/cells/c$(IMPACT_CONV_SEED_CELL),2019) || exit $$?; \
	    for s in $(IMPACT_CONV_SEEDS); do \
	      $(call conv_run,$$d,$(IMPACT_CONV_SEED_CELL),$(IMPACT_CONV_DIR)/d$$d/seeds-c$(IMPACT_CONV_SEED_CELL)/s$$s,$$s) || exit $$?; \
	    done; \
	    $(PY) $(IMPACT_DIR)/ensemble.py $(IMPACT_CONV_DIR)/d$$d/cells/c$(IMPACT_CONV_SEED_CELL) \
	      $$(for s in $(IMPACT_CONV_SEEDS); do echo $(IMPACT_CONV_DIR)/d$$d/seeds-c$(IMPACT_CONV_SEED_CELL)/s$$s; done) \
	      --out $(IMPACT_CONV_DIR)/d$$d/ensemble-c$(IMPACT_CONV_SEED_CELL) > /dev/null || exit $$?; \
	  fi; \
	  $(PY) $(IMPACT_DIR)/convergence.py $$(ls -d $(IMPACT_CONV_DIR)/d$$d/cells/c*/) \
	    $$(for e in $(IMPACT_CONV_DIR)/d$$d/ensemble-c*/ensemble.csv; do test -f $$e && echo --ensemble $$(dirname $$e); done) \
	    --out $(IMPACT_CONV_DIR)/d$$d || exit $$?; \
	done
