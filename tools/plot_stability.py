#!/usr/bin/env python3
"""Draws aerial-bench --stability's CSV: the worst error (8-bit steps, symlog) of each method
against the swept parameter, one panel per sweep, a line at 2 LSB and markers where an artefact
appears (x: NaN/Inf, ^: clamped, s: banding, D: popping).
Usage: plot_stability.py stability.csv stability.png"""
import sys

from plot_common import first_seen, label_panel, panel_grid, plt, read_rows

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
    rows = read_rows(sys.argv, "plot_stability.py stability.csv stability.png")
    if rows is None:
        return 2
    sweeps, methods = first_seen(rows, "sweep"), first_seen(rows, "method")
    cmap = plt.get_cmap("tab10")
    colours = {m: STYLES.get(m, (cmap(i % 10), "-"))[0] for i, m in enumerate(methods)}
    fig, panel = panel_grid(len(sweeps), 3, 5.2, 3.8)
    for i, sweep in enumerate(sweeps):
        ax = panel(i)
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
        label_panel(ax, sweep, sweep, "max error (LSB)")
    handles, labels = panel(0).get_legend_handles_labels()
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
