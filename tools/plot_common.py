"""What the plot_*.py scripts share: the command line (a CSV in, one output path), the CSV's rows,
the order in which values first appear, a grid of panels with the unused ones blanked, and the
axis labels and fonts every panel uses. matplotlib draws off-screen (Agg)."""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401  (the scripts take pyplot from here)


def read_rows(argv, usage):
    """The rows of the CSV named by argv[1], or None after printing USAGE (e.g. "plot_x.py in.csv
    out.png") when the command line is not exactly one CSV and one output path."""
    if len(argv) != 3:
        print("usage: " + usage, file=sys.stderr)
        return None
    with open(argv[1]) as f:
        return list(csv.DictReader(f))


def first_seen(rows, field, **match):
    """The values of FIELD in the order they first appear, over the rows whose other fields equal
    MATCH (e.g. first_seen(rows, "method", scene="hazy"))."""
    values = []
    for r in rows:
        if all(r[k] == v for k, v in match.items()) and r[field] not in values:
            values.append(r[field])
    return values


def panel_grid(count, cols, width, height):
    """A figure with COUNT panels, COLS to a row, each WIDTH x HEIGHT inches; the panels past COUNT
    are switched off. Returns (fig, panel) where panel(i) is the i-th axes."""
    lines = math.ceil(count / cols)
    fig, axes = plt.subplots(lines, cols, figsize=(width * cols, height * lines), squeeze=False)
    for j in range(count, lines * cols):
        axes[j // cols][j % cols].axis("off")
    return fig, lambda i: axes[i // cols][i % cols]


def label_panel(ax, title, xlabel, ylabel):
    """The title, axis labels and tick sizes of every panel (9, 8 and 7 points)."""
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(xlabel, fontsize=8)
    ax.set_ylabel(ylabel, fontsize=8)
    ax.tick_params(labelsize=7)
