"""Reader of Google Benchmark JSON output (`--benchmark_out=F --benchmark_out_format=json`).

Shared by the pipelines' bench_table.py scripts (mpm, nbody, report):

    data = gbench.load(path)                     # the parsed JSON
    rows = gbench.aggregates(data, "median")     # entries of one aggregate, in file order
    gbench.family(b), gbench.args(b)             # "BM_Fof/100000/2/real_time" -> "BM_Fof", [100000, 2]
    gbench.args_label(b)                         # "100000/2" (the arguments as in the name)
    gbench.seconds(b)                            # real_time converted from time_unit to seconds
    gbench.counter(b, "spheres")                 # a user counter (NaN when the benchmark has none)
    gbench.us_per_item(b, n, threads)            # 1e6 * seconds * threads / n: per item (per core)

An entry is the benchmark's JSON object: run_name, aggregate_name (with --benchmark_repetitions),
real_time, cpu_time, time_unit, iterations and the user counters as top-level keys.
"""
import json

TIME_UNIT_S = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
# name parts that are settings of the run, not arguments: iterations:N, repeats:N, threads:N, min_time:T
_MODES = ("real_time", "process_time", "manual_time")


def load(path):
    """The benchmark output file as a dict ({"context": ..., "benchmarks": [...]})."""
    with open(path) as f:
        return json.load(f)


def aggregates(data, name="median", plain=False):
    """Entries whose aggregate_name is `name`, in file order. With plain=True, entries without an
    aggregate (a run without --benchmark_repetitions) are kept too."""
    out = []
    for b in data["benchmarks"]:
        agg = b.get("aggregate_name")
        if agg == name or (plain and agg is None):
            out.append(b)
    return out


def _parts(b):
    return b["run_name"].split("/")


def family(b):
    """The benchmark's registered name: "BM_RubblePile/50000/1/1/iterations:3/real_time" -> "BM_RubblePile"."""
    return _parts(b)[0]


def _arg_parts(b):
    return [p for p in _parts(b)[1:] if ":" not in p and p not in _MODES]


def args(b):
    """The benchmark's integer arguments (->Arg/->Args), in order."""
    return [int(p) for p in _arg_parts(b)]


def args_label(b):
    """The arguments as written in the name: "50000/1/1"."""
    return "/".join(_arg_parts(b))


def seconds(b, field="real_time"):
    """real_time (or cpu_time) of an entry, in seconds."""
    return b[field] * TIME_UNIT_S[b["time_unit"]]


def counter(b, key, default=float("nan")):
    """A user counter of the entry, `default` when the benchmark did not set it."""
    return b.get(key, default)


def us_per_item(b, items, threads=1, field="real_time"):
    """Microseconds per item (particle, sphere, ...) of one iteration; times `threads` gives the
    cost per core."""
    return 1e6 * seconds(b, field) * threads / items
