#!/usr/bin/env python3
"""Draws aerial-bench --stability's CSV: the worst error (8-bit steps, symlog) of each method
against the swept parameter, one panel per sweep, a line at 2 LSB and markers where an artefact
appears (x: NaN/Inf, ^: clamped, s: banding, D: popping).
Usage: plot_stability.py stability.csv stability.png"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LOG_SWEEPS = {"altitude_m", "distance_m", "turbidity", "visibility_m"}
# Colour by model (blue: the 2002 model, green: height, red/purple: fog, grey: interpolation),
# line style by path (solid: CPU, dashed: ARB, dotted: ARB at 10 bits).
STYLES = {"reference": ("black", "-"), "cpu-hp": ("tab:blue", "-"), "arb-hp": ("tab:cyan", "--"),
          "arb-hp-10bit": ("tab:blue", ":"), "cpu-height": ("tab:green", "-"),
          "arb-height": ("tab:olive", "--"), "arb-height-10bit": ("tab:green", ":"),
          "gl-fog": ("tab:red", "-"), "fg-fog": ("tab:purple", "-"),
          "lerp-screen-4deg": ("tab:gray", "-."), "lerp-world-1km": ("tab:brown", "-.")}
ARTEFACTS = [("nonfinite", "x", "NaN/Inf"), ("clamped", "^", "clamped"),
             ("banding", "s", "banding"), ("popping", "D", "popping")]


def main():
    if len(sys.argv) != 3:
        print("usage: plot_stability.py stability.csv stability.png", file=sys.stderr)
        return 2
    rows = list(csv.DictReader(open(sys.argv[1])))
    sweeps, methods = [], []
    for r in rows:
        if r["sweep"] not in sweeps:
            sweeps.append(r["sweep"])
        if r["method"] not in methods:
            methods.append(r["method"])
    cmap = plt.get_cmap("tab10")
    colours = {m: STYLES.get(m, (cmap(i % 10), "-"))[0] for i, m in enumerate(methods)}
    cols = 3
    lines = (len(sweeps) + cols - 1) // cols
    fig, axes = plt.subplots(lines, cols, figsize=(5.2 * cols, 3.8 * lines), squeeze=False)
    for i, sweep in enumerate(sweeps):
        ax = axes[i // cols][i % cols]
        for m in methods:
            pts = [r for r in rows if r["sweep"] == sweep and r["method"] == m]
            xs = [float(r["value"]) for r in pts]
            ys = [float(r["max_lsb"]) for r in pts]
            style = STYLES.get(m, (None, "-"))[1]
            ax.plot(xs, ys, style, color=colours[m], label=m, linewidth=1.1)
            for field, marker, _ in ARTEFACTS:
                flagged = [(float(r["value"]), float(r["max_lsb"])) for r in pts
                           if int(r[field]) > 0]
                if flagged:
                    ax.plot([p[0] for p in flagged], [p[1] for p in flagged], marker,
                            color=colours[m], markersize=4, fillstyle="none")
        ax.axhline(2.0, color="black", linewidth=0.8, linestyle=(0, (1, 3)))
        if sweep in LOG_SWEEPS:
            ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set_ylim(0, 300)
        ax.set_title(sweep, fontsize=9)
        ax.set_xlabel(sweep, fontsize=8)
        ax.set_ylabel("max error (LSB)", fontsize=8)
        ax.tick_params(labelsize=7)
    for j in range(len(sweeps), lines * cols):
        axes[j // cols][j % cols].axis("off")
    handles, labels = axes[0][0].get_legend_handles_labels()
    for field, marker, name in ARTEFACTS:
        handles.append(plt.Line2D([], [], color="grey", marker=marker, linestyle="none",
                                  fillstyle="none"))
        labels.append(name)
    handles.append(plt.Line2D([], [], color="black", linewidth=0.8, linestyle=(0, (1, 3))))
    labels.append("2 LSB")
    fig.legend(handles, labels, loc="lower center", ncol=8, fontsize=7)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(sys.argv[2], dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
