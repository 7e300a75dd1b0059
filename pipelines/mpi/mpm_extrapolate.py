#!/usr/bin/env python3
"""Extrapolation of the MPI mpm-frag (ORB boxes by work, two-round sparse halo) from the measured
runs on this machine to 10^7 particles on 64, 512 and 4096 ranks (issue 19). A stated model, not
a measurement; every input is an option whose default is a measured value or a property of the
code (mpm/README.md, "MPI").

Model, per step, for P ranks (one core each) sharing a body of N particles at q particles per
occupied cell (V = N / q cells, a sphere), each rank owning a near-cubic ORB box of V / P body
cells, side L = (V / P)^(1/3) cells:
  compute   c N / P                       c: the wall per particle-step of one core (Tillotson,
                                          `basalt_impact.toml` at 0.0055: 29.1 s for 203 050
                                          particles x 205 steps = 0.70 us; Tonge-Ramesh,
                                          `fragment.toml` at 700 m: 40.9 s for 190 764 x 17 =
                                          12.6 us), times the work imbalance I before a check
                                          (measured mean 1.03-1.15 with the boxes)
  grid      g ((L + 2H)^3 - L^3)          the held ghost nodes' grid update (H = 2), g = 20 ns per
                                          node (assumed: a node update is a few loads and FMAs;
                                          a cell's q = 8 particles cost 8 c)
  halo      6 L^2 H b / B + m k a         the ghost shell of the box's 6 faces inside the body, b
                                          bytes per ghost node per step (two rounds: to the owner
                                          and back, 8 B of ordinal + the pass's fields each:
                                          midpoint 2 x 64 B, MUSL 2 x (64 + 32) = 192 B), at
                                          bandwidth B; m = 2 rounds x passes messages to each of
                                          k neighbours (26 for an interior box) of latency a
  reductions r a (1 + log2 P)             r collectives per step (dt's signal speed, the failure
                                          flags, the imbalance check's two integer sums, the
                                          diagnostics' allgather): 5
Check of the halo term against a measured run: `fragment.toml` at 700 m (radius 17.9 cells,
midpoint) on 4 ranks (2 x 2 boxes, two full cut planes through the body): 2 planes x 2 sides x
pi 17.9^2 x H nodes x 128 B = 1.03 MB per step, 17.5 MB over the 17 steps; measured 15.8 MB.
Box count limit: every side of a cut keeps W = 4 planes, so at most ~V / 64 boxes (more ranks
than the set-up's weights allow: an input error; a rebalancing that cannot cut keeps its boxes);
slabs (before 2026-12-07) allowed only ~2 V^(1/3) / 4.

  mpm_extrapolate.py [--particles 1e7] [--ppc 8] [--c 0.70e-6] [--imbalance 1.1] [--scheme musl]
                     [--ranks 64,512,4096] [--latency 3e-6] [--bandwidth 5e9] [--node-ns 20]
"""
import argparse
import math


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--particles", type=float, default=1e7)
    ap.add_argument("--ppc", type=float, default=8.0, help="particles per occupied cell")
    ap.add_argument("--c", type=float, default=0.70e-6, help="s per particle-step on one core (Tillotson 0.70e-6, TR 12.6e-6)")
    ap.add_argument("--imbalance", type=float, default=1.1)
    ap.add_argument("--scheme", choices=["musl", "midpoint"], default="musl")
    ap.add_argument("--ranks", default="64,512,4096")
    ap.add_argument("--latency", type=float, default=3e-6)
    ap.add_argument("--bandwidth", type=float, default=5e9)
    ap.add_argument("--node-ns", type=float, default=20.0)
    ap.add_argument("--neighbours", type=int, default=26)
    ap.add_argument("--reductions", type=int, default=5)
    a = ap.parse_args()
    H = 2
    passes = 2 if a.scheme == "musl" else 1
    b = 192.0 if a.scheme == "musl" else 128.0
    V = a.particles / a.ppc
    print(f"{a.particles:.3g} particles, {a.ppc:g} per cell: {V:.3g} body cells (a sphere of radius "
          f"{(3 * V / (4 * math.pi)) ** (1 / 3):.1f} cells); c = {a.c * 1e6:.2f} us per particle-step, "
          f"imbalance {a.imbalance}, {a.scheme} ({b:g} B per ghost node per step), {a.latency * 1e6:g} us latency, "
          f"{a.bandwidth / 1e9:g} GB/s")
    print("| ranks | box side L cells | compute ms | grid ms | halo MB per rank | halo ms | reductions ms "
          "| step ms | communication % | efficiency vs 1 rank | particle-steps per s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    t1 = a.c * a.particles
    for P in (int(x) for x in a.ranks.split(",")):
        L = (V / P) ** (1 / 3)
        if L < 4:
            print(f"| {P} | {L:.1f} | (fewer than 4 planes a box: refused) |||||||||")
            continue
        comp = a.c * a.particles / P * a.imbalance
        grid = a.node_ns * 1e-9 * ((L + 2 * H) ** 3 - L ** 3)
        nodes = 6 * L * L * H
        halo_b = nodes * b
        halo = halo_b / a.bandwidth + 2 * passes * a.neighbours * a.latency
        red = a.reductions * a.latency * (1 + math.log2(P))
        step = comp + grid + halo + red
        comm = (halo + red) / step
        print(f"| {P} | {L:.1f} | {comp * 1e3:.3g} | {grid * 1e3:.2g} | {halo_b / 1e6:.2g} | {halo * 1e3:.2g} | "
              f"{red * 1e3:.2g} | {step * 1e3:.3g} | {100 * comm:.1f} | {t1 / (P * step):.2f} | "
              f"{a.particles / step:.3g} |")


if __name__ == "__main__":
    main()
