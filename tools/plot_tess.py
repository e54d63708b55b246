#!/usr/bin/env python3
"""Draws aerial-tess's CSV: max error (8-bit steps) against vertices, log-log, one panel per
scene, a line at 1 LSB.  The maxima are whole steps (GL images against the per-pixel
reference); 0 is drawn at 0.5 so that it stays on the log scale.  Each method's points are
joined in order of vertices (the sweep's fine search runs between coarse levels).
Usage: plot_tess.py tess.csv tess.png"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 3:
        print("usage: plot_tess.py tess.csv tess.png", file=sys.stderr)
        return 2
    rows = list(csv.DictReader(open(sys.argv[1])))
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    cols = min(4, len(scenes))
    lines = math.ceil(len(scenes) / cols)
    fig, axes = plt.subplots(lines, cols, figsize=(4 * cols, 3.2 * lines), squeeze=False)
    styles = {"adaptive": "o-", "adaptive-relocate": "P-", "uniform-geodesic": "s--", "uniform-latlong": "^:",
              "uniform-grid": "s--", "uniform-distance-lod": "v:", "decimated": "d-."}
    for i, scene in enumerate(scenes):
        ax = axes[i // cols][i % cols]
        methods = []
        for r in rows:
            if r["scene"] == scene and r["method"] not in methods:
                methods.append(r["method"])
        for m in methods:
            pts = sorted((int(r["vertices"]), max(float(r["max_lsb"]), 0.5)) for r in rows
                         if r["scene"] == scene and r["method"] == m)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], styles.get(m, "x-"), label=m,
                    markersize=3)
        ax.axhline(1.0, color="grey", linewidth=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(scene, fontsize=9)
        ax.set_xlabel("vertices", fontsize=8)
        ax.set_ylabel("max error (LSB)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=6)
    for j in range(len(scenes), lines * cols):
        axes[j // cols][j % cols].axis("off")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
