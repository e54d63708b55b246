#!/usr/bin/env python3
"""Checks aerial-bench --stability's output: the CSV's shape and finiteness, and properties of
the data that can fail. Usage: check_stability.py DIR (holding stability.csv and stability.png).
Prints one line per failed check and exits 1 if any failed."""
import csv
import math
import os
import sys

HEADER = ("sweep,value,method,max_lsb,mean_lsb,over2,nonfinite,clamped,banding,popping,fails,"
          "worst_at,max_lsb_off_sun")
SWEEPS = ["sun_elevation_deg", "altitude_m", "distance_m", "mie_g", "turbidity", "visibility_m"]
METHODS = ["reference", "cpu-hp", "cpu-height", "arb-hp", "arb-hp-10bit", "arb-height",
           "arb-height-10bit", "gl-fog", "fg-fog", "lerp-screen-4deg", "lerp-world-1km"]
FLAGS = ["nonfinite", "clamped", "banding", "popping"]


def main():
    folder = sys.argv[1]
    failures = []

    def check(condition, message):
        if not condition:
            failures.append(message)

    path = os.path.join(folder, "stability.csv")
    with open(path) as f:
        header = f.readline().strip()
        check(header == HEADER, "header is %r, expected %r" % (header, HEADER))
        f.seek(0)
        rows = list(csv.DictReader(f))
    check(len(rows) > 0, "no rows")
    for i, r in enumerate(rows):
        where = "row %d (%s=%s %s)" % (i + 2, r.get("sweep"), r.get("value"), r.get("method"))
        for field in ["value", "mean_lsb", "over2"]:
            v = float(r[field])
            check(math.isfinite(v), "%s: %s is not finite" % (where, field))
        lsb = int(r["max_lsb"])
        check(0 <= lsb <= 255, "%s: max_lsb %d outside 0..255" % (where, lsb))
        check(float(r["mean_lsb"]) <= lsb, "%s: mean_lsb above max_lsb" % where)
        check(0 <= int(r["max_lsb_off_sun"]) <= lsb, "%s: max_lsb_off_sun outside 0..max_lsb" % where)
        flagged = lsb > 2 or any(int(r[k]) > 0 for k in FLAGS)
        check(int(r["fails"]) == int(flagged), "%s: fails is not (max_lsb > 2 or a flag)" % where)
        # The module never produces NaN or Inf.
        check(int(r["nonfinite"]) == 0, "%s: %s non-finite values" % (where, r["nonfinite"]))
        if r["method"] == "reference":
            check(lsb == 0 and not flagged, "%s: the reference against itself is not 0" % where)

    by = {}
    for r in rows:
        by.setdefault((r["sweep"], r["method"]), []).append(r)
    sweeps = []
    for r in rows:
        if r["sweep"] not in sweeps:
            sweeps.append(r["sweep"])
    check(sweeps == SWEEPS, "sweeps are %s, expected %s" % (sweeps, SWEEPS))
    for s in SWEEPS:
        count = len(by.get((s, "reference"), []))
        check(count >= 3, "%s: %d samples, expected at least 3" % (s, count))
        for m in METHODS:
            got = by.get((s, m), [])
            check(len(got) == count, "%s: %s has %d rows, reference %d" % (s, m, len(got), count))
            check([g["value"] for g in got] == [g["value"] for g in by.get((s, "reference"), [])],
                  "%s: %s is sampled at other values than reference" % (s, m))

    def worst(s, m, keep=lambda v: True):
        return max([int(r["max_lsb"]) for r in by.get((s, m), []) if keep(float(r["value"]))],
                   default=-1)

    for s in SWEEPS:
        # The ARB program computes the 2002 model in float: within 1 LSB of the CPU model.
        for a, b in zip(by.get((s, "cpu-hp"), []), by.get((s, "arb-hp"), [])):
            check(abs(int(a["max_lsb"]) - int(b["max_lsb"])) <= 1,
                  "%s=%s: arb-hp max %s LSB, cpu-hp %s: not within 1" %
                  (s, a["value"], b["max_lsb"], a["max_lsb"]))
        # Per-vertex scattering beats plain fog: the height model's worst error is below
        # gl-fog's in every sweep.
        check(worst(s, "cpu-height") < worst(s, "gl-fog"),
              "%s: cpu-height worst %d LSB is not below gl-fog's %d" %
              (s, worst(s, "cpu-height"), worst(s, "gl-fog")))
    # The 2002 model on its own ground: eye at 2 m, rays up to 1 km: within 2 LSB.
    near = worst("distance_m", "cpu-hp", lambda d: d <= 1000.0)
    check(0 <= near <= 2, "cpu-hp within 1 km: %d LSB, expected <= 2" % near)
    # Fog is not aerial perspective: gl-fog exceeds 2 LSB somewhere.
    check(max(worst(s, "gl-fog") for s in SWEEPS) > 2, "gl-fog never exceeds 2 LSB")
    # Interpolation across a narrow Mie peak fails: a 4-degree edge at g = 0.99.
    peak = by.get(("mie_g", "lerp-screen-4deg"), [])
    check(bool(peak) and float(peak[-1]["value"]) >= 0.98 and int(peak[-1]["max_lsb"]) > 2,
          "lerp-screen-4deg at the largest g does not exceed 2 LSB")

    png = os.path.join(folder, "stability.png")
    check(os.path.isfile(png) and os.path.getsize(png) > 1000, "%s missing or empty" % png)
    with open(png, "rb") as f:
        check(f.read(8) == b"\x89PNG\r\n\x1a\n", "%s is not a PNG" % png)

    for message in failures:
        print(message)
    print("%d rows, %d failed checks" % (len(rows), len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
