"""Shared pieces of the impact report: the "not available" marker, number formatting for the
Markdown tables, and a nested-dict lookup."""
import math


NA = "not available"


def fmt(x, digits=4, unit=""):
    if x is None:
        return NA
    try:
        x = float(x)
    except (TypeError, ValueError):
        return str(x)
    if not math.isfinite(x):
        return NA
    s = f"{x:.{digits}g}"
    return f"{s} {unit}".strip()


def pct(x, digits=3):
    return NA if x is None or not math.isfinite(float(x)) else f"{100.0 * float(x):.{digits}g} %"


def vec3(v, unit=""):
    if not isinstance(v, (list, tuple)) or len(v) != 3:
        return NA
    return "(" + ", ".join(fmt(c, 4) for c in v) + f") {unit}".rstrip()


def dig(d, ks):
    """d[k0][k1]... or None where a key is missing."""
    for k in ks:
        if not isinstance(d, dict) or k not in d:
            return None
        d = d[k]
    return d
