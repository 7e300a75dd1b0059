"""CSV readers shared by the pipelines: rows as dicts, and time-series files (the tools'
series.csv / frag_series.csv, one number per cell) as one numpy column per header name."""
import csv

import numpy as np


def read_rows(path):
    """All rows of a CSV file with a header line, as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_columns(path):
    """A numeric CSV with a header line (e.g. ssdem-grav's series.csv) as {column: float array}.
    Raises IndexError for a file without data rows, ValueError for a non-numeric cell."""
    rows = read_rows(path)
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
