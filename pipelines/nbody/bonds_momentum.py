"""Where the beta of a bonded remnant comes from (issue 18; target nbody-bonds-momentum).

A bonded body's beta is momentum bookkeeping: along the impact direction U (target frame)
    beta m|U| = P_bound.U = P_handoff.U - P_esc.U
where P_handoff is what the hand-off gave the N-body stage (m U less the momentum of what was
dropped at the hand-off or left the MPM grid). This script measures each term from the files:

  partition  the MPM snapshots of a run: momentum along U of a top cap of the target (particles
             whose initial z lies above the cut that holds the mass fraction of the spheres outside
             the largest bonded component at the end of VARIANT_DIR: the material that breaks away in
             the bonded run) against the rest and the impactor material, in units of m|U| (m U from
             the t = 0 snapshot: its particles faster than 1 km/s)
  components a bonds-study variant (hand-off spheres.h5 + nbody snapshots with /bonds): connected
             components of the intact bonds in each snapshot; momentum of the largest component and
             of the rest at the hand-off and in the snapshot; series.csv momentum and energy drift
  lattice    the dt rule's bond modes (single-bond half-periods, bonds.cpp bond_time) against the
             highest mode of an infinite simple-cubic lattice of bonded spheres (the hand-off's
             face bonds), by Bloch analysis of the linearised bond of bonds.hpp (axial k_n A, shear
             k_s A at the contact point, bending k_n I, twisting k_s J; k_s = k_n / 2.5, R_b = R as
             in the study), alone and with the contact springs of compressed neighbours (k_n A and
             2/7 of it tangentially); leapfrog is stable for omega dt < 2 (Hairer et al. 2003)

usage: bonds_momentum.py components VARIANT_DIR
       bonds_momentum.py partition RUN_DIR VARIANT_DIR
       bonds_momentum.py lattice
"""
import csv
import glob
import itertools
import os
import sys

import numpy as np


def impactor_momentum(ids, m, v):
    imp = v[:, 2] < -1000.0
    return -(m[imp] * v[imp, 2]).sum(), imp


def load_mpm(path):
    import h5py
    with h5py.File(path, "r") as f:
        g = f["particles"]
        return float(f.attrs["time"]), g["id"][:], g["mass"][:], g["position"][:], g["velocity"][:], g["damage"][:]


def partition(run, frac):
    files = sorted(glob.glob(os.path.join(run, "fragment", "frag_[0-9]*.h5")))
    _, id0, m0, x0, v0, _ = load_mpm(files[0])
    mU, imp = impactor_momentum(id0, m0, v0)
    zt, mt = x0[~imp, 2], m0[~imp]
    order = np.argsort(-zt)
    zcut = zt[order][np.searchsorted(np.cumsum(mt[order]) / mt.sum(), frac)]
    cap_ids, imp_ids = id0[~imp][zt > zcut], id0[imp]
    print(f"m|U| = {mU:.4e} kg m/s; top cap: initial z > {zcut:.1f} m ({frac:.3f} of the target mass)\n")
    print("| t [s] | P_cap.U / m|U| | P_rest.U / m|U| | P_impactor.U / m|U| | sum / m|U| | cap mean v_z [m/s] | target mass with D < 0.125 |")
    print("|---|---|---|---|---|---|---|")
    for p in files:
        t, i, m, _, v, D = load_mpm(p)
        cap, im = np.isin(i, cap_ids), np.isin(i, imp_ids)
        rest = ~cap & ~im
        pc, pr, pi = (-(m[s] * v[s, 2]).sum() / mU for s in (cap, rest, im))
        print(f"| {t:.3f} | {pc:.3f} | {pr:.3f} | {pi:.3f} | {pc + pr + pi:.3f} | "
              f"{(m[cap] * v[cap, 2]).sum() / m[cap].sum():.3f} | {m[~im][D[~im] < 0.125].sum() / m[~im].sum():.4f} |")
    out = os.path.join(run, "fragment", "frag_outflow.h5")
    if os.path.exists(out):
        _, i, m, _, v, _ = load_mpm(out)
        print(f"\nleft the grid (frag_outflow.h5, not in the snapshots above): {len(m)} particles, "
              f"{np.isin(i, imp_ids).sum()} of them impactor material, P.U / m|U| = {-(m * v[:, 2]).sum() / mU:.3f}")


def load_spheres(path):
    import h5py
    with h5py.File(path, "r") as f:
        s = f["spheres"]
        d = {k: s[k][:] for k in ("id", "mass", "velocity")}
        d["t"] = float(f.attrs.get("time", 0.0))
        if "bonds" in f:
            b = f["bonds"]
            d["bonds"] = (b["id_a"][:], b["id_b"][:], b["broken"][:] if "broken" in b else np.zeros(b["id_a"].shape[0]))
    return d


