"""HDF5 files of the suite's tools (mpm-frag particles, ssdem.spheres snapshots): root attributes
(bytes decoded, 0-d arrays unwrapped), the /provenance group, and the datasets of one group
with the file's time. h5py is None where the module is not installed."""
import numpy as np

try:
    import h5py
except ImportError:  # pragma: no cover
    h5py = None


def attr(f, name, default=None):
    """A root attribute of an open file: str for strings, a scalar for 0-d arrays."""
    v = f.attrs.get(name, default)
    if isinstance(v, bytes):
        v = v.decode()
    if isinstance(v, np.ndarray) and v.shape == ():
        v = v[()]
    return v


def provenance(f):
    """The /provenance attributes (tool, version, git_sha, command_line, scene) as strings."""
    out = {}
    if "provenance" in f:
        for k, v in f["provenance"].attrs.items():
            out[k] = v.decode() if isinstance(v, bytes) else str(v)
    return out


def read_group(path, group, names, optional=()):
    """(time attribute, {name: array}) for the datasets `names` of `group` (a missing one raises
    h5py's KeyError) and those of `optional` that the file has."""
    with h5py.File(path, "r") as f:
        g = f[group]
        data = {k: g[k][...] for k in names}
        data.update({k: g[k][...] for k in optional if k in g})
        t = attr(f, "time", 0.0)
    return t, data
