"""The report's Markdown sections as lists of lines: title, inputs and the impact energy, outcome
of the analysis, comparison with El Mir et al. (2019) (and where this run differs), the hand-off
audit, stage run times, and the list of files found with the notes."""
import math
import os

import numpy as np

from .common import NA, dig, fmt, pct, vec3
from .inputs import parse_timing_file
from .physics import PAPER


def title_section(title):
    return [f"# {title}\n",
            "Pipeline: `mpm-frag` (fragmentation) -> `mpm2spheres` (hand-off) -> `ssdem-grav` (reaccumulation) "
            "-> `ssdem-analyse` -> this report. Seed paper: El Mir, Ramesh & Richardson (2019), Icarus 321:1013.\n"]


def inputs_section(e, summary, bodies):
    """Inputs table: the bodies, Q, Q*_D and Q/Q*_D (e: physics.impact_energy)."""
    inp = (summary or {}).get("inputs", {})
    m_imp, m_src, speed, v_src = e["m_imp"], e["m_src"], e["speed"], e["v_src"]
    M_t, M_t_src, rho_t, R_t, R_src = e["M_t"], e["M_t_src"], e["rho_t"], e["R_t"], e["R_src"]
    Q, Qs, q_ratio = e["Q"], e["Qs"], e["q_ratio"]
    md = []
    md.append("## Inputs\n")
    md.append("| quantity | value | source |\n|---|---|---|")
    md.append(f"| impactor mass m_imp | {fmt(m_imp, 5, 'kg')} | {m_src} |")
    md.append(f"| impact speed U | {fmt(speed, 5, 'm/s')} | {v_src} |")
    if bodies and inp.get("impactor_mass"):
        md.append(f"| impactor mass / speed used for beta | {fmt(inp.get('impactor_mass'), 5, 'kg')} / "
                  f"{fmt(inp.get('impact_speed'), 5, 'm/s')} | analysis |")
    if bodies:
        md.append(f"| impactor radius | {fmt(bodies['impactor']['radius'], 5, 'm')} | scene |")
    md.append(f"| target mass M_target | {fmt(M_t, 5, 'kg')} | {M_t_src} |")
    md.append(f"| target radius R | {fmt(R_t, 5, 'm')} | {R_src} |")
    md.append(f"| parent-body mass M_PB (for M_LR/M_PB) | {fmt(inp.get('parent_body_mass'), 5, 'kg')} | "
              f"{inp.get('parent_body_mass_source', NA)} |")
    md.append(f"| impact direction | {inp.get('impact_direction', NA)} | analysis |")
    if inp.get("impact_source"):
        md.append(f"| impact values used by the analysis | from {inp['impact_source']} | analysis |")
    mi = inp.get("mpm_initial")
    if isinstance(mi, dict):
        md.append(f"| discretised impactor / target (MPM t = 0) | {fmt(mi.get('impactor_mass'), 5, 'kg')} "
                  f"({mi.get('impactor_particles', '?')} particles) / {fmt(mi.get('target_mass'), 5, 'kg')} "
                  f"({mi.get('target_particles', '?')} particles) | analysis |")
        try:
            vi = np.asarray(mi["impactor_velocity"], float) - np.asarray(mi["target_velocity"], float)
            qd = 0.5 * mi["impactor_mass"] * float(vi @ vi) / mi["target_mass"]
            md.append(f"| Q of the discretised bodies | {fmt(qd, 5, 'J/kg')} | computed |")
        except (KeyError, TypeError, ZeroDivisionError):
            pass
    md.append(f"| specific impact energy Q = m_imp U^2 / (2 M_target) | {fmt(Q, 5, 'J/kg')} = {fmt(Q * 1e4 if Q else None, 4, 'erg/g')} | computed |")
    md.append(f"| Q*_D (Benz & Asphaug 1999, basalt 5 km/s, R, rho = {fmt(rho_t, 4)} kg/m^3) | {fmt(Qs, 4, 'erg/g')} | computed |")
    md.append(f"| Q / Q*_D | {fmt(q_ratio, 3)} | computed |")
    if q_ratio is not None:
        est = 0.5 - 0.5 * (q_ratio - 1)
        md.append("| BA99 rough estimate of M_LR/M_PB, 0.5 - 0.5 (Q/Q*_D - 1) | "
                  + (fmt(est, 3) if 0.0 < est <= 1.0 else f"outside the fit's range (Q/Q*_D = {q_ratio:.3g})")
                  + " | [R] near-Q* fit |")
    if summary:
        md.append(f"| FOF surface linking length | {fmt(inp.get('link_length'), 4, 'm')} | analysis |")
        md.append(f"| G | {fmt(inp.get('G'), 5)} | analysis |")
    md.append("")
    return md


