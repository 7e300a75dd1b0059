# Hand-off studies (mpm2spheres). Included by pipelines/Makefile, which declares ROOT, BUILD, RUNS, PY and JOBS.
# default: the impact at the former demo settings (1 km cells, 10 s of MPM: 8225 particles), the
# snapshot of the handoff README's tables (made by `make -C pipelines nbody-debris-scenes`)
HANDOFF_SNAPSHOT ?= $(RUNS)/demo-c1000/fragment/final.h5

.PHONY: handoff-compare handoff-bench

handoff-compare: $(BIN_HANDOFF) ## paper vs conserving method, coarsen 1-3, on one snapshot (default: the 1 km impact's last MPM snapshot)
	@test -f $(HANDOFF_SNAPSHOT) || { echo "no snapshot $(HANDOFF_SNAPSHOT): run 'make -C pipelines nbody-debris-scenes' or set HANDOFF_SNAPSHOT=..."; exit 2; }
	$(PY) $(ROOT)/pipelines/handoff/compare.py $(BIN_HANDOFF) $(HANDOFF_SNAPSHOT) $(RUNS)/handoff-compare

handoff-bench: build ## hand-off throughput on 1e6 particles, 1 and 2 threads, peak memory, snapshot I/O vs dd (table in runs/handoff-bench)
	cmake --build $(BUILD) --target bench_handoff -j $(JOBS)
	mkdir -p $(RUNS)/handoff-bench
	$(BUILD)/tests/handoff/bench_handoff --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/handoff-bench/bench.json --benchmark_out_format=json | tee $(RUNS)/handoff-bench/bench.txt
	@echo "# steady state: freed blocks reused by malloc, no first-touch page faults (compute cost alone)" | tee -a $(RUNS)/handoff-bench/bench.txt
	MALLOC_MMAP_THRESHOLD_=4000000000 MALLOC_TRIM_THRESHOLD_=4000000000 $(BUILD)/tests/handoff/bench_handoff \
	  --benchmark_filter=BM_HandOff --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/handoff-bench/bench_warm.json --benchmark_out_format=json | tee -a $(RUNS)/handoff-bench/bench.txt
	@echo "# the disk: 256 MB sequential write with fdatasync, then read back (page cache as for the benchmark)" | tee -a $(RUNS)/handoff-bench/bench.txt
	dd if=/dev/zero of=$(RUNS)/handoff-bench/dd.tmp bs=1M count=256 conv=fdatasync 2>&1 | tail -n 1 | tee -a $(RUNS)/handoff-bench/bench.txt
	dd if=$(RUNS)/handoff-bench/dd.tmp of=/dev/null bs=1M 2>&1 | tail -n 1 | tee -a $(RUNS)/handoff-bench/bench.txt
	rm -f $(RUNS)/handoff-bench/dd.tmp
