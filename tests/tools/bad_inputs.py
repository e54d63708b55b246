#!/usr/bin/env python3
"""Every tool, a table of bad inputs: exit status 2, nothing on stdout, exactly one line on
stderr that starts with "tool: " and names the offending flag, file, field or line, and no signal
(docs/conventions.md, Interfaces).

Usage: bad_inputs.py BIN_DIR [WORK_DIR]
Prints one line per case and "N passed, M failed"; exits 1 when a case fails.
"""
import os
import subprocess
import sys
import tempfile

# A valid scene for aerial-render (the cases change one thing in it).
SCENE = """{
  "camera": {"eye": [0, -500, 60], "look_at": [0, 500, 0], "up": [0, 0, 1],
             "fov_y_deg": 50, "near": 1, "far": 20000},
  "sun": {"elevation_deg": 40, "azimuth_deg": 20},
  "atmosphere": "hazy", "model": "hoffman-preetham",
  "display": {"exposure": 10, "tone": "clamp"}, "meters_per_unit": 1,
  "background": [0.5, 0.6, 0.8],
  "terrain": {"center": [0, 2000], "size": 8000, "resolution": 8, "height_amplitude": 50,
              "feature_size": 2000, "seed": 3, "texture_repeat": 200}
}"""

# Input files the cases refer to as {name}; written into WORK_DIR.
FILES = {
    "points_bad_line.csv": "1,2,3\n# comment\n4,5\n",
    "points_nan.csv": "1,2,3\nnan,0,0\n",
    "points_text.csv": "1,2,3\n\n7,eight,9\n",
    "atm_malformed.json": '{"rayleigh_scattering": [5.8e-6, 13.5e-6',
    "atm_negative.json": '{"rayleigh_scattering": [-5.8e-6, 13.5e-6, 33.1e-6]}',
    "atm_unknown.json": '{"ozone": 1e-6}',
    "atm_array.json": "[1, 2, 3]",
    "atm_nan_g.json": '{"mie_g": NaN}',
    "atm_g_out.json": '{"mie_g": 1.5}',
    "scene_malformed.json": '{"camera": ',
    "scene_unknown.json": SCENE[:-1] + ', "skybox": true}',
    "scene_negative_mpu.json": SCENE.replace('"meters_per_unit": 1', '"meters_per_unit": -1'),
    "not_a_png.png": "this is not a PNG\n",
    "empty.png": "",
}

E = "aerial-eval"
EV = ["--preset", "earth", "--eye", "0,0,100", "--sun", "0,0.5,1"]
R = "aerial-render"
S = "aerial-sample"


def with_atmosphere(name):
    """aerial-eval's arguments with the atmosphere file {dir}/NAME instead of a preset."""
    return ["--atmosphere", "{dir}/" + name, "--eye", "0,0,1", "--sun", "0,0,1"]


def rendering(scene, *more, backend="none"):
    """aerial-render's arguments: {dir}/SCENE drawn by BACKEND into {dir}/o.png, with MORE."""
    return ["--scene", "{dir}/" + scene, "--backend", backend, *more, "--out", "{dir}/o.png"]


