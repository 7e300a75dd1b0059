#!/usr/bin/python3
"""convergence.py's estimate (impact-convergence): Richardson through the three finest runs recovers
an exact power law f = f0 + C h^p (value and order), and refuses non-monotone data, an order outside
the credible range, and a value outside the quantity's physical range (a negative heat).
usage: test_convergence.py <repo root>"""
import math
import os
import sys

sys.path.insert(0, os.path.join(sys.argv[1], "pipelines", "impact"))
import convergence as cv  # noqa: E402

fails = []


def check(cond, msg):
    if not cond:
        fails.append(msg)


h = [2000.0, 1500.0, 1000.0, 750.0]
# exact power law: the three finest runs (1500, 1000, 750) give f0 and p
f = [0.8 + 3e-5 * x ** 1.5 for x in h]
f0, p, note = cv.estimate("M_LR_over_M_PB", h, f)
check(note == "Richardson" and abs(f0 - 0.8) < 1e-9 and abs(p - 1.5) < 1e-6, f"power law: {f0} {p} {note}")
# only the three finest count: a wild coarsest run changes nothing
f0b, pb, _ = cv.estimate("M_LR_over_M_PB", h, [5.0] + f[1:])
check(f0b is not None and abs(f0b - f0) < 1e-12 and abs(pb - p) < 1e-12, "the coarsest run entered the fit")
# non-monotone
f0, p, note = cv.estimate("beta", h, [1.4, 1.5, 2.08, 1.9])
check(f0 is None and "non-monotone" in note, f"non-monotone: {note}")
# an order outside [0.5, 4]: differences that barely shrink (p ~ 0.1)
g = [1.0 + x ** 0.1 for x in h]
f0, p, note = cv.estimate("beta", h, g)
check(f0 is None and "outside" in note, f"p = 0.1 accepted: {note}")
# the physical range: the transfer heat of the paper-method runs at 2000/1500/1000 m extrapolates to < 0
f0, p, note = cv.estimate("transfer_heat_frac", [2000.0, 1500.0, 1000.0], [1.573, 1.071, 0.597])
check(f0 is None and "physical range" in note, f"negative heat accepted: {note}")
# the same numbers as a quantity without a range are extrapolated
f0, p, note = cv.estimate("beta", [2000.0, 1500.0, 1000.0], [1.573, 1.071, 0.597])
check(f0 is not None and f0 < 0 and math.isfinite(p), f"unbounded quantity refused: {note}")
if fails:
    print("FAIL:\n  " + "\n  ".join(fails))
    sys.exit(1)
print("convergence.py estimate: power law, non-monotone, order range and physical range: ok")