def components(vdir, quiet=False):
    """Prints the table (unless quiet); returns the largest component's mass fraction at the end."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    audit = os.path.join(vdir, "spheres.audit.json")
    import json
    mU = abs(json.load(open(audit))["input"]["momentum"][2])  # the MPM's momentum at hand-off: m U (head-on)
    h = load_spheres(os.path.join(vdir, "spheres.h5"))
    order = np.argsort(h["id"])
    ids, m, v0 = h["id"][order], h["mass"][order], h["velocity"][order]
    nb = os.path.join(vdir, "nbody")
    snaps = sorted(glob.glob(os.path.join(nb, "snap_*.h5")) or glob.glob(os.path.join(nb, ".staging-*", "snap_*.h5")))
    say = (lambda *a: None) if quiet else print
    say(f"m|U| = {mU:.4e} kg m/s (mpm2spheres audit: input momentum); hand-off total P.U / m|U| = "
        f"{-(m * v0[:, 2]).sum() / mU:.4f}\n")
    say("| t [s] | intact bonds | bonded components | largest: mass fraction | largest: P.U/m|U| at hand-off | "
          "largest: P.U/m|U| now | rest: P.U/m|U| at hand-off | rest: P.U/m|U| now |")
    say("|---|---|---|---|---|---|---|---|")
    frac = 1.0
    for p in snaps:
        s = load_spheres(p)
        o = np.argsort(s["id"])
        assert (s["id"][o] == ids).all(), p
        v1 = s["velocity"][o]
        a, b, broken = s["bonds"]
        keep = broken == 0
        ia, ib = np.searchsorted(ids, a[keep]), np.searchsorted(ids, b[keep])
        n = len(ids)
        nc, lab = connected_components(coo_matrix((np.ones(len(ia)), (ia, ib)), shape=(n, n)), directed=False)
        cm = np.bincount(lab, weights=m)
        L = lab == np.argmax(cm)
        pu = lambda sel, v: -(m[sel] * v[sel, 2]).sum() / mU  # noqa: E731
        frac = cm.max() / m.sum()
        say(f"| {s['t']:.0f} | {keep.sum()} | {nc} | {cm.max() / m.sum():.4f} | {pu(L, v0):.3f} | {pu(L, v1):.3f} | "
              f"{pu(~L, v0):.3f} | {pu(~L, v1):.3f} |")
    ser = sorted(glob.glob(os.path.join(nb, "series.csv")) or glob.glob(os.path.join(nb, ".staging-*", "series.csv*")))
    rows = list(csv.DictReader(open(ser[0])))
    p = np.array([[float(r[k]) for k in ("px_kgm_s", "py_kgm_s", "pz_kgm_s")] for r in rows])
    e = np.array([float(r["total_J"]) + float(r.get("bond_released_J", 0.0)) for r in rows])
    say(f"\nseries.csv ({len(rows)} rows to t = {float(rows[-1]['time_s']):.0f} s): max |P - P(0)| / m|U| = "
          f"{np.abs(p - p[0]).max() / mU:.2e}; total_J + bond_released_J: start {e[0]:.5e} J, max {e.max():.5e} J, "
          f"end {e[-1]:.5e} J (largest rise between rows {max(0.0, np.diff(e).max()):.3e} J)")
    return frac


def skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def lattice():
    R, kn = 1.0, 1.0
    ks, m = kn / 2.5, (2 * R) ** 3
    Is, A, Ib, J = 0.4 * m * R * R, np.pi * R * R, np.pi * R ** 4 / 4, np.pi * R ** 4 / 2
    mu, Ir = m / 2, Is / 2
    modes = {"axial": np.pi * np.sqrt(mu / (kn * A)), "bending": np.pi * np.sqrt(Ir / (kn * Ib)),
             "shear": np.pi * np.sqrt(mu / (ks * A)), "twist": np.pi * np.sqrt(Ir / (ks * J))}
    tau = min(modes.values())

    def bond_k(e, contact):
        E, Pn = skew(e), np.outer(e, e)
        Pt = np.eye(3) - Pn
        # contact-point slip delta = u_b - u_a + R e x (th_a + th_b); relative rotation th_b - th_a
        Bd = np.hstack([-np.eye(3), R * E, np.eye(3), R * E])
        Bt = np.hstack([np.zeros((3, 3)), -np.eye(3), np.zeros((3, 3)), np.eye(3)])
        kd = kn * A * Pn + ks * A * Pt + (kn * A * Pn + 2.0 / 7.0 * kn * A * Pt if contact else 0.0)
        return Bd.T @ kd @ Bd + Bt.T @ (kn * Ib * Pt + ks * J * Pn) @ Bt

    w = np.diag([m ** -0.5] * 3 + [Is ** -0.5] * 3)

    def omega_max(dirs, contact, nq=9):
        best = 0.0
        for q in itertools.product(np.linspace(-np.pi, np.pi, nq), repeat=3):
            D = np.zeros((6, 6), complex)
            for e in dirs:
                K, ph = bond_k(e, contact), np.exp(1j * np.dot(q, e))
                D += K[:6, :6] + K[6:, 6:] + K[:6, 6:] * ph + K[6:, :6] * np.conj(ph)
            best = max(best, np.linalg.eigvalsh(w @ D @ w).max())
        return np.sqrt(best)

    print("single-bond half-periods / the shortest: " + ", ".join(f"{k} {v / tau:.3f}" for k, v in modes.items()))
    print("\n| body | omega_max tau_bond / pi | steps per tau_bond needed (omega dt < 2) |\n|---|---|---|")
    for name, dirs, contact in [("one bond (two spheres)", [np.eye(3)[0]], False), ("simple-cubic lattice, bonds", list(np.eye(3)), False),
                                ("simple-cubic lattice, bonds + contacts in compression", list(np.eye(3)), True)]:
        if name.startswith("one"):
            K = bond_k(dirs[0], contact)
            W = np.kron(np.eye(2), w)
            om = np.sqrt(np.linalg.eigvalsh(W @ K @ W).max())
        else:
            om = omega_max(dirs, contact)
        print(f"| {name} | {om * tau / np.pi:.3f} | {om * tau / 2:.2f} |")


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in ("partition", "components", "lattice"):
        sys.exit(__doc__)
    if sys.argv[1] == "partition":
        partition(sys.argv[2], 1.0 - components(sys.argv[3], quiet=True))
    elif sys.argv[1] == "components":
        components(sys.argv[2])
    else:
        lattice()