# (tool, arguments, stdin, pieces the stderr line must contain). "{dir}" is WORK_DIR.
CASES = [
    # aerial-eval: flags
    (E, ["--frobnicate"], "", ["--frobnicate"]),
    (E, EV + ["--model", "fast"], "", ["--model", "fast"]),
    (E, ["--preset", "venus", "--eye", "0,0,100", "--sun", "0,0,1"], "", ["--preset", "venus"]),
    (E, ["--preset", "earth", "--eye", "nan,0,100", "--sun", "0,0,1"], "", ["--eye", "nan"]),
    (E, ["--preset", "earth", "--eye", "0,0,inf", "--sun", "0,0,1"], "", ["--eye", "inf"]),
    (E, ["--preset", "earth", "--eye", "0,0", "--sun", "0,0,1"], "", ["--eye"]),
    (E, ["--preset", "earth", "--eye", "0,0,1e999", "--sun", "0,0,1"], "", ["--eye"]),
    (E, ["--preset", "earth", "--eye", "0,0,100", "--sun", "0,0,0"], "", ["--sun"]),
    (E, ["--preset", "earth", "--eye", "0,0,100", "--sun", "0,NaN,1"], "", ["--sun"]),
    (E, EV + ["--up", "0,0,0"], "", ["--up"]),
    (E, ["--preset", "earth", "--sun", "0,0,1"], "", ["--eye"]),
    (E, ["--eye", "0,0,100", "--sun", "0,0,1"], "", ["--preset"]),
    (E, EV + ["--arb-height-fidelity", "2"], "", ["--arb-height-fidelity"]),
    # aerial-eval: files and lines
    (E, EV + ["--points", "{dir}/missing.csv"], "", ["--points", "missing.csv"]),
    (E, EV + ["--points", "{dir}/points_bad_line.csv"], "", ["points_bad_line.csv", "line 3"]),
    (E, EV + ["--points", "{dir}/points_nan.csv"], "", ["points_nan.csv", "line 2"]),
    (E, EV + ["--points", "{dir}/points_text.csv"], "", ["points_text.csv", "line 3", "eight"]),
    (E, EV, "1,2,3\n1,2,3,4\n", ["line 2"]),
    (E, EV, "0,0,-inf\n", ["line 1"]),
    (E, with_atmosphere("missing.json"), "", ["--atmosphere", "missing.json"]),
    (E, with_atmosphere("atm_malformed.json"), "", ["--atmosphere", "atm_malformed.json"]),
    (E, with_atmosphere("atm_negative.json"), "", ["rayleigh_scattering"]),
    (E, with_atmosphere("atm_unknown.json"), "", ["ozone"]),
    (E, with_atmosphere("atm_array.json"), "", ["--atmosphere", "atm_array.json"]),
    (E, with_atmosphere("atm_nan_g.json"), "", ["--atmosphere", "atm_nan_g.json"]),
    (E, with_atmosphere("atm_g_out.json"), "", ["mie_g"]),
    # aerial-render
    (R, ["--bogus"], "", ["--bogus"]),
    (R, rendering("missing.json"), "", ["--scene", "missing.json"]),
    (R, rendering("scene_malformed.json"), "", ["--scene", "scene_malformed.json"]),
    (R, rendering("scene_unknown.json"), "", ["skybox"]),
    (R, rendering("scene_negative_mpu.json"), "", ["meters_per_unit"]),
    (R, rendering("scene_unknown.json", backend="d3d"), "", ["--backend", "d3d"]),
    (R, rendering("scene_unknown.json", "--size", "0x5"), "", ["--size"]),
    (R, rendering("scene_unknown.json", "--gl", "glx"), "", ["--gl", "glx"]),
    # aerial-compare
    ("aerial-compare", ["{dir}/missing.png", "{dir}/missing.png"], "", ["missing.png"]),
    ("aerial-compare", ["{dir}/not_a_png.png", "{dir}/not_a_png.png"], "", ["not_a_png.png"]),
    ("aerial-compare", ["{dir}/empty.png", "{dir}/empty.png"], "", ["empty.png"]),
    ("aerial-compare", ["{dir}/a.png"], "", ["B"]),
    ("aerial-compare", ["--nope", "x", "y"], "", ["--nope"]),
    # aerial-bench
    ("aerial-bench", ["--cpu-throughput", "--vertices", "-5"], "", ["--vertices"]),
    ("aerial-bench", ["--cpu-throughput", "--vertices", "many"], "", ["--vertices"]),
    ("aerial-bench", ["--cpu-throughput", "--repetitions", "0"], "", ["--repetitions"]),
    ("aerial-bench", ["--cpu-throughput", "--preset", "venus"], "", ["--preset", "venus"]),
    ("aerial-bench", ["--cpu-throughput", "--model", "reference"], "", ["--model"]),
    ("aerial-bench", ["--warp"], "", ["--warp"]),
    # aerial-sky-table
    ("aerial-sky-table", ["--dome", "0x8"], "", ["--dome"]),
    ("aerial-sky-table", ["--elevations", "45,nan"], "", ["--elevations", "nan"]),
    ("aerial-sky-table", ["--eye-altitude", "-5"], "", ["--eye-altitude"]),
    ("aerial-sky-table", ["--eye-altitude", "nan"], "", ["--eye-altitude"]),
    ("aerial-sky-table", ["--cubemap", "-1"], "", ["--cubemap"]),
    ("aerial-sky-table", ["--probe", "x"], "", ["--probe"]),
    ("aerial-sky-table", ["--atmosphere", "{dir}/missing.json"], "",
     ["--atmosphere", "missing.json"]),
    ("aerial-sky-table", ["--atmosphere", "{dir}/atm_malformed.json"], "",
     ["--atmosphere", "atm_malformed.json"]),
    ("aerial-sky-table", ["--atmosphere", "{dir}/atm_negative.json"], "",
     ["rayleigh_scattering"]),
    ("aerial-sky-table", ["--gl", "glx"], "", ["--gl", "glx"]),
    ("aerial-sky-table", ["--gl-stride", "0"], "", ["--gl-stride"]),
    ("aerial-sky-table", ["--panorama-size", "10", "--panorama", "{dir}/p.png"], "",
     ["--panorama-size"]),
    # aerial-tess
    ("aerial-tess", ["--frames", "0", "--bench-update"], "", ["--frames"]),
    ("aerial-tess", ["--frames", "ten", "--bench-update"], "", ["--frames"]),
    ("aerial-tess", [], "", ["--out"]),
    ("aerial-tess", ["--fast"], "", ["--fast"]),
    # aerial-sample and aerial-scene-bench
    (S, ["--size", "0x90"], "", ["--size"]),
    (S, ["--frames", "-3"], "", ["--frames"]),
    (S, ["--error-target", "nan"], "", ["--error-target"]),
    (S, ["--error-target", "-1"], "", ["--error-target"]),
    (S, ["--latitude", "nan"], "", ["--latitude"]),
    (S, ["--seed", "-1"], "", ["--seed"]),
    (S, ["--soak", "0"], "", ["--soak"]),
    (S, ["--soak", "many"], "", ["--soak"]),
    (S, ["--soak", "100", "--window"], "", ["--soak"]),
    (S, ["--unknown"], "", ["--unknown"]),
    (S, ["--tile-resolution", "1"], "", ["--tile-resolution"]),
    (S, ["--tess-budget", "-1"], "", ["--tess-budget"]),
    (S, ["--tile-resolution", "1e3"], "", ["--tile-resolution"]),
    (S, ["--cube-size", "0"], "", ["--cube-size"]),
    ("aerial-scene-bench", ["--frames", "1"], "", ["--frames"]),
    ("aerial-scene-bench", ["--size", "axb"], "", ["--size"]),
    ("aerial-scene-bench", ["--model", "fast"], "", ["--model"]),
    ("aerial-scene-bench", ["--what"], "", ["--what"]),
]


