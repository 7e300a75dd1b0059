"""The physics of the report: the seed paper's outcome numbers, Benz & Asphaug (1999) Q*_D, and the
impact's specific energy Q = m_imp U^2 / (2 M_target) with where each input came from.

  Q*_D (Benz & Asphaug 1999, basalt 5 km/s): Q0 (R/cm)^a + B rho (R/cm)^b, Q0 = 9e7 erg/g,
       a = -0.36, B = 0.5 erg cm^3 g^-2, b = 1.36 (validation-data.md §4.2)
  BA99 rough largest remnant: M_LR/M_PB ~ -0.5 (Q/Q*_D - 1) + 0.5 (validation-data.md §4.2, [R])
"""
import math

import numpy as np

from .common import NA

# El Mir, Ramesh & Richardson (2019), Icarus 321:1013 (validation-data.md §4.3)
PAPER = {"M_LR_over_M_PB": 0.85, "beta": 1.69, "handoff_ke_loss": 0.0039,
         "Q_erg_g": 1.13e8, "target_diameter_m": 25e3, "speed": 5000.0, "particles": 1e6,
         "nbody_time_s": 4.5 * 3600, "mpm_time_s": 30.0}
# Benz & Asphaug (1999) basalt at 5 km/s (validation-data.md §4.2) [V]
BA99 = {"Q0": 9.0e7, "a": -0.36, "B": 0.5, "b": 1.36}


def q_star_ba99(R_m, rho_kg_m3):
    Rcm = R_m * 100.0
    rho = rho_kg_m3 / 1000.0
    return BA99["Q0"] * Rcm ** BA99["a"] + BA99["B"] * rho * Rcm ** BA99["b"]  # erg/g



def impact_energy(summary, bodies):
    """Q, Q*_D and Q/Q*_D with their inputs and each input's source, as a dict.

    Q from the scene (nominal bodies, as the paper defines it); the analysis values otherwise."""
    inp = (summary or {}).get("inputs", {})
    if bodies:
        m_imp, m_src = bodies["impactor"]["mass"], "scene"
        speed, v_src = float(np.linalg.norm(bodies["impactor"]["velocity"] - bodies["target"]["velocity"])), "scene"
    else:
        m_imp, m_src = inp.get("impactor_mass") or None, "analysis" if inp.get("impactor_mass") else NA
        speed, v_src = inp.get("impact_speed") or None, "analysis" if inp.get("impact_speed") else NA
    if bodies:
        M_t, M_t_src = bodies["target"]["mass"], f"target body of the scene ({bodies['source']})"
    elif inp.get("parent_body_mass"):
        M_t, M_t_src = inp["parent_body_mass"], "parent-body mass of the analysis (" + inp.get("parent_body_mass_source", "") + ")"
    else:
        M_t, M_t_src = None, NA
    rho_t = bodies["target"]["density"] if bodies else 2700.0
    if bodies:
        R_t, R_src = bodies["target"]["radius"], "scene"
    elif inp.get("target_radius"):
        R_t, R_src = inp["target_radius"], "analysis input"
    elif M_t:
        R_t, R_src = (3 * M_t / (4 * math.pi * rho_t)) ** (1 / 3), "from M_target at 2700 kg/m^3"
    else:
        R_t, R_src = None, NA
    Q = 0.5 * m_imp * speed ** 2 / M_t if (m_imp and speed and M_t) else None
    Qs = q_star_ba99(R_t, rho_t) if R_t else None  # erg/g
    q_ratio = Q * 1e4 / Qs if (Q and Qs) else None
    return {"m_imp": m_imp, "m_src": m_src, "speed": speed, "v_src": v_src, "M_t": M_t, "M_t_src": M_t_src,
            "rho_t": rho_t, "R_t": R_t, "R_src": R_src, "Q": Q, "Qs": Qs, "q_ratio": q_ratio}
