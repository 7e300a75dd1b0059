# ssdem-grav on MPI (issue 19). Targets:
#   nbody-mpi-scaling : a ~1e5-sphere two-body reaccumulation, 1 rank x 2 OpenMP threads against
#                       2 ranks x 1 thread (interleaved, medians of MPI_SCALING_REPS), wall time,
#                       cost per sphere-step per core and communication volume per step
#                       (runs/nbody-mpi-scaling/scaling.{md,csv})
# Included by pipelines/Makefile (ROOT, PY, JOBS, MPI_BUILD, build-mpi).
MPI_SCALING_STEPS ?= 200
MPI_SCALING_REPS ?= 3
MPIRUN ?= mpirun --allow-run-as-root --oversubscribe

.PHONY: nbody-mpi-scaling
nbody-mpi-scaling: build-mpi ## ssdem-grav 1 rank x 2 threads vs 2 ranks x 1 thread on 1e5 spheres (comm volume)
	mkdir -p $(RUNS)/nbody-mpi-scaling
	$(PY) $(ROOT)/pipelines/mpi/mpi_scaling.py $(MPI_BUILD)/nbody/ssdem-grav $(RUNS)/nbody-mpi-scaling \
	  $(MPI_SCALING_STEPS) $(MPI_SCALING_REPS) $(MPIRUN)
