#!/usr/bin/env python3
"""Extrapolation of the MPI ssdem-grav (multi-rate, the pipeline's reaccumulation scene) from the
measured 2-rank run on the 1 km paper-method debris to the paper's 10^6 spheres on 64, 512 and 4096
ranks (issue 19). A stated model, not a measurement; every input is a command-line option whose
default is the measured value (nbody/README.md, "Multi-rate on MPI, the paper-method debris").

Model, per base step, for P ranks of n = N / P own spheres each (one core per rank):
  compute   c n (1 + f_g)/(1 + f_g0)      c: contacts, neighbour list, levels and kicks per own sphere
                                          and base step, measured with ghost fraction f_g0; pairs
                                          across a boundary are computed on both sides, so the
                                          ghost fraction f_g = g/n adds in proportion
  ghosts    g = k_g n^(2/3)               k_g from the measured run: 487 ghosts behind one cut of a
                                          body of 8 225 spheres (area ~ 8225^(2/3) sphere diameters^2
                                          -> 1.2 per unit area); an ORB box has up to 6 cut faces
  gravity   (E / S) (t_loc n + w n + t_let + t_top)
                                          locally essential trees (mpi/gravity_let.hpp, since
                                          2026-12-04): per evaluation each rank counts, builds and
                                          moments its own groups (t_loc per own sphere) and walks
                                          them (w); it imports the cells and particles its groups
                                          open, L = k_let n^(2/3) per cut face (k_let B measured
                                          behind one cut, 6 faces for an interior ORB box), sent at
                                          bandwidth B and unpacked at c_let per byte; the top tree's
                                          level counts (~1 B per sphere of the run, an allreduce:
                                          2 x that / B) and the maximal cells (m = 1 + k_m
                                          (n/40)^(2/3) per rank, 144 B each, allgathered: P m 144 B / B),
                                          plus (levels + 5) collectives a (1 + log2 P);
                                          E evaluations in S base steps. Before: every rank built
                                          the tree of all N (146 ns per sphere) from allgathered
                                          positions (32 B per sphere of the run), which stalled the
                                          wall at ~3.5 h beyond 64 ranks (--replicated)
  messages  3 a + g m_h / B + 3 a (1 + log2 P) + P a_g / B
                                          three point-to-point halos (opened ghosts' state, levels,
                                          synchronised ghosts' velocities: m_h = 33 B per ghost and
                                          base step measured, 15 985 B for 486 ghosts; 145 B before
                                          the halos of the ghosts that changed) and three collectives
                                          (movers' allgather, which also carries the failure check
                                          inside gravity blocks since 2026-12-04, the mover check's
                                          and the levels-changed allreduces; --collectives 4 before),
                                          plus the movers' allgather's data beyond the movers
                                          themselves (not counted: a handful per step on the
                                          debris): P a_g, a_g the bytes every rank adds to it.
                                          a_g = 0 since 2026-12-06 (a rank sends its failure-check
                                          part only when it fails); before, every rank sent two
                                          48 B records every base step (--ag 96), which the model
                                          had left out (it counted that allgather's latency only)
  rows      r N / R                       the O(N) work a series row every R base steps leaves on
                                          rank 0; r = 0 since 2026-12-04 (exact sums over the
                                          ranks, no gather: 0.6 ms per row on 2 ranks for 8 217
                                          spheres, ~1.7 base steps, and O(N/P)). Binaries before
                                          gathered every sphere to rank 0: r = 0.7 us per sphere
                                          (5.8 ms per row; 18.3 ms when rank 0 also evaluated the
                                          potential); R = output.series_every (the pipeline's 200)
The paper's run: N = 8 225 x 5^3 (200 m cells instead of 1 km), S and E 5x the measured 1 km run's
(base step proportional to the cell: the kinetic k_n rule), 4.5 h.
Usage: nbody_extrapolate.py [--c NS] [--b NS] [--w NS] ... (see --help); prints a Markdown table.
"""
import argparse
import math

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--c", type=float, default=23.5, help="ns per own sphere per base step, no gravity (2 x 1 run)")
ap.add_argument("--fg0", type=float, default=487 / 4112, help="ghost fraction of the measured run")
ap.add_argument("--kg", type=float, default=6 * 1.2, help="ghosts per n^(2/3) (6 faces x 1.2)")
ap.add_argument("--b", type=float, default=146.0, help="ns per sphere for the replicated tree build (--replicated)")
ap.add_argument("--replicated", action="store_true", help="the former gravity: replicated positions and tree")
ap.add_argument("--tloc", type=float, default=85.0,
                help="ns per own sphere: top-tree counts, build and moments of the own groups (measured, 2 ranks)")
