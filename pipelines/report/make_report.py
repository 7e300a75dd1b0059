#!/usr/bin/python3
"""Impact report: one Markdown page + PNG figures for a run directory of the impact pipeline.

    /usr/bin/python3 make_report.py RUN_DIR [--out DIR] [--mpm F ...] [--spheres F ...]
        [--handoff F] [--audit F] [--analysis F] [--timings F ...] [--scene F ...] [--title T]

Inputs are found in RUN_DIR (recursively) by *content*, so stage file names do not matter:
  * *.h5 with root attribute format = "mpm-frag.particles"  -> MPM snapshots (damage cut-aways, Fig. 4)
  * *.h5 with format = "ssdem.spheres" and /provenance tool "mpm2spheres" -> hand-off spheres
  * *.h5 with format = "ssdem.spheres" (other tools; checkpoint*/failed_state* skipped) -> N-body
    snapshots (spheres coloured by damage, Fig. 5)
  * *.audit.json -> hand-off audit (mpm2spheres)
  * *.json with "format": "ssdem-analyse.summary" -> analysis summary; its "outputs" name the
    time-series and damage-profile CSVs (also looked up beside the JSON)
  * timings: timings.csv / times.csv (columns stage, wall_s), *.timing.json ({"stage", "wall_s"}),
    *.time (a number of seconds, `/usr/bin/time -p` output "real S", or `/usr/bin/time -v` output)
  * scenes: *.toml in RUN_DIR, and the scene recorded in each file's /provenance (mpm-frag's
    [[body]] / [[material]] give target and impactor masses when the analysis JSON does not)
Explicit options override discovery. Every missing piece is reported as "not available"; the
script only fails (exit 2) when RUN_DIR does not exist.

Outputs (in --out, default RUN_DIR/report): report.md, fig_mpm_damage.png, fig_nbody_spheres.png,
fig_history.png, fig_damage_profile.png (a figure whose inputs are missing is not written and the
report says so). Files are written atomically (temporary name + rename).

Physics in the report:
  Q = 1/2 m_imp |U|^2 / M_target (specific impact energy; validation-data.md §4.1)
  Q*_D (Benz & Asphaug 1999, basalt 5 km/s): Q0 (R/cm)^a + B rho (R/cm)^b, Q0 = 9e7 erg/g,
       a = -0.36, B = 0.5 erg cm^3 g^-2, b = 1.36 (validation-data.md §4.2)
  BA99 rough largest remnant: M_LR/M_PB ~ -0.5 (Q/Q*_D - 1) + 0.5 (validation-data.md §4.2, [R])
  beta: as defined in the analysis JSON ("definitions"), momentum bookkeeping in the target frame.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from impact_report.cli import main  # noqa: E402
from impact_report.physics import q_star_ba99  # noqa: E402  (tests/analysis/test_report.py uses it)

__all__ = ["main", "q_star_ba99"]

if __name__ == "__main__":
    sys.exit(main())