def outcome_section(summary):
    """Outcome of the analysis at the last snapshot, with its definitions."""
    md = []
    fin = (summary or {}).get("final", {})
    md.append("## Outcome\n")
    if summary:
        md.append(f"At t = {fmt(fin.get('time'), 5, 's')} ({fmt((fin.get('time') or 0) / 3600, 4, 'h')}), "
                  f"{fin.get('n_spheres', NA)} spheres form {fin.get('n_clumps', NA)} clumps "
                  f"({fin.get('n_single_spheres', NA)} single spheres).\n")
        md.append("| quantity | value |\n|---|---|")
        rows = [("largest remnant M_LR / M_PB", fmt(fin.get("M_LR_over_M_PB"), 5)),
                ("bound remnant (LR + bound clumps) / M_PB", fmt(fin.get("bound_mass_fraction"), 5)),
                ("escaping mass", fmt(fin.get("escaping_mass"), 5, "kg") + f" ({pct(fin.get('escaping_mass_fraction'))} of M_PB)"),
                ("escaping momentum along impact direction", fmt(fin.get("escaping_momentum_along_impact"), 5, "kg m/s")),
                ("beta (bound remnant)", fmt(fin.get("beta"), 5)),
                ("beta (largest remnant only)", fmt(fin.get("beta_lr"), 5)),
                ("beta from escaping ejecta, 1 - P_esc.U/(mU)", fmt(fin.get("beta_ejecta"), 5)),
                ("beta, vector form (Cheng et al. 2023)", fmt(fin.get("beta_vector"), 5)),
                ("beta with the snapshot's total momentum as reference", fmt(fin.get("beta_total"), 5)),
                ("beta from spheres above the local escape speed (sphere by sphere)", fmt(fin.get("beta_escape_speed"), 5)),
                ("momentum conservation |P - mU|/(mU)", fmt(fin.get("momentum_error"), 3)),
                ("bound-remnant velocity", vec3(fin.get("bound_remnant_velocity"), "m/s"))]
        for k, v in rows:
            md.append(f"| {k} | {v} |")
        md.append("")
        defs = summary.get("definitions", {})
        if defs:
            md.append("**Definitions** (from the analysis):\n")
            for k in ("frame", "clumps", "bound", "beta", "beta_lr", "beta_ejecta", "beta_vector", "beta_total",
                      "beta_escape_speed", "damage_profile"):
                if k in defs:
                    md.append(f"- *{k}*: {defs[k]}")
            md.append("")
    else:
        md.append(f"Analysis summary: {NA} (no ssdem-analyse JSON in the run directory).\n")
    return md


