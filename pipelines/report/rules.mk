# Reaccumulation analysis and report (owner: analysis). Included by pipelines/Makefile.
# The impact pipeline (pipelines/impact/) calls the two tools through these variables:
#   $(BIN_ANALYSE) SNAP... -o RUN/analysis/analysis --mpm MPM_LAST.h5 --impactor-mass M --impactor-velocity '[vx,vy,vz]' --parent-mass M_PB
#   $(REPORT_PY) RUN [--out RUN/report]
REPORT_PY   ?= $(PY) $(ROOT)/pipelines/report/make_report.py

.PHONY: report-selftest analysis-bench

report-selftest: ## report generator on a synthetic run (report.md + PNGs in $(RUNS)/report-selftest)
	cmake --build $(BUILD) --target ssdem-analyse -j $(JOBS)
	$(PY) $(ROOT)/tests/analysis/test_report.py --report $(ROOT)/pipelines/report/make_report.py \
	  --analyse $(BIN_ANALYSE) --workdir $(RUNS)/report-selftest
	@echo "report: $(RUNS)/report-selftest/run/report/report.md"

analysis-bench: ## FOF + bound-mass benchmark, 1e5/1e6 spheres, 1-2 threads (table + PNG in $(RUNS)/analysis-bench)
	cmake --build $(BUILD) --target bench_analysis -j $(JOBS)
	mkdir -p $(RUNS)/analysis-bench
	$(BUILD)/tests/analysis/bench_analysis --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
	  --benchmark_out=$(RUNS)/analysis-bench/bench.json --benchmark_out_format=json
	$(PY) $(ROOT)/pipelines/report/bench_table.py $(RUNS)/analysis-bench/bench.json $(RUNS)/analysis-bench
