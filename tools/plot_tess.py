#!/usr/bin/env python3
"""Draws aerial-tess's CSV: max error (8-bit steps) against vertices, log-log, one panel per
scene, a line at 1 LSB.  The maxima are whole steps (GL images against the per-pixel
reference); 0 is drawn at 0.5 so that it stays on the log scale.  Each method's points are
joined in order of vertices (the sweep's fine search runs between coarse levels).
Usage: plot_tess.py tess.csv tess.png"""
import sys
import textwrap

from plot_common import first_seen, label_panel, panel_grid, read_rows


def main():
    rows = read_rows(sys.argv, "plot_tess.py tess.csv tess.png")
    if rows is None:
        return 2
    scenes = first_seen(rows, "scene")
    fig, panel = panel_grid(len(scenes), min(4, len(scenes)), 4, 3.2)
    styles = {"adaptive": "o-", "adaptive-relocate": "P-", "uniform-geodesic": "s--", "uniform-latlong": "^:",
              "uniform-grid": "s--", "uniform-distance-lod": "v:", "decimated": "d-.",
              "adaptive-decimating": "D-"}
    for i, scene in enumerate(scenes):
        ax = panel(i)
        for m in first_seen(rows, "method", scene=scene):
            pts = sorted((int(r["vertices"]), max(float(r["max_lsb"]), 0.5)) for r in rows
                         if r["scene"] == scene and r["method"] == m)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], styles.get(m, "x-"), label=m,
                    markersize=3)
        ax.axhline(1.0, color="grey", linewidth=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        label_panel(ax, scene, "vertices", "max error (LSB)")
        ax.legend(fontsize=6)
    face = rows[0].get("face_pixels", "?") if rows else "?"
    quick = rows and rows[0].get("quick") == "1"
    title = ("Max error of the drawn image against the per-pixel reference (8-bit steps) by "
             "vertex count; six cube faces of %s x %s pixels%s" %
             (face, face, " - QUICK RUN (subset, coarser grading)" if quick else ""))
    width = fig.get_size_inches()[0]
    fig.suptitle(textwrap.fill(title, max(40, int(width * 14))), fontsize=8)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