def comparison_section(e, summary, audit):
    """The paper's numbers beside this run's, and where they differ."""
    Q, q_ratio = e["Q"], e["q_ratio"]
    fin = (summary or {}).get("final", {})
    md = []
    md.append("## Comparison with El Mir et al. (2019)\n")
    ke = audit.get("kinetic_rel_loss") if audit else None
    md.append("| quantity | paper | this run |\n|---|---|---|")
    md.append(f"| Q | 1.13e+08 erg/g (d_imp/D = 0.0968; see note) | {fmt(Q * 1e4 if Q else None, 4, 'erg/g')} |")
    md.append(f"| M_LR/M_PB | {PAPER['M_LR_over_M_PB']} | {fmt(fin.get('M_LR_over_M_PB'), 4)} |")
    md.append(f"| beta | {PAPER['beta']} | {fmt(fin.get('beta'), 4)} |")
    md.append(f"| hand-off kinetic-energy loss | 0.39 % | {pct(ke)} |")
    md.append(f"| N-body time | 4.5 h | {fmt(fin['time'] / 3600, 3, 'h') if fin.get('time') is not None else NA} |")
    n_part = None
    if audit:
        n_part = audit.get("input", {}).get("count")
    md.append(f"| MPM particles | ~1e6 (200 m cells) | {n_part if n_part else NA} |")
    md.append("")
    md.append("The paper's abstract gives a 1.21 km impactor but Q = 1.13e8 erg/g needs d_imp/D = 0.0968 (a 2.42 km "
              "impactor on the 25 km target); a 1.21 km diameter gives Q = 1.417e7 erg/g (validation-data.md §4.1, §0).\n")
    md.append(differences(Q, fin, ke, n_part, summary, audit))
    if q_ratio is not None and 0.0 < 0.5 - 0.5 * (q_ratio - 1) <= 1.0:
        md.append(f"For this run's Q/Q*_D = {q_ratio:.3g}, the Benz & Asphaug (1999) near-Q* fit suggests "
                  f"M_LR/M_PB ~ {0.5 - 0.5 * (q_ratio - 1):.2f} (a rough guide, [R]); the paper reports higher disruption "
                  "thresholds when granular flow and pore collapse are included (M_LR/M_PB = 0.85 against ~0.5 in "
                  "Michel & Richardson 2013).\n")
    return md


def audit_section(run, audit):
    """The mpm2spheres audit: counts, conservation, kinetic-energy loss."""
    md = []
    md.append("## Hand-off audit (mpm2spheres)\n")
    if audit:
        md.append(f"Source: `{run.audit}`, method `{audit.get('method', NA)}`.\n")
        md.append("| quantity | value |\n|---|---|")
        g = lambda *ks: dig(audit, ks)  # noqa: E731
        for k, v in [("particles in file / handed off / dropped", f"{g('input', 'count')} / {g('before', 'count')} / {g('dropped', 'count')}"),
                     ("spheres", g("after", "count")),
                     ("mass relative difference", fmt(g("mass_rel_diff"), 3)),
                     ("momentum |dP| / (M v_rms)", fmt(g("momentum_rel_diff"), 3)),
                     ("angular momentum relative difference", fmt(g("angular_momentum_rel_diff"), 3)),
                     ("kinetic energy before / after", f"{fmt(g('before', 'kinetic'), 5, 'J')} / {fmt(g('after', 'kinetic'), 5, 'J')}"),
                     ("kinetic energy loss (paper: 0.39 %)", pct(g("kinetic_rel_loss"))),
                     ("rotational KE of spheres", fmt(g("after", "kinetic_rotational"), 4, "J")),
                     ("centre-of-mass shift", fmt(g("centre_of_mass_shift"), 4, "m")),
                     ("closest sphere gap / max overlap", f"{fmt(g('min_gap'), 4, 'm')} / {fmt(g('max_overlap'), 4, 'm')}"),
                     ("note", g("note") or "")]:
            md.append(f"| {k} | {v} |")
        md.append("")
    else:
        md.append(f"Hand-off audit: {NA}.\n")
    return md


def timings_section(run):
    """Wall time of each stage found in the timing files, and the total."""
    md = []
    md.append("## Run times\n")
    times = []
    for p in run.timings:
        times += parse_timing_file(p)
    if times:
        md.append("| stage | wall time |\n|---|---|")
        for s, w in times:
            md.append(f"| {s} | {fmt(w, 4, 's')} |")
        md.append(f"| **total** | {fmt(sum(w for _, w in times), 4, 's')} |\n")
    else:
        md.append(f"Stage timings: {NA} (no timings.csv, *.timing.json or *.time file).\n")
    return md