def check(bin_dir, work_dir, tool, args, stdin, expected):
    """Runs one case; returns None when it behaves, else what is wrong."""
    binary = os.path.join(bin_dir, tool)
    if not os.access(binary, os.X_OK):
        return "no executable %s" % binary
    args = [a.replace("{dir}", work_dir) for a in args]
    env = dict(os.environ, LP_NUM_THREADS="1")
    try:
        run = subprocess.run([binary] + args, input=stdin.encode(), capture_output=True,
                             cwd=work_dir, env=env, timeout=120)
    except subprocess.TimeoutExpired:
        return "timed out after 120 s"
    err = run.stderr.decode(errors="replace")
    lines = err.splitlines()
    if run.returncode < 0:
        return "killed by signal %d; stderr: %r" % (-run.returncode, err[:300])
    if run.returncode != 2:
        return "exit status %d, expected 2; stderr: %r" % (run.returncode, err[:300])
    if run.stdout:
        return "wrote to stdout: %r" % run.stdout[:200]
    if len(lines) != 1 or not err.endswith("\n"):
        return "expected exactly one stderr line, got %d: %r" % (len(lines), err[:300])
    if not lines[0].startswith(tool + ": "):
        return "stderr line does not start with %r: %r" % (tool + ": ", lines[0])
    missing = [p.replace("{dir}", work_dir) for p in expected
               if p.replace("{dir}", work_dir) not in lines[0]]
    if missing:
        return "stderr line does not name %r: %r" % (missing, lines[0])
    return None


def main():
    args = sys.argv[1:]
    skipped_tools = set()
    while args and args[0] == "--not-built":
        if len(args) < 2:
            sys.stderr.write("bad_inputs.py: --not-built needs a tool name\n")
            return 2
        skipped_tools.add(args[1])
        args = args[2:]
    if len(args) not in (1, 2):
        sys.stderr.write("usage: bad_inputs.py [--not-built TOOL]... BIN_DIR [WORK_DIR]\n")
        return 2
    known = set(tool for tool, _, _, _ in CASES)
    if not skipped_tools <= known:
        sys.stderr.write("bad_inputs.py: --not-built: unknown tool %s\n" %
                         ", ".join(sorted(skipped_tools - known)))
        return 2
    bin_dir = os.path.abspath(args[0])
    work_dir = os.path.abspath(args[1]) if len(args) == 2 else tempfile.mkdtemp(
        prefix="bad_inputs.")
    os.makedirs(work_dir, exist_ok=True)
    for name, text in FILES.items():
        with open(os.path.join(work_dir, name), "w") as f:
            f.write(text)
    passed = failed = skipped = 0
    for tool, args, stdin, expected in CASES:
        if tool in skipped_tools:
            skipped += 1
            continue
        what = check(bin_dir, work_dir, tool, args, stdin, expected)
        label = "%s %s" % (tool, " ".join(args).replace("{dir}/", ""))
        if what is None:
            passed += 1
            print("ok   %s" % label)
        else:
            failed += 1
            print("FAIL %s: %s" % (label, what))
    print("%d passed, %d failed" % (passed, failed))
    if skipped:
        print("%d cases of %s not run: not built in this build" %
              (skipped, ", ".join(sorted(skipped_tools))))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
