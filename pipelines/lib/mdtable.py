"""Markdown table lines shared by the pipelines' table writers (header + separator, one row)."""


def header(columns):
    """Two lines: "| a | b |" and "|---|---|"."""
    return ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]


def row(cells):
    """One table line from already formatted cells."""
    return "| " + " | ".join(str(c) for c in cells) + " |"
