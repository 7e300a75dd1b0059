"""Shared pieces of the impact report: the "not available" marker, number formatting for the
Markdown tables, and reading HDF5 root attributes and /provenance of the suite's output files."""
import math

import numpy as np

try:
    import h5py
except ImportError:  # pragma: no cover
    h5py = None

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


def h5_attr(f, name, default=None):
    v = f.attrs.get(name, default)
    if isinstance(v, bytes):
        v = v.decode()
    if isinstance(v, np.ndarray) and v.shape == ():
        v = v[()]
    return v


def provenance(f):
    out = {}
    if "provenance" in f:
        for k, v in f["provenance"].attrs.items():
            out[k] = v.decode() if isinstance(v, bytes) else str(v)
    return out


def dig(d, ks):
    """d[k0][k1]... or None where a key is missing."""
    for k in ks:
        if not isinstance(d, dict) or k not in d:
            return None
        d = d[k]
    return d
