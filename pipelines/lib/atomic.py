"""Atomic output files for the pipelines' scripts: written under a temporary name in the target
directory, then renamed, so that a reader (or Make) never sees a half-written table or PNG."""
import io
import os
import tempfile


def _umask():
    """The process umask, read without changing it (/proc), else by setting and restoring it."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except OSError:
        pass
    m = os.umask(0o022)
    os.umask(m)
    return m


def write_bytes(path, data):
    """Write `data` to `path` atomically (fsync, then rename over any old file). The file gets the
    mode the umask implies (0666 & ~umask, as open(2) and the C++ tools give), not mkstemp's 0600."""
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", dir=d)
    try:
        os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_text(path, text):
    write_bytes(path, text.encode())


def save_png(fig, path, dpi, close=True):
    """A matplotlib figure as PNG at `path`, atomically; closes the figure unless close=False."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    if close:
        import matplotlib.pyplot as plt
        plt.close(fig)
    write_bytes(path, buf.getvalue())
