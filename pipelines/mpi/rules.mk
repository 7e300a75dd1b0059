# ssdem-grav on MPI (issue 19). Targets:
#   nbody-mpi-scaling : a ~1e5-sphere two-body reaccumulation, 1 rank x 2 OpenMP threads against
#                       2 ranks x 1 thread (interleaved, medians of MPI_SCALING_REPS), wall time,
#                       cost per sphere-step per core and communication volume per step
#                       (runs/nbody-mpi-scaling/scaling.{md,csv})
#   nbody-mpi-paper-scaling : the paper-method debris (nbody-paper-bench's 1 km hand-off, 8 225
#                       spheres) under the pipeline's multi-rate reaccumulation scene for
#                       MPI_PAPER_TIME s, 1 x 2 against 2 x 1 (interleaved, MPI_SCALING_REPS rounds),
#                       phases, communication, equalisation rounds and an h5diff of the two final
#                       checkpoints (runs/nbody-mpi-paper-scaling/scaling.md)
#   mpm-mpi-scaling     : mpm-frag 1 -> 2 ranks against 1 -> 2 threads: a Tillotson impact and the
#                       Tonge-Ramesh impact along z and along the cut axis (MPM_SCALING_CASES), medians of
#                       MPI_SCALING_REPS rounds, OLD = MPM_SCALING_OLD (runs/mpm-mpi-scaling/scaling.md)
#   mpm-mpi-files-bench : mpm-frag's collective files: memory and wall against MPM_FILES_OLD
#   mpm-mpi-outflow-bench : mpm-frag's outflow record written together: memory and wall against MPM_OUTFLOW_OLD
#   nbody-rows-bench    : ms per series row of ssdem-grav, serial and on 2 ranks
#   nbody-mpi-files-bench: ssdem-grav's collective files on 2 ranks: memory and wall vs another binary
#   nbody-mpi-gravity-bench: ssdem-grav's gravity (locally essential trees) on 2-3 ranks vs another binary
#   nbody-mpi-extrapolate : the model of nbody_extrapolate.py from those measured figures to the
#                       paper's 10^6 spheres on 64, 512 and 4 096 ranks (stated model, seconds)
#   mpm-mpi-extrapolate : the model of mpm_extrapolate.py: mpm-frag's ORB boxes for 10^7 particles
#                       on 64, 512 and 4 096 ranks, Tillotson (MUSL) and Tonge-Ramesh (midpoint)
# Included by pipelines/Makefile (ROOT, PY, JOBS, MPI_BUILD, build-mpi).
MPI_SCALING_STEPS ?= 200
MPI_SCALING_REPS ?= 3
# --bind-to none: mpirun binds each rank to one core by default (np <= 2), which would put the
# OpenMP threads of a 1-rank x 2-thread run on one core (measured: 25.0 s instead of 14.7 s)
MPIRUN ?= mpirun --allow-run-as-root --oversubscribe --bind-to none
MPI_PAPER_TIME ?= 60

.PHONY: nbody-mpi-scaling
nbody-mpi-scaling: build-mpi ## ssdem-grav 1 rank x 2 threads vs 2 ranks x 1 thread on 1e5 spheres (comm volume)
	mkdir -p $(RUNS)/nbody-mpi-scaling
	$(PY) $(ROOT)/pipelines/mpi/mpi_scaling.py $(MPI_BUILD)/nbody/ssdem-grav $(RUNS)/nbody-mpi-scaling \
	  $(MPI_SCALING_STEPS) $(MPI_SCALING_REPS) $(MPIRUN)

.PHONY: nbody-mpi-paper-scaling
nbody-mpi-paper-scaling: build-mpi ## multi-rate on MPI: paper-method debris, 1 x 2 vs 2 x 1 (phases, comm, identical result)
	cmake --build $(BUILD) --target mpm2spheres -j $(JOBS)
	test -f $(DEMO1K)/fragment/done || $(MAKE) -f $(ROOT)/pipelines/Makefile $(DEMO1K)/fragment/done $(DEMO1K_SETTINGS)
	mkdir -p $(RUNS)/nbody-paper $(RUNS)/nbody-mpi-paper-scaling
	test -f $(PAPER_SPHERES) || $(BIN_HANDOFF) -i $(DEMO1K)/fragment/final.h5 -o $(PAPER_SPHERES) \
	  --method paper --coarsen 1 $$(test -f $(DEMO1K)/fragment/frag_outflow.h5 && echo --outflow $(DEMO1K)/fragment/frag_outflow.h5)
	$(PY) $(ROOT)/pipelines/mpi/mpi_paper_scaling.py $(MPI_BUILD)/nbody/ssdem-grav $(PAPER_SPHERES) \
	  $(RUNS)/nbody-mpi-paper-scaling $(MPI_PAPER_TIME) $(MPI_SCALING_REPS) $(MPIRUN)

