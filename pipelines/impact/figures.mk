# The paper's figures for one run (issue 17, item 6): ParaView cut-away renders of damage in the
# MPM stage (El Mir et al. 2019, Fig. 4) and of the spheres in the N-body stage (Fig. 5), the damage
# profile against radius (Fig. 6), M_LR/M_PB and beta against time with the paper's values.
# Included by rules.mk.
#
#   make -C pipelines impact-figures RUN=runs/demo        (any run directory of the impact pipeline)
#
# Needs Debian's paraview, python3-paraview and xvfb (installed here when missing; pvbatch renders
# off screen under xvfb-run). The nearest snapshots to the wanted times are used and
# $(RUN)/figures/figures.md names the times shown. Times: FIG_MPM_TIMES after impact,
# FIG_NBODY_TIMES and FIG_PROFILE_TIMES after hand-off (the paper's profiles: 3 s, 30 s, 2 h).
FIG_MPM_TIMES     ?= 0 1 3 10 30
FIG_NBODY_TIMES   ?= 0 30 1800 16200
FIG_PROFILE_TIMES ?= 3 30 7200
PVBATCH           ?= xvfb-run -a pvbatch

.PHONY: impact-figures
impact-figures: ## ParaView cut-aways (paper Figs. 4, 5), damage profile (Fig. 6), M_LR/M_PB and beta vs time, for RUN
	@$(ROOT)/pipelines/install-deps.sh paraview python3-paraview xvfb xauth
	$(PY) $(IMPACT_DIR)/figures.py $(RUN) --out $(RUN)/figures --pvbatch "$(PVBATCH)" \
	  --mpm-times $(FIG_MPM_TIMES) --nbody-times $(FIG_NBODY_TIMES) --profile-times $(FIG_PROFILE_TIMES)
	@echo "figures: $(RUN)/figures/figures.md"
