"""pipelines/lib/atomic.py: report files (report.md, PNGs) get the mode the umask implies, like the
C++ tools' outputs, not mkstemp's 0600 (which left reports unreadable by the group)."""
import os
import stat
import sys
import tempfile

sys.path.insert(0, sys.argv[1])  # pipelines/lib
import atomic  # noqa: E402

FAILURES = []


class FakeFigure:
    def savefig(self, buf, format, dpi):
        buf.write(b"\x89PNG fake")


with tempfile.TemporaryDirectory() as d:
    for umask in (0o022, 0o002, 0o077):
        old = os.umask(umask)
        try:
            for name, write in (("report.md", lambda p: atomic.write_text(p, "# report\n")),
                                ("fig.png", lambda p: atomic.save_png(FakeFigure(), p, 72, close=False))):
                path = os.path.join(d, name)
                write(path)
                mode = stat.S_IMODE(os.stat(path).st_mode)
                want = 0o666 & ~umask
                ok = mode == want
                print(("ok   " if ok else "FAIL ") + f"umask {umask:03o}: {name} mode {mode:03o}, expected {want:03o}")
                if not ok:
                    FAILURES.append(name)
        finally:
            os.umask(old)
    leftovers = sorted(set(os.listdir(d)) - {"report.md", "fig.png"})
    if leftovers:
        print("FAIL temporary files left:", leftovers)
        FAILURES.append("leftovers")
sys.exit(1 if FAILURES else 0)