# mpm-frag's strong scaling (issue 19): ~6 min per round with all three cases on this 2-core VM.
MPM_SCALING_CASES ?= all
MPM_SCALING_OLD ?= -
.PHONY: mpm-mpi-scaling
mpm-mpi-scaling: build-mpi ## mpm-frag 1 -> 2 ranks vs 1 -> 2 threads: Tillotson and Tonge-Ramesh impacts (cuts by work)
	cmake --build $(BUILD) --target mpm-frag -j $(JOBS)
	mkdir -p $(RUNS)/mpm-mpi-scaling
	$(PY) $(ROOT)/pipelines/mpi/mpm_scaling.py $(BUILD)/mpm/mpm-frag $(MPI_BUILD)/mpm/mpm-frag $(RUNS)/mpm-mpi-scaling \
	  $(MPI_SCALING_REPS) $(MPM_SCALING_CASES) $(MPM_SCALING_OLD) $(MPIRUN)

.PHONY: nbody-mpi-extrapolate
nbody-mpi-extrapolate: ## model: the paper's 1e6-sphere N-body on 64-4096 ranks from the measured 2-rank figures
	$(PY) $(ROOT)/pipelines/mpi/nbody_extrapolate.py

.PHONY: mpm-mpi-extrapolate
mpm-mpi-extrapolate: ## model: mpm-frag's ORB boxes for 1e7 particles on 64-4096 ranks from the measured figures
	$(PY) $(ROOT)/pipelines/mpi/mpm_extrapolate.py
	$(PY) $(ROOT)/pipelines/mpi/mpm_extrapolate.py --c 12.6e-6 --scheme midpoint

# mpm-frag's files on MPI ranks (issue 19 item 4): peak memory per rank and wall of a 203 050-
# particle run writing snapshots and checkpoints (2 ranks) and of its restart (2 and 3 ranks),
# this build against MPM_FILES_OLD (an MPI mpm-frag of another commit, e.g. built in a `git
# worktree`), interleaved MPI_SCALING_REPS times; runs/mpm-mpi-files/files.md.
.PHONY: mpm-mpi-files-bench
mpm-mpi-files-bench: build-mpi ## mpm-frag on 2-3 ranks: memory and wall of snapshots, checkpoints, restart vs MPM_FILES_OLD
	@test -n "$(MPM_FILES_OLD)" || { echo "set MPM_FILES_OLD=<an MPI mpm-frag of another commit>"; exit 2; }
	$(ROOT)/pipelines/mpi/mpm_files_bench.sh $(MPI_BUILD)/mpm/mpm-frag $(MPM_FILES_OLD) $(RUNS)/mpm-mpi-files \
	  $(MPI_SCALING_REPS) $(MPIRUN)

# mpm-frag's outflow record on MPI ranks (issue 19): peak memory per rank and wall of a run in
# which 187 500 particles leave the grid, this build against MPM_OUTFLOW_OLD (an MPI mpm-frag that
# gathered the record to rank 0), interleaved MPI_SCALING_REPS times; runs/mpm-mpi-outflow/outflow.md.
.PHONY: mpm-mpi-outflow-bench
mpm-mpi-outflow-bench: build-mpi ## mpm-frag on 2 ranks: memory and wall of the outflow record written together vs MPM_OUTFLOW_OLD
	@test -n "$(MPM_OUTFLOW_OLD)" || { echo "set MPM_OUTFLOW_OLD=<an MPI mpm-frag of another commit>"; exit 2; }
	$(ROOT)/pipelines/mpi/mpm_outflow_bench.sh $(MPI_BUILD)/mpm/mpm-frag $(MPM_OUTFLOW_OLD) $(RUNS)/mpm-mpi-outflow \
	  $(MPI_SCALING_REPS) $(MPIRUN)

# ssdem-grav's files on MPI ranks (issue 19 item 4): peak memory per rank and wall of a
# 151 837-sphere pile and of the 1 km impact debris writing snapshots, rows and a checkpoint on 2
# ranks, this build against
# NBODY_FILES_OLD (an MPI ssdem-grav of another commit), interleaved MPI_SCALING_REPS times;
# runs/nbody-mpi-files/files.md.
.PHONY: nbody-mpi-files-bench
nbody-mpi-files-bench: build-mpi ## ssdem-grav on 2 ranks: memory and wall of collective snapshots/checkpoints vs NBODY_FILES_OLD
	@test -n "$(NBODY_FILES_OLD)" || { echo "set NBODY_FILES_OLD=<an MPI ssdem-grav of another commit>"; exit 2; }
	test -f $(PAPER_SPHERES) || { echo "no $(PAPER_SPHERES): run make -C pipelines nbody-rows-bench first" >&2; exit 2; }
	$(ROOT)/pipelines/mpi/nbody_files_bench.sh $(MPI_BUILD)/nbody/ssdem-grav $(NBODY_FILES_OLD) $(RUNS)/nbody-mpi-files \
	  $(MPI_SCALING_REPS) $(PAPER_SPHERES) $(MPIRUN)

