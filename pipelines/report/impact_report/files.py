"""The report's output files, written atomically (temporary name + rename) via pipelines/lib/atomic.py."""
import atomic


def save_fig(fig, path):
    """A figure as PNG (110 dpi); the figure is closed."""
    atomic.save_png(fig, path, dpi=110)


def write_text(path, text):
    atomic.write_text(path, text)
