# Hand-off studies (mpm2spheres).
HANDOFF_SNAPSHOT ?= $(RUNS)/demo/fragment/final.h5

.PHONY: handoff-compare handoff-bench

handoff-compare: $(BIN_HANDOFF) ## paper vs conserving method, coarsen 1-3, on one snapshot (default: the demo's last MPM snapshot)
	@test -f $(HANDOFF_SNAPSHOT) || { echo "no snapshot $(HANDOFF_SNAPSHOT): run 'make -C pipelines demo' or set HANDOFF_SNAPSHOT=..."; exit 2; }
	$(PY) $(ROOT)/pipelines/handoff/compare.py $(BIN_HANDOFF) $(HANDOFF_SNAPSHOT) $(RUNS)/handoff-compare

handoff-bench: build ## hand-off throughput on 1e6 particles, 1 and 2 threads, peak memory (table in runs/handoff-bench)
	mkdir -p $(RUNS)/handoff-bench
	$(BUILD)/tests/handoff/bench_handoff --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/handoff-bench/bench.json --benchmark_out_format=json | tee $(RUNS)/handoff-bench/bench.txt
