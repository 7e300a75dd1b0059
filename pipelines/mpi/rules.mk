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
#   nbody-mpi-extrapolate : the model of nbody_extrapolate.py from those measured figures to the
#                       paper's 10^6 spheres on 64, 512 and 4 096 ranks (stated model, seconds)
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

.PHONY: nbody-mpi-extrapolate
nbody-mpi-extrapolate: ## model: the paper's 1e6-sphere N-body on 64-4096 ranks from the measured 2-rank figures
	$(PY) $(ROOT)/pipelines/mpi/nbody_extrapolate.py
