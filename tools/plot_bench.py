#!/usr/bin/env python3
"""Draws aerial-bench's CSV: milliseconds per frame against error (RMSE in 8-bit steps against the
per-pixel image of the reference model), log-log, one chart per scene (DIR/pareto-SCENE.png) and
an overview with a panel per scene (DIR/pareto.png). The Pareto front (no other row is both
faster and more accurate) is drawn as a step line through its points, which are ringed.
Usage: plot_bench.py bench.csv DIR"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

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
    ax.set_title(scene, fontsize=9)
    ax.set_xlabel("ms per frame (llvmpipe, best of several)", fontsize=8)
    ax.set_ylabel("RMSE against reference (8-bit steps)", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    if legend:
        ax.legend(fontsize=6, loc="best", title="o uniform, ^ adaptive", title_fontsize=6)


def main():
    if len(sys.argv) != 3:
        print("usage: plot_bench.py bench.csv DIR", file=sys.stderr)
        return 2
    with open(sys.argv[1]) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print("plot_bench.py: %s has no rows" % sys.argv[1], file=sys.stderr)
        return 2
    out = sys.argv[2]
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    for scene in scenes:
        fig, ax = plt.subplots(figsize=(6, 4.2))
        draw(ax, [r for r in rows if r["scene"] == scene], scene)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "pareto-%s.png" % scene), dpi=100)
        plt.close(fig)
    cols = min(3, len(scenes))
    lines = math.ceil(len(scenes) / cols)
    fig, axes = plt.subplots(lines, cols, figsize=(4.6 * cols, 3.6 * lines), squeeze=False)
    for i, scene in enumerate(scenes):
        draw(axes[i // cols][i % cols], [r for r in rows if r["scene"] == scene], scene,
             legend=(i == 0))
    for j in range(len(scenes), lines * cols):
        axes[j // cols][j % cols].axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "pareto.png"), dpi=90)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