def files_section(run, summary, notes):
    """The files found, then every note (discovery, loading, figures, the analysis' own notes);
    the analysis notes are appended to `notes`."""
    md = []
    md.append("## Files\n")
    md.append(f"- MPM snapshots: {len(run.mpm)}" + (f" ({os.path.dirname(run.mpm[0][1])})" if run.mpm else ""))
    md.append(f"- hand-off spheres: {run.handoff[0][1] if run.handoff else NA}")
    md.append(f"- N-body snapshots: {len(run.nbody)}" + (f" ({os.path.dirname(run.nbody[0][1])})" if run.nbody else ""))
    md.append(f"- analysis summary: {run.analysis or NA}")
    md.append(f"- hand-off audit: {run.audit or NA}")
    if run.failed_states:
        md.append(f"- **failed-state files present** (a stage stopped with a numerical failure): {', '.join(run.failed_states)}")
    if summary and summary.get("notes"):
        notes += [f"analysis: {n}" for n in summary["notes"]]
    if notes:
        md.append("\n## Notes\n")
        md += [f"- {n}" for n in notes]
    return md


def dropped_momentum_fraction(audit, summary):
    """|momentum of the fragments dropped at the hand-off| / (m |U|), from the hand-off audit and the
    analysis' impactor momentum; None where either is missing."""
    try:
        p = audit["dropped"]["momentum"]
        mu = float(summary["inputs"]["impactor_momentum"])
    except (KeyError, TypeError, ValueError):
        return None
    return math.sqrt(sum(float(x) ** 2 for x in p)) / mu if mu > 0 else None


def differences(Q, fin, ke, n_part, summary, audit=None):
    """Plain sentences where this run differs from the paper."""
    s = []
    lr, beta = fin.get("M_LR_over_M_PB"), fin.get("beta")
    if Q:
        r = Q * 1e4 / PAPER["Q_erg_g"]
        if abs(r - 1) > 0.05:
            s.append(f"This run's specific impact energy is {r:.3g} times the paper's Q = 1.13e8 erg/g, so a different "
                     "largest remnant and beta are expected even with identical physics.")
    if lr is not None and abs(lr - PAPER["M_LR_over_M_PB"]) > 0.05 * PAPER["M_LR_over_M_PB"]:
        s.append(f"M_LR/M_PB = {lr:.3g} differs from the paper's 0.85 by {100 * (lr / 0.85 - 1):+.0f} %.")
    if beta is not None and abs(beta - PAPER["beta"]) > 0.05 * PAPER["beta"]:
        s.append(f"beta = {beta:.3g} differs from the paper's 1.69 by {100 * (beta / 1.69 - 1):+.0f} %.")
    if ke is not None and abs(ke - PAPER["handoff_ke_loss"]) > 0.5 * PAPER["handoff_ke_loss"]:
        s.append(f"The hand-off kinetic-energy loss ({100 * ke:.3g} %) differs from the paper's 0.39 %; "
                 "it depends on the sphere size relative to the MPM cell and on the projection method.")
    if s:
        t = fin.get("time")
        if t is not None and t < 0.9 * PAPER["nbody_time_s"]:
            s.append(f"The N-body run covers {t / 3600:.3g} h of the paper's 4.5 h, so reaccumulation may be unfinished "
                     "(compare the M_LR/M_PB history below).")
        if n_part and n_part < 0.5 * PAPER["particles"]:
            s.append(f"The MPM resolution ({n_part} particles against ~1e6) is coarser than the paper's, which changes "
                     "the damage pattern, fragment sizes and ejecta speeds.")
        if summary and (fin.get("momentum_error") or 0) > 0.01:
            drop = dropped_momentum_fraction(audit, summary)
            if drop is not None and drop > 0.01:
                s.append(f"The spheres' total momentum differs from the impactor's by {100 * fin['momentum_error']:.2g} % of "
                         f"it; the {audit['dropped'].get('count', '')} fragments dropped at the hand-off (faster than its "
                         f"speed limit; audited) carry {100 * drop:.2g} % of the impactor momentum. beta from the bound "
                         "remnant (the headline) does not depend on them; beta_ejecta and beta_total miss their momentum.")
            else:
                s.append(f"Momentum is conserved only to {100 * fin['momentum_error']:.2g} % of the impactor momentum, "
                         "which limits the accuracy of beta.")
        s.append("Flaw seeding is random, so a few per cent of scatter is expected between runs (validation-data.md §8).")
        return "**Where we differ.** " + " ".join(s) + "\n"
    if lr is None and beta is None:
        return f"Outcome numbers: {NA}.\n"
    return "M_LR/M_PB, beta and the hand-off loss agree with the paper within 5 %.\n"
