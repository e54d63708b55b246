#!/usr/bin/env python3
"""Checks an aerial-bench --out directory: the CSV header, at least one row for every (scene,
method) with finite, non-negative figures and a positive vertex count, and the charts.
Usage: check_bench_csv.py DIR METHOD[,METHOD...] SCENE[,SCENE...]"""
import csv
import math
import os
import sys

HEADER = ("scene,method,tessellation,vertices,ms_per_frame,max_lsb,p99_lsb,rmse_lsb,"
          "de2000_mean")


def main():
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    out, methods, scenes = sys.argv[1], sys.argv[2].split(","), sys.argv[3].split(",")
    path = os.path.join(out, "bench.csv")
    with open(path) as f:
        header = f.readline().rstrip("\n")
        if header != HEADER:
            print("%s: header is %r, expected %r" % (path, header, HEADER))
            return 1
        rows = list(csv.DictReader(f, fieldnames=HEADER.split(",")))
    problems = []
    for r in rows:
        if r["tessellation"] not in ("uniform", "adaptive"):
            problems.append("bad tessellation %r" % r["tessellation"])
        if int(r["vertices"]) <= 0:
            problems.append("%s %s: no vertices" % (r["scene"], r["method"]))
        for key in ("ms_per_frame", "max_lsb", "p99_lsb", "rmse_lsb", "de2000_mean"):
            v = float(r[key])
            if not math.isfinite(v) or v < 0:
                problems.append("%s %s: %s = %s" % (r["scene"], r["method"], key, r[key]))
        if float(r["ms_per_frame"]) <= 0:
            problems.append("%s %s: ms_per_frame not positive" % (r["scene"], r["method"]))
    for s in scenes:
        for m in methods:
            if not any(r["scene"] == s and r["method"] == m for r in rows):
                problems.append("no row for scene %s, method %s" % (s, m))
        chart = os.path.join(out, "pareto-%s.png" % s)
        if not os.path.exists(chart) or os.path.getsize(chart) == 0:
            problems.append("missing or empty %s" % chart)
    extra = {r["scene"] for r in rows} - set(scenes)
    if extra:
        problems.append("unexpected scenes %s" % sorted(extra))
    overview = os.path.join(out, "pareto.png")
    if not os.path.exists(overview) or os.path.getsize(overview) == 0:
        problems.append("missing or empty %s" % overview)
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
