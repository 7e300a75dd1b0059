"""Atomic output files for the pipelines' scripts: written under a temporary name in the target
directory, then renamed, so that a reader (or Make) never sees a half-written table or PNG."""
import io
import os
import tempfile


def write_bytes(path, data):
    """Write `data` to `path` atomically (fsync, then rename over any old file)."""
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", dir=d)
    try:
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