# ssdem-grav's input on MPI ranks (issue 19: each rank reads only its rows): peak memory of the
# largest rank and wall of a restart from a 151 837-sphere checkpoint, of a fresh start from its
# sphere file and of a restart from the impact chain's run NBODY_INPUT_DEBRIS (if it exists; its
# nbody/checkpoint.h5 with the contact history), on 2, 3 and 6 ranks, this build against
# NBODY_INPUT_OLD (an MPI ssdem-grav of another commit), interleaved MPI_SCALING_REPS times;
# runs/nbody-mpi-input/input.md.
NBODY_INPUT_DEBRIS ?= $(RUNS)/paper-convergence/d1210/cells/c750
.PHONY: nbody-mpi-input-bench
nbody-mpi-input-bench: build-mpi ## ssdem-grav restarts and file start on 2, 3, 6 ranks: memory and wall vs NBODY_INPUT_OLD
	@test -n "$(NBODY_INPUT_OLD)" || { echo "set NBODY_INPUT_OLD=<an MPI ssdem-grav of another commit>"; exit 2; }
	$(ROOT)/pipelines/mpi/nbody_input_bench.sh $(MPI_BUILD)/nbody/ssdem-grav $(NBODY_INPUT_OLD) $(RUNS)/nbody-mpi-input \
	  $(MPI_SCALING_REPS) $(NBODY_INPUT_DEBRIS) $(MPIRUN)

# ssdem-grav's gravity on MPI ranks (issue 19): this build against NBODY_GRAVITY_OLD (an MPI
# ssdem-grav of another commit) with gravity every step on a 151 837-sphere pile (2 and 3 ranks)
# and two bodies of 89 012 spheres (2 ranks): wall, peak memory of the largest rank, gravity
# traffic per step, the tree's figures, and an h5diff of the two final checkpoints;
# runs/nbody-mpi-gravity/gravity.md.
.PHONY: nbody-mpi-gravity-bench
nbody-mpi-gravity-bench: build-mpi ## ssdem-grav's gravity on 2-3 ranks: memory, traffic, wall vs NBODY_GRAVITY_OLD
	@test -n "$(NBODY_GRAVITY_OLD)" || { echo "set NBODY_GRAVITY_OLD=<an MPI ssdem-grav of another commit>"; exit 2; }
	$(ROOT)/pipelines/mpi/nbody_gravity_bench.sh $(MPI_BUILD)/nbody/ssdem-grav $(NBODY_GRAVITY_OLD) \
	  $(RUNS)/nbody-mpi-gravity $(MPI_SCALING_REPS) $(MPIRUN)

# Bonds on MPI ranks (issue 19): a bonded two-body collision, the serial binary of this build
# against NBODY_BONDS_OLD (a serial ssdem-grav of another commit) and this MPI build on 1 x 2 and
# 2 x 1; walls, the bonds' traffic and the final checkpoints' identity; runs/nbody-mpi-bonds/bonds.md.
.PHONY: nbody-mpi-bonds-bench
nbody-mpi-bonds-bench: build-mpi ## bonds on 2 ranks vs 1 rank x 2 threads, serial path vs NBODY_BONDS_OLD
	@test -n "$(NBODY_BONDS_OLD)" || { echo "set NBODY_BONDS_OLD=<a serial ssdem-grav of another commit>"; exit 2; }
	cmake --build $(BUILD) --target ssdem-grav -j $(JOBS)
	$(ROOT)/pipelines/mpi/nbody_bonds_bench.sh $(MPI_BUILD)/nbody/ssdem-grav $(BUILD)/nbody/ssdem-grav \
	  $(NBODY_BONDS_OLD) $(RUNS)/nbody-mpi-bonds $(MPI_SCALING_REPS) $(MPIRUN)

# Cost of ssdem-grav's series rows, serial and on 2 ranks (issues 15, 19), this build against
# NBODY_ROWS_OLD / NBODY_ROWS_OLD_MPI (default: this build itself); runs/nbody-rows/rows.md.
.PHONY: nbody-rows-bench
nbody-rows-bench: build-mpi ## ms per series row of ssdem-grav, serial 1x2 and MPI 2x1, on the 1 km paper debris
	cmake --build $(BUILD) --target ssdem-grav mpm2spheres -j $(JOBS)
	test -f $(DEMO1K)/fragment/done || $(MAKE) -f $(ROOT)/pipelines/Makefile $(DEMO1K)/fragment/done $(DEMO1K_SETTINGS)
	mkdir -p $(RUNS)/nbody-paper $(RUNS)/nbody-rows
	test -f $(PAPER_SPHERES) || $(BIN_HANDOFF) -i $(DEMO1K)/fragment/final.h5 -o $(PAPER_SPHERES) \
	  --method paper --coarsen 1 $$(test -f $(DEMO1K)/fragment/frag_outflow.h5 && echo --outflow $(DEMO1K)/fragment/frag_outflow.h5)
	$(ROOT)/pipelines/mpi/nbody_rows_bench.sh $(PAPER_SPHERES) $(RUNS)/nbody-rows $(MPI_SCALING_REPS) \
	  $(BUILD)/nbody/ssdem-grav $(or $(NBODY_ROWS_OLD),$(BUILD)/nbody/ssdem-grav) \
	  $(MPI_BUILD)/nbody/ssdem-grav $(or $(NBODY_ROWS_OLD_MPI),$(MPI_BUILD)/nbody/ssdem-grav) $(MPIRUN)
