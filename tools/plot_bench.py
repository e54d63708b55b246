#!/usr/bin/env python3
"""Draws aerial-bench's CSV: milliseconds per frame against error (RMSE in 8-bit steps against the
per-pixel image of the reference model), log-log, one chart per scene (DIR/pareto-SCENE.png) and
an overview with a panel per scene (DIR/pareto.png). The Pareto front (no other row is both
faster and more accurate) is drawn as a step line through its points, which are ringed.
Usage: plot_bench.py bench.csv DIR"""
import math
import os
import sys

from plot_common import first_seen, label_panel, panel_grid, plt, read_rows

COLOURS = {"gl-fog": "#7f7f7f", "fg-fog": "#bcbd22", "cpu-hp": "#1f77b4", "arb-hp": "#17becf",
           "cpu-height": "#d62728", "arb-height": "#ff7f0e", "lut-texture": "#9467bd",
           "perpixel-reference": "#2ca02c"}
MARKERS = {"uniform": "o", "adaptive": "^"}
FLOOR = 0.01  # an error of 0 is drawn here on the log axis


def front(points):
    """Indices of the Pareto front of (ms, error) points, fastest first."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    result, best = [], math.inf
    for i in order:
        if points[i][1] < best:
            result.append(i)
            best = points[i][1]
    return result


def draw(ax, rows, scene, legend=True):
    pts = [(float(r["ms_per_frame"]), max(float(r["rmse_lsb"]), FLOOR)) for r in rows]
    for method in COLOURS:
        for tess, marker in MARKERS.items():
            sel = [(p, r) for p, r in zip(pts, rows)
                   if r["method"] == method and r["tessellation"] == tess]
            if not sel:
                continue
            label = method if tess == "uniform" or all(
                r["method"] != method or r["tessellation"] != "uniform" for r in rows) else None
            ax.scatter([p[0] for p, _ in sel], [p[1] for p, _ in sel], c=COLOURS[method],
                       marker=marker, s=22, label=label, zorder=3)
    f = front(pts)
    fx = [pts[i][0] for i in f]
    fy = [pts[i][1] for i in f]
    ax.step(fx, fy, where="post", color="black", linewidth=0.8, zorder=2, label="Pareto front")
    ax.scatter(fx, fy, s=70, facecolors="none", edgecolors="black", linewidths=0.8, zorder=4)
    ax.set_xscale("log")
    ax.set_yscale("log")
    label_panel(ax, scene, "ms per frame (llvmpipe, best of several)",
                "RMSE against reference (8-bit steps)")
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    if legend:
        ax.legend(fontsize=6, loc="best", title="o uniform, ^ adaptive", title_fontsize=6)


def main():
    rows = read_rows(sys.argv, "plot_bench.py bench.csv DIR")
    if rows is None:
        return 2
    if not rows:
        print("plot_bench.py: %s has no rows" % sys.argv[1], file=sys.stderr)
        return 2
    out = sys.argv[2]
    scenes = first_seen(rows, "scene")
    for scene in scenes:
        fig, ax = plt.subplots(figsize=(6, 4.2))
        draw(ax, [r for r in rows if r["scene"] == scene], scene)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "pareto-%s.png" % scene), dpi=100)
        plt.close(fig)
    fig, panel = panel_grid(len(scenes), min(3, len(scenes)), 4.6, 3.6)
    for i, scene in enumerate(scenes):
        draw(panel(i), [r for r in rows if r["scene"] == scene], scene, legend=(i == 0))
    fig.tight_layout()
    fig.savefig(os.path.join(out, "pareto.png"), dpi=90)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
