"""The impact report generator (pipelines/report/make_report.py is its command line).

Modules, one concern each:
  common    "not available", number formatting
  discover  finding a run's files by content (Run)
  inputs    reading them: JSON, CSV, snapshot arrays, stage timings, scene bodies
  physics   the paper's and Benz & Asphaug's numbers, specific impact energy Q and Q*_D
  sections  the Markdown tables: inputs, outcome, comparison with the paper, audit, run times, files
  cutaway   cut-away views of snapshots (impact frame, slab, panels)
  figures   the four figures and their paragraphs
  files     atomic output files
  cli       command line and the report's assembly (main)
Shared with the other pipelines (pipelines/lib): atomic, csvio, h5io.
"""
import os
import sys

# the pipelines' shared helpers (pipelines/lib)
_LIB = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "lib"))
if _LIB not in sys.path:
    sys.path.insert(0, _LIB)
