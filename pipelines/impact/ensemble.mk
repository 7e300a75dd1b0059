# Flaw-seed ensembles (issue 17, item 4): the same impact with several Tonge-Ramesh flaw seeds.
# Included by rules.mk; every variable of the impact target applies (CELL, IMPACTOR_DIAMETER,
# IMPACT_SPEED, COARSEN, NBODY_TIME, MPM_SETS, NBODY_SETS, ...).
#
#   make -C pipelines impact-ensemble SEEDS="1 2 3" CELL=500
#   make -C pipelines demo-ensemble SEEDS="1 2 3"        the demo's settings
#
# Each seed is an ordinary impact run in $(ENSEMBLE)/seed<s> (stages up to the analysis; its
# report: `make -C pipelines impact RUN=$(ENSEMBLE)/seed<s> SEED=<s> ...`), so a changed N-body
# setting reruns only the N-body stage and after for every seed, and a new seed runs only itself.
# ensemble.py then writes $(ENSEMBLE)/ensemble.{csv,md} (mean, std, sem, min, max of M_LR/M_PB,
# beta, the hand-off loss, the bound fraction and the MPM energy change) and ensemble_runs.csv
# (one row per seed); it fails when a run is incomplete or the runs differ in more than the seed.
SEEDS    ?= 1 2 3
ENSEMBLE ?= $(RUNS)/impact-ensemble-c$(CELL)-v$(IMPACT_SPEED)-d$(IMPACTOR_DIAMETER)

.PHONY: impact-ensemble demo-ensemble
impact-ensemble: tools ## the impact once per flaw seed (SEEDS="1 2 3"), mean and spread of M_LR/M_PB, beta, hand-off loss
	@test -n "$(strip $(SEEDS))" || { echo "impact-ensemble: SEEDS is empty (give e.g. SEEDS=\"1 2 3\")" >&2; exit 2; }
	for s in $(SEEDS); do \
	  $(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact-analyse RUN=$(ENSEMBLE)/seed$$s SEED=$$s || exit $$?; \
	done
	$(PY) $(IMPACT_DIR)/ensemble.py $(foreach s,$(SEEDS),$(ENSEMBLE)/seed$(s)) --out $(ENSEMBLE)
	@echo "ensemble: $(ENSEMBLE)/ensemble.md"

demo-ensemble: tools ## the demo impact once per flaw seed (SEEDS="1 2 3"; minutes per seed on 2 cores, as the demo)
	$(MAKE) -f $(firstword $(MAKEFILE_LIST)) impact-ensemble ENSEMBLE=$(RUNS)/demo-ensemble $(DEMO_SETTINGS)