ap.add_argument("--klet", type=float, default=890.0, help="LET bytes per n^(2/3) per cut face (measured behind one cut)")
ap.add_argument("--faces", type=float, default=6.0, help="cut faces of a rank's domain (interior ORB box)")
ap.add_argument("--clet", type=float, default=1.3, help="ns per LET byte to export and import (measured)")
ap.add_argument("--km", type=float, default=0.4, help="maximal cells per rank: 1 + km (n/40)^(2/3)")
ap.add_argument("--levels", type=float, default=10.0, help="levels of the top tree (one allreduce each)")
ap.add_argument("--w", type=float, default=1900.0, help="ns per own sphere for the tree walk (theta 0.25)")
ap.add_argument("--evals-per-step", type=float, default=12875 / 3242057, help="gravity evaluations per base step")
ap.add_argument("--alpha", type=float, default=3.0, help="us per message (network latency; assumed)")
ap.add_argument("--bw", type=float, default=5.0, help="GB/s per rank (network bandwidth; assumed)")
ap.add_argument("--collectives", type=float, default=3.0, help="collectives per base step")
ap.add_argument("--mh", type=float, default=33.0, help="halo bytes per ghost and base step (measured)")
ap.add_argument("--ag", type=float, default=0.0,
                help="bytes every rank adds to the movers' allgather per base step (96 before 2026-12-06)")
ap.add_argument("--row", type=float, default=0.0,
                help="us per sphere per series row on rank 0 (0 since the exact-sum rows; 0.7 before)")
ap.add_argument("--series-every", type=float, default=200.0, help="base steps per series row (output.series_every)")
ap.add_argument("--N", type=float, default=8225 * 125, help="spheres (the paper's 200 m hand-off)")
ap.add_argument("--steps", type=float, default=5 * 3242057, help="base steps of the 4.5 h run")
args = ap.parse_args()

rows = ["| ranks P | own n | ghosts g (g/n) | compute µs | gravity µs (build / walk / "
        + ("gather" if args.replicated else "LET, top and latency") + ") | "
        "communication µs | series rows µs | per base step µs | communication share | 4.5 h wall | core-hours |",
        "|---|---|---|---|---|---|---|---|---|---|---|"]
for P in (64, 512, 4096):
    n = args.N / P
    g = args.kg * n ** (2 / 3)
    comp = args.c * 1e-3 * n * (1 + g / n) / (1 + args.fg0)
    e = args.evals_per_step
    lat = args.alpha * (1 + math.log2(P))
    if args.replicated:
        build = e * args.b * 1e-3 * args.N
        gather = e * args.N * 32 / (args.bw * 1e3)
    else:
        let_b = args.klet * n ** (2 / 3) * args.faces
        m = 1 + args.km * (n / 40) ** (2 / 3)
        build = e * (args.tloc * 1e-3 * n + let_b * args.clet * 1e-3)
        gather = e * ((let_b + 2 * 1.0 * args.N + P * m * 144) / (args.bw * 1e3) + (args.levels + 5) * lat)
    walk = e * args.w * 1e-3 * n
    grav = build + walk + gather
    comm = (3 * args.alpha + g * args.mh / (args.bw * 1e3) + args.collectives * args.alpha * (1 + math.log2(P))
            + P * args.ag / (args.bw * 1e3))
    rows_us = args.row * args.N / args.series_every
    tot = comp + grav + comm + rows_us
    wall_h = tot * 1e-6 * args.steps / 3600
    rows.append(f"| {P} | {n:.0f} | {g:.0f} ({g / n:.2f}) | {comp:.1f} | {grav:.1f} ({build:.1f} / {walk:.1f} / "
                f"{gather:.1f}) | {comm:.1f} | {rows_us:.1f} | {tot:.1f} | {(comm + gather) / tot:.0%} | {wall_h:.2f} h | "
                f"{wall_h * P:.0f} |")
print(f"N = {args.N:.3g} spheres, {args.steps:.3g} base steps, {args.evals_per_step * args.steps:.3g} gravity "
      f"evaluations, a series row every {args.series_every:.0f} base steps; latency {args.alpha} µs, bandwidth {args.bw} GB/s per rank (assumed)\n")
print("\n".join(rows))
