#!/usr/bin/env python3
"""Independent single-scattering integrator, the oracle for aerial-eval's `single-scattering` model.

Pure Python 3, standard library only. It implements docs/conventions.md (Physics) from scratch and
shares no code and no numerical scheme with module/src/core/reference.cpp (which steps adaptively
with 4-point Gauss-Legendre):

  * geometry: a spherical planet of radius R centred at -R * up; sea level is altitude 0;
  * densities: exp(-h / H) for Rayleigh and for Mie; for ozone a tent, 1 at
    ozone_center_altitude_m falling linearly to 0 at ozone_center_altitude_m +- ozone_width_m / 2
    and 0 beyond; all zero above the atmosphere radius, and altitudes below
    max(-5000 m, -40 H_min) count as that floor (the module's min_density_altitude_m);
  * extinction: beta_R rho_R + (beta_M,sc + beta_M,abs) rho_M + beta_O3 rho_O3; ozone only
    absorbs: it is in every optical depth (eye to sample, eye to vertex, sample or vertex to the
    sun) and in no source term;
  * phases: Rayleigh 3/(16 pi) (1 + cos^2), normalised Henyey-Greenstein with g > 0 forwards,
    cos_theta = dot(normalize(vertex - eye), sun_dir);
  * F_ex = exp(-tau(eye, vertex));
    L_in = E_sun0 * integral_0^s sum_i beta_sc_i rho_i(t) P_i(theta) T_sun(x(t))
                    * exp(-tau(eye, x(t))) dt,  i in {Rayleigh, Mie};
    T_sun(x) = exp(-optical depth from x to the atmosphere top along sun_dir), 0 when the planet
    blocks the sun; esun = E_sun0 * T_sun(vertex).
  * It computes single scattering only: no light scattered more than once and no light reflected
    by the ground. `ground_albedo` is therefore accepted (and range-checked) but unused. The
    `reference` model adds both and is refused here.

Numerical scheme: every ray (the view segment, clipped to the atmosphere, and each sun ray) is
first split where its integrand has a kink or a jump: where it crosses the altitudes of the ozone
tent's corners (centre and centre +- width / 2) and the density floor (found in closed form, the
roots of |origin + t dir| = R + h), and, for the view ray, where it enters or leaves the planet's
shadow (T_sun jumps there; also in closed form). Each piece is then cut into a FIXED number of
EQUAL steps, chosen once per piece so that a step spans at most 1/STEPS_PER_SCALE_HEIGHT of the
smallest scale height and at most 1/STEPS_PER_SCALE_HEIGHT of an optical depth at the piece's
densest point; the integrals are composite Simpson. Inside a piece every density is smooth, so
Simpson keeps its fourth order across the ozone layer. Along the view ray the optical depth from
the eye is accumulated node by node, each step by Simpson's rule on its own midpoint. At the
default step count every value of the --compare cases is within 5e-7 (relative) of a run with six
times the steps (`--compare` checks the change on doubling against 1e-4), and vertical rays match
their closed forms, ozone included, to 1e-9 for F_ex and E_sun and about 1e-6 for L_in, falling
16-fold per doubling of the steps. Without the splits at the ozone tent's corners, the dense low
layer of the --compare cases would be off by up to 1e-5.

Usage:
  check_reference.py (--preset earth | --atmosphere FILE.json) --eye=X,Y,Z --sun=X,Y,Z
                     [--model single-scattering] [--up=X,Y,Z] [--points FILE] [--steps-scale K]
      reads points x,y,z (blank lines and # comments ignored) from --points or stdin and prints
      the CSV of aerial-eval: x,y,z,fex_r,fex_g,fex_b,lin_r,lin_g,lin_b,esun_r,esun_g,esun_b.
      The atmosphere JSON takes the fields of docs/conventions.md (Interfaces): missing fields
      keep the `earth` values, except mie_absorption, ozone_absorption and ground_albedo (a
      number or [3]), which are 0 when missing; unknown fields are refused. --model
      single-scattering is the only model computed (and the default); --model reference is
      refused, since it includes multiple scattering.
  check_reference.py --compare BIN/aerial-eval
      runs `aerial-eval --preset earth --eye=0,0,100 --sun=0,0.6,0.8 --model single-scattering` on
      a fixed set of points (and more views: a low sun, a sun below the horizon whose shadow the
      view rays cross, and an atmosphere file with a dense, low ozone layer and a ground albedo,
      whose corners the view rays cross), prints a table (point, channel, aerial-eval,
      independent, relative error) and the largest relative error of each column, and exits 1 if
      any relative error exceeds 1 %. It also reruns the independent integration with twice the
      steps and fails if that changes anything by more than 1e-4 (the independent side must be
      converged well below the tolerance it checks), if it misses the closed forms of vertical
      rays by more than that, or if leaving the ozone out would change no value by more than
      the tolerance (the cases must be able to see the ozone).
Exit status: 0 on success, 1 on disagreement, 2 on bad input.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

TOOL = "check_reference.py"
HEADER = "x,y,z,fex_r,fex_g,fex_b,lin_r,lin_g,lin_b,esun_r,esun_g,esun_b"

# docs/conventions.md, Physics: preset `earth` (the C++ `earth` preset, ozone and ground included).
EARTH = {
    "rayleigh_scattering": [5.802e-6, 13.558e-6, 33.1e-6],
    "mie_scattering": [3.996e-6, 3.996e-6, 3.996e-6],
    "mie_absorption": [0.0, 0.0, 0.0],
    "mie_g": 0.8,
    "rayleigh_scale_height_m": 8000.0,
    "mie_scale_height_m": 1200.0,
    "ozone_absorption": [0.650e-6, 1.881e-6, 0.085e-6],
    "ozone_center_altitude_m": 25000.0,
    "ozone_width_m": 30000.0,
    "planet_radius_m": 6360e3,
    "atmosphere_radius_m": 6420e3,
    "ground_albedo": [0.1, 0.1, 0.1],
    "sun_irradiance": [1.0, 1.0, 1.0],
}
VECTOR_FIELDS = ("rayleigh_scattering", "mie_scattering", "mie_absorption", "ozone_absorption",
                 "ground_albedo", "sun_irradiance")
# Fields that may also be one number for every channel.
GREY_FIELDS = ("ground_albedo",)
# An atmosphere file leaves these at 0 when it does not give them (the absorbers and the ground);
# every other missing field keeps its `earth` value.
ZERO_WHEN_MISSING = ("mie_absorption", "ozone_absorption", "ground_albedo")
# Ranges of the ozone layer's centre and width, m (docs/conventions.md, Interfaces).
OZONE_CENTER_RANGE_M = (0.0, 1e6)
OZONE_WIDTH_RANGE_M = (1.0, 1e6)

MODEL = "single-scattering"

# Altitudes below max(MIN_ALTITUDE_M, -MIN_ALTITUDE_SCALE_HEIGHTS * smallest scale height) count as
# that floor for density (docs: scattering.hpp, kMinAltitudeM and Frame::min_altitude_m).
MIN_ALTITUDE_M = -5000.0
MIN_ALTITUDE_SCALE_HEIGHTS = 40.0
# Steps per smallest scale height (and per unit of optical depth) on every ray. 8 is converged
# to a few 1e-7 for earth (see the module docstring); --steps-scale multiplies it for
# convergence studies.
STEPS_PER_SCALE_HEIGHT = 8.0
MIN_STEPS = 16
MAX_STEPS = 200000

# --compare: tolerance against aerial-eval, and convergence demanded of this integrator.
COMPARE_TOLERANCE = 0.01
CONVERGENCE_TOLERANCE = 1e-4
# Values below this are compared in absolute terms (a shadowed E_sun is exactly 0 on both sides).
COMPARE_FLOOR = 1e-12
# An atmosphere file for --compare: a dense ozone layer low enough that the view rays cross its
# corners (-1000, 3000 and 7000 m; a quarter of the peak density at sea level), and a ground
# albedo, which single scattering must ignore on both sides.
LOW_OZONE = {
    "ozone_absorption": [2.0e-5, 3.0e-5, 1.0e-5],
    "ozone_center_altitude_m": 3000.0,
    "ozone_width_m": 8000.0,
    "ground_albedo": 0.3,
}
# (atmosphere, eye, sun, [(point, label)]), metres, up = +Z; atmosphere None is the preset earth,
# otherwise the fields of an atmosphere file. The first case is the one named in the tool's
# contract: 1, 10 and 50 km away, towards and away from the sun's azimuth, across it, slightly up
# and down, straight at the sun, up to 10 km altitude and up through earth's ozone layer. The
# others add a low sun (long, grazing sun paths through the ozone layer), a sun below the
# horizon, whose shadow the view rays cross, and the dense low ozone layer.
COMPARE_CASES = [
    (None, (0.0, 0.0, 100.0), (0.0, 0.6, 0.8), [
        ((0.0, 1000.0, 100.0), "1 km level, towards the sun's azimuth"),
        ((0.0, 10000.0, 100.0), "10 km level, towards the sun's azimuth"),
        ((0.0, 50000.0, 100.0), "50 km level, towards the sun's azimuth"),
        ((0.0, -1000.0, 100.0), "1 km level, away from the sun"),
        ((0.0, -10000.0, 100.0), "10 km level, away from the sun"),
        ((0.0, -50000.0, 100.0), "50 km level, away from the sun"),
        ((10000.0, 0.0, 100.0), "10 km level, across the sun"),
        ((0.0, 10000.0, 600.0), "10 km, slightly up (2.9 deg)"),
        ((0.0, 10000.0, 0.0), "10 km, slightly down to sea level"),
        ((-7000.0, -7000.0, 0.0), "9.9 km, slightly down, away from the sun"),
        ((0.0, 6000.0, 8100.0), "10 km straight at the sun (Mie peak)"),
        ((0.0, 20000.0, 10000.0), "22 km, up to 10 km altitude"),
        ((-30000.0, 0.0, 10000.0), "31.6 km across, up to 10 km altitude"),
        ((0.0, -40000.0, 45000.0), "60 km, up through the whole ozone layer (45 km altitude)"),
    ]),
    (None, (0.0, 0.0, 100.0), (0.995, 0.0, 0.0998), [
        ((30000.0, 0.0, 100.0), "low sun (5.7 deg): 30 km level, towards it"),
        ((0.0, 30000.0, 3000.0), "low sun: 30 km across, up to 3 km altitude"),
        ((-20000.0, 0.0, 30000.0), "low sun: 36 km, up to 30 km altitude, away from it"),
    ]),
    (None, (0.0, 0.0, 20000.0), (1.0, 0.0, -0.02), [
        ((0.0, 10000.0, 100.0), "sun 1.1 deg below the horizon: down into the shadow"),
        ((20000.0, 0.0, 1000.0), "sun below: down towards it, still lit at the end"),
        ((-20000.0, 0.0, 1000.0), "sun below: down away from it, into the shadow"),
    ]),
    (LOW_OZONE, (0.0, 0.0, 100.0), (0.8, 0.0, 0.6), [
        ((0.0, 20000.0, 100.0), "low ozone layer: 20 km level, inside it"),
        ((0.0, 15000.0, 5000.0), "low ozone layer: 15.8 km, up through its peak"),
        ((30000.0, 0.0, 9000.0), "low ozone layer: 31 km, up through all of it, towards the sun"),
        ((-20000.0, 5000.0, 3000.0), "low ozone layer: 20.8 km, up to its peak, away from the sun"),
    ]),
]


class BadInput(Exception):
    """One line naming the offending flag, field or line."""


# ---- small vector helpers (tuples of three floats) -------------------------------------------


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(a, k):
    return (a[0] * k, a[1] * k, a[2] * k)


def norm(a):
    return math.sqrt(dot(a, a))


# ---- input -----------------------------------------------------------------------------------


def parse_number(text, where):
    try:
        value = float(text)
    except ValueError:
        raise BadInput(f"{where}: expected a finite number, got '{text.strip()}'") from None
    if not math.isfinite(value):
        raise BadInput(f"{where}: expected a finite number, got '{text.strip()}'")
    return value


def parse_vec3(text, where):
    parts = text.split(",")
    if len(parts) != 3:
        raise BadInput(f"{where}: expected three finite numbers X,Y,Z, got '{text}'")
    return tuple(parse_number(p, where) for p in parts)


def parse_direction(text, where):
    v = parse_vec3(text, where)
    length = norm(v)
    if not length > 1e-12:
        raise BadInput(f"{where}: expected a non-zero direction, got '{text}'")
    return scale(v, 1.0 / length)


def parse_points(text, source):
    points = []
    for number, line in enumerate(text.split("\n"), start=1):
        line = line.split("#", 1)[0].strip()
        if line:
            points.append(parse_vec3(line, f"{source} line {number}"))
    return points


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def load_atmosphere(path):
    try:
        with open(path, encoding="utf-8") as f:
            root = json.load(f)
    except OSError as e:
        raise BadInput(f"--atmosphere {path}: cannot read ({e.strerror})") from None
    except ValueError as e:
        raise BadInput(f"--atmosphere {path}: malformed JSON ({e})") from None
    if not isinstance(root, dict):
        raise BadInput(f"--atmosphere {path}: expected a JSON object")
    atmosphere = load_earth()
    for key in ZERO_WHEN_MISSING:
        atmosphere[key] = [0.0, 0.0, 0.0]
    for key, value in root.items():
        if key not in EARTH:
            raise BadInput(f"--atmosphere {path}: {key} is not an atmosphere field")
        if key in GREY_FIELDS and is_number(value):
            value = [value, value, value]
        if key in VECTOR_FIELDS:
            ok = isinstance(value, list) and len(value) == 3 and all(is_number(v) for v in value)
        else:
            ok = is_number(value)
        if not ok:
            raise BadInput(f"--atmosphere {path}: {key} has the wrong type: {json.dumps(value)}")
        atmosphere[key] = [float(v) for v in value] if key in VECTOR_FIELDS else float(value)
    a = atmosphere
    for key in VECTOR_FIELDS:
        for c, v in enumerate(a[key]):
            if not (math.isfinite(v) and v >= 0.0):
                raise BadInput(f"--atmosphere {path}: {key}[{c}] must be finite and >= 0")
    for c, v in enumerate(a["ground_albedo"]):
        if not v <= 1.0:
            raise BadInput(f"--atmosphere {path}: ground_albedo[{c}] must be in [0, 1]")
    if not abs(a["mie_g"]) < 1.0:
        raise BadInput(f"--atmosphere {path}: mie_g must satisfy |g| < 1")
    for key in ("rayleigh_scale_height_m", "mie_scale_height_m", "planet_radius_m"):
        if not (math.isfinite(a[key]) and a[key] > 0.0):
            raise BadInput(f"--atmosphere {path}: {key} must be finite and > 0")
    for key, (lo, hi) in (("ozone_center_altitude_m", OZONE_CENTER_RANGE_M),
                          ("ozone_width_m", OZONE_WIDTH_RANGE_M)):
        if not lo <= a[key] <= hi:
            raise BadInput(f"--atmosphere {path}: {key} must be in [{lo:.10g}, {hi:.10g}] m")
    if not (math.isfinite(a["atmosphere_radius_m"])
            and a["atmosphere_radius_m"] > a["planet_radius_m"]):
        raise BadInput(f"--atmosphere {path}: atmosphere_radius_m must be above planet_radius_m")
    return a


# ---- physics ---------------------------------------------------------------------------------


def rayleigh_phase(cos_theta):
    return 3.0 / (16.0 * math.pi) * (1.0 + cos_theta * cos_theta)


def henyey_greenstein_phase(cos_theta, g):
    return (1.0 - g * g) / (4.0 * math.pi * (1.0 + g * g - 2.0 * g * cos_theta) ** 1.5)


def step_count(length, densest_extinction, scale_height, steps_scale):
    """Even number of equal Simpson steps for a ray of `length` metres."""
    per_metre = STEPS_PER_SCALE_HEIGHT * steps_scale * max(1.0 / scale_height, densest_extinction)
    n = max(MIN_STEPS, min(MAX_STEPS, math.ceil(length * per_metre)))
    return n + (n % 2)


def sphere_interval(origin, direction, radius):
    """(t0, t1) of origin + t direction (unit) inside the sphere of `radius` about the frame
    origin, or None when the line misses it."""
    b = dot(origin, direction)
    disc = b * b - (dot(origin, origin) - radius * radius)
    if disc < 0.0:
        return None
    root = math.sqrt(disc)
    return (-b - root, -b + root)


class Integrator:
    """Single scattering in one atmosphere; positions are relative to the planet centre."""

    def __init__(self, atmosphere, steps_scale=1.0):
        a = atmosphere
        self.beta_r = list(a["rayleigh_scattering"])
        self.beta_m_sc = list(a["mie_scattering"])
        self.beta_m_ex = [s + k for s, k in zip(a["mie_scattering"], a["mie_absorption"])]
        self.beta_o = list(a["ozone_absorption"])
        self.g = a["mie_g"]
        self.h_r = a["rayleigh_scale_height_m"]
        self.h_m = a["mie_scale_height_m"]
        self.o_center = a["ozone_center_altitude_m"]
        self.o_half_width = 0.5 * a["ozone_width_m"]
        self.radius = a["planet_radius_m"]
        self.top = a["atmosphere_radius_m"]
        self.e_sun0 = list(a["sun_irradiance"])
        self.steps_scale = steps_scale
        self.floor = max(MIN_ALTITUDE_M, -MIN_ALTITUDE_SCALE_HEIGHTS * min(self.h_r, self.h_m))
        # Altitudes where a density has a kink: the floor, and the ozone tent's three corners
        # (those above the floor, below which nothing varies). Rays are split where they cross
        # them.
        corners = [self.o_center + k * self.o_half_width for k in (-1.0, 0.0, 1.0)]
        self.kink_radii = [self.radius + h for h in [self.floor, *corners]
                           if h >= self.floor and 0.0 < self.radius + h < self.top]

    def ozone_density(self, h):
        """The tent: 1 at the centre, 0 at centre +- width / 2 and beyond."""
        return max(0.0, 1.0 - abs(h - self.o_center) / self.o_half_width)

    def densities(self, r):
        """Relative Rayleigh, Mie (1 at sea level) and ozone (1 at the layer's peak) densities at
        distance r from the centre. Callers integrate only over rays clipped to the atmosphere
        sphere, so the truncation at its top is the end of the interval, not a jump inside it
        (a node that rounding puts a nanometre above the top still counts)."""
        h = max(r - self.radius, self.floor)
        return math.exp(-h / self.h_r), math.exp(-h / self.h_m), self.ozone_density(h)

    def densest_extinction(self, origin, direction, t0, t1):
        """An upper bound of the extinction (1/m, any channel) on the ray segment: Rayleigh and
        Mie at its lowest point, ozone at its densest altitude on the segment."""
        t_low = min(max(-dot(origin, direction), t0), t1)
        h_low = norm(add(origin, scale(direction, t_low))) - self.radius
        h_high = max(norm(add(origin, scale(direction, t))) for t in (t0, t1)) - self.radius
        rho_r, rho_m, _ = self.densities(self.radius + h_low)
        rho_o = self.ozone_density(min(max(self.o_center, max(h_low, self.floor)),
                                       max(h_high, self.floor)))
        return max(max(self.beta_r) * rho_r + max(self.beta_m_ex) * rho_m
                   + max(self.beta_o) * rho_o, 0.0)

    def kink_crossings(self, origin, direction, t0, t1):
        """Parameters in (t0, t1) where origin + t direction (unit) crosses one of the kink
        altitudes: roots of |origin + t direction|^2 = r_k^2, in closed form."""
        b = dot(origin, direction)
        c = dot(origin, origin)
        crossings = []
        for r_k in self.kink_radii:
            disc = b * b - (c - r_k * r_k)
            if disc <= 0.0:
                continue  # missed, or touched tangentially: no kink crossed
            root = math.sqrt(disc)
            crossings.extend(t for t in (-b - root, -b + root) if t0 < t < t1)
        return crossings

    def column(self, origin, direction, t0, t1):
        """Integrals of the Rayleigh, Mie and ozone densities (m) along origin + t direction,
        t0..t1: split at the kink altitudes, composite Simpson with equal steps on each piece."""
        if not t1 - t0 > 0.0:
            return 0.0, 0.0, 0.0
        b = dot(origin, direction)
        c = dot(origin, origin)
        bounds = sorted([t0, *self.kink_crossings(origin, direction, t0, t1), t1])
        sum_r = sum_m = sum_o = 0.0
        for a, z in zip(bounds, bounds[1:]):
            if not z > a:
                continue
            n = step_count(z - a, self.densest_extinction(origin, direction, a, z),
                           min(self.h_r, self.h_m), self.steps_scale)
            dt = (z - a) / n
            piece_r = piece_m = piece_o = 0.0
            for i in range(n + 1):
                t = a + i * dt
                rho_r, rho_m, rho_o = self.densities(math.sqrt(max(c + t * (2.0 * b + t), 0.0)))
                w = 1.0 if i == 0 or i == n else (4.0 if i % 2 else 2.0)
                piece_r += w * rho_r
                piece_m += w * rho_m
                piece_o += w * rho_o
            sum_r += piece_r * dt / 3.0
            sum_m += piece_m * dt / 3.0
            sum_o += piece_o * dt / 3.0
        return sum_r, sum_m, sum_o

    def optical_depth(self, ch, col_r, col_m, col_o):
        return self.beta_r[ch] * col_r + self.beta_m_ex[ch] * col_m + self.beta_o[ch] * col_o

    def in_shadow(self, x, sun):
        """Whether the planet is between x (relative to the centre) and the sun; points below
        sea level are shadowed as if they were on the surface."""
        r = norm(x)
        mu = dot(x, sun) / r if r > 0.0 else -1.0
        if mu >= 0.0:
            return False
        return r <= self.radius or r * math.sqrt(max(0.0, 1.0 - mu * mu)) < self.radius

    def sun_transmittance(self, x, sun, lit=None):
        """T_sun per channel at x (relative to the centre). `lit` overrides the shadow test
        (True: the limit from the sunlit side, used on the shadow boundary itself)."""
        if lit is None:
            lit = not self.in_shadow(x, sun)
        if not lit:
            return [0.0, 0.0, 0.0]
        interval = sphere_interval(x, sun, self.top)
        if interval is None or interval[1] <= 0.0:
            return [1.0, 1.0, 1.0]
        cols = self.column(x, sun, max(interval[0], 0.0), interval[1])
        return [math.exp(-self.optical_depth(ch, *cols)) for ch in range(3)]

    def shadow_crossings(self, origin, direction, sun, t0, t1):
        """Parameters in (t0, t1) where origin + t direction crosses the boundary of the planet's
        shadow (the cylinder of the planet radius about the centre, on the night side). T_sun
        jumps there, so the integration is split at them to keep Simpson's order."""
        o = sub(origin, scale(sun, dot(origin, sun)))
        v = sub(direction, scale(sun, dot(direction, sun)))
        a = dot(v, v)
        if a <= 0.0:
            return []
        half_b = dot(o, v)
        disc = half_b * half_b - a * (dot(o, o) - self.radius * self.radius)
        if disc <= 0.0:
            return []
        root = math.sqrt(disc)
        crossings = []
        for t in ((-half_b - root) / a, (-half_b + root) / a):
            if t0 < t < t1 and dot(add(origin, scale(direction, t)), sun) < 0.0:
                crossings.append(t)
        return crossings

    def scatter(self, eye, vertex, sun, up):
        """(F_ex, L_in, E_sun) per channel for world positions in metres."""
        offset = scale(up, self.radius)
        eye_c = add(eye, offset)
        vertex_c = add(vertex, offset)
        e_sun = [e * t for e, t in zip(self.e_sun0, self.sun_transmittance(vertex_c, sun))]
        segment = sub(vertex_c, eye_c)
        s = norm(segment)
        if not s > 0.0:
            return [1.0, 1.0, 1.0], [0.0, 0.0, 0.0], e_sun
        d = scale(segment, 1.0 / s)
        cos_theta = dot(d, sun)
        p_r = rayleigh_phase(cos_theta)
        p_m = henyey_greenstein_phase(cos_theta, self.g)
        interval = sphere_interval(eye_c, d, self.top)
        t0 = 0.0 if interval is None else max(interval[0], 0.0)
        t1 = 0.0 if interval is None else min(interval[1], s)
        if not t1 > t0:
            return [1.0, 1.0, 1.0], [0.0, 0.0, 0.0], e_sun

        b = dot(eye_c, d)
        c = dot(eye_c, eye_c)

        def rho(t):
            return self.densities(math.sqrt(max(c + t * (2.0 * b + t), 0.0)))

        col = [0.0, 0.0, 0.0]  # Rayleigh, Mie and ozone density columns from the eye, m
        radiance = [0.0, 0.0, 0.0]  # in-scattered radiance per unit E_sun0
        bounds = sorted([t0, *self.shadow_crossings(eye_c, d, sun, t0, t1),
                         *self.kink_crossings(eye_c, d, t0, t1), t1])
        for a, z in zip(bounds, bounds[1:]):
            if not z > a:
                continue
            lit = not self.in_shadow(add(eye_c, scale(d, 0.5 * (a + z))), sun)
            n = step_count(z - a, self.densest_extinction(eye_c, d, a, z),
                           min(self.h_r, self.h_m), self.steps_scale)
            dt = (z - a) / n
            piece = [0.0, 0.0, 0.0]  # Simpson sum of the in-scattering integrand on [a, z]
            here = rho(a)
            for i in range(n + 1):
                t = a + i * dt
                if i > 0:
                    mid = rho(t - 0.5 * dt)
                    nxt = rho(t)
                    for k in range(3):
                        col[k] += dt / 6.0 * (here[k] + 4.0 * mid[k] + nxt[k])
                    here = nxt
                t_sun = self.sun_transmittance(add(eye_c, scale(d, t)), sun, lit)
                w = 1.0 if i == 0 or i == n else (4.0 if i % 2 else 2.0)
                for ch in range(3):
                    tau = self.optical_depth(ch, *col)
                    # Ozone absorbs only: no source term.
                    source = self.beta_r[ch] * here[0] * p_r + self.beta_m_sc[ch] * here[1] * p_m
                    piece[ch] += w * source * t_sun[ch] * math.exp(-tau)
            for ch in range(3):
                radiance[ch] += piece[ch] * dt / 3.0
        f_ex = [math.exp(-self.optical_depth(ch, *col)) for ch in range(3)]
        l_in = [radiance[ch] * self.e_sun0[ch] for ch in range(3)]
        return f_ex, l_in, e_sun


def csv_row(point, f_ex, l_in, e_sun):
    return ",".join(format(v, ".9g") for v in (*point, *f_ex, *l_in, *e_sun))


# ---- comparison ------------------------------------------------------------------------------

CHANNELS = [(f"{q}_{c}", 3 + 3 * qi + ci) for qi, q in enumerate(("fex", "lin", "esun"))
            for ci, c in enumerate("rgb")]


def relative_error(ours, theirs):
    return abs(ours - theirs) / max(abs(theirs), COMPARE_FLOOR)


def run_aerial_eval(binary, atmosphere_args, eye, sun, points):
    command = [binary, *atmosphere_args, "--eye=%.17g,%.17g,%.17g" % eye,
               "--sun=%.17g,%.17g,%.17g" % sun, "--model", MODEL]
    stdin = "".join("%.17g,%.17g,%.17g\n" % p for p in points)
    try:
        done = subprocess.run(command, input=stdin, capture_output=True, text=True, timeout=120)
    except OSError as e:
        raise BadInput(f"--compare {binary}: cannot run ({e.strerror})") from None
    if done.returncode != 0:
        raise BadInput(f"--compare {binary}: exit status {done.returncode}: "
                       f"{done.stderr.strip()}")
    lines = done.stdout.strip().split("\n")
    if lines[0] != HEADER or len(lines) != len(points) + 1:
        raise BadInput(f"--compare {binary}: unexpected output: {done.stdout[:200]!r}")
    return [[float(v) for v in line.split(",")] for line in lines[1:]]


def tent_column(center, half_width, h0, h1):
    """Closed form of the integral of the ozone tent from altitude h0 to h1 (m)."""

    def below(h):  # integral from -infinity to h
        u = (h - center) / half_width
        if u <= -1.0:
            return 0.0
        if u <= 0.0:
            return 0.5 * half_width * (u + 1.0) ** 2
        if u < 1.0:
            return half_width * (1.0 - 0.5 * (1.0 - u) ** 2)
        return half_width

    return below(h1) - below(h0)


def closed_form_errors():
    """Largest relative error of this integrator against closed forms of a vertical ray, where
    altitude = distance along the ray: the column to the top, F_ex, and L_in with the sun at the
    zenith (then tau(eye, x) + tau(x, top) = tau(eye, top) for every x on the ray, so
    L_in = E_sun0 T_sun(eye) sum_i beta_i P_i(1) H_i (exp(-h0/H_i) - exp(-h1/H_i)), i over the
    scatterers; ozone enters through T_sun(eye) alone). The rays start below, inside and above
    the ozone layer's corners."""
    a = load_earth()
    integrator = Integrator(a)
    up = (0.0, 0.0, 1.0)
    top = a["atmosphere_radius_m"] - a["planet_radius_m"]
    scale_heights = (a["rayleigh_scale_height_m"], a["mie_scale_height_m"])
    center, half_width = a["ozone_center_altitude_m"], 0.5 * a["ozone_width_m"]

    def columns(h0, h1):
        return [*(hs * (math.exp(-h0 / hs) - math.exp(-h1 / hs)) for hs in scale_heights),
                tent_column(center, half_width, h0, h1)]

    worst = 0.0
    for h0, h1 in ((0.0, 2000.0), (100.0, 10000.0), (1000.0, 30000.0), (5000.0, 45000.0),
                   (27000.0, 50000.0)):
        f_ex, l_in, e_sun = integrator.scatter((0.0, 0.0, h0), (0.0, 0.0, h1), up, up)
        col_view, col_top = columns(h0, h1), columns(h0, top)
        for ch in range(3):
            beta = (a["rayleigh_scattering"][ch],
                    a["mie_scattering"][ch] + a["mie_absorption"][ch],
                    a["ozone_absorption"][ch])
            beta_sc = (a["rayleigh_scattering"][ch], a["mie_scattering"][ch])
            phase = (rayleigh_phase(1.0), henyey_greenstein_phase(1.0, a["mie_g"]))
            t_eye = math.exp(-sum(b * c for b, c in zip(beta, col_top)))
            expected_f_ex = math.exp(-sum(b * c for b, c in zip(beta, col_view)))
            expected_l_in = a["sun_irradiance"][ch] * t_eye * sum(
                b * p * c for b, p, c in zip(beta_sc, phase, col_view))
            expected_e_sun = a["sun_irradiance"][ch] * math.exp(
                -sum(b * c for b, c in zip(beta, columns(h1, top))))
            worst = max(worst, relative_error(f_ex[ch], expected_f_ex),
                        relative_error(l_in[ch], expected_l_in),
                        relative_error(e_sun[ch], expected_e_sun))
    return worst


def compare(binary):
    up = (0.0, 0.0, 1.0)
    worst = (0.0, None)
    worst_by_channel = {channel: 0.0 for channel, _ in CHANNELS}
    worst_convergence = 0.0
    ozone_effect = 0.0  # largest relative change of any value when the ozone is left out
    print(f"aerial-eval --model {MODEL} vs independent Simpson integration (up +Z)")
    with tempfile.TemporaryDirectory(prefix="check_reference.") as scratch:
        for number, (fields, eye, sun_text, points) in enumerate(COMPARE_CASES, start=1):
            if fields is None:
                atmosphere_args, atmosphere, name = ["--preset", "earth"], load_earth(), "earth"
            else:
                path = os.path.join(scratch, f"case{number}.json")
                with open(path, "w", encoding="utf-8") as f:
                    json.dump(fields, f)
                atmosphere_args, atmosphere = ["--atmosphere", path], load_atmosphere(path)
                name = "file " + json.dumps(fields)
            integrator = Integrator(atmosphere)
            fine_integrator = Integrator(atmosphere, steps_scale=2.0)
            no_ozone_integrator = Integrator(dict(atmosphere, ozone_absorption=[0.0, 0.0, 0.0]))
            theirs = run_aerial_eval(binary, atmosphere_args, eye, sun_text,
                                     [p for p, _ in points])
            sun = scale(sun_text, 1.0 / norm(sun_text))
            print()
            print("atmosphere %s, eye=%g,%g,%g sun=%g,%g,%g" % (name, *eye, *sun_text))
            print(f"{'point':>26}  {'channel':7}  {'aerial-eval':>14}  {'independent':>14}  "
                  f"{'rel. error':>10}")
            for (point, label), row in zip(points, theirs):
                def values(which):
                    return [*point, *(v for q in which.scatter(eye, point, sun, up) for v in q)]

                ours, fine, no_ozone = (values(i) for i in (integrator, fine_integrator,
                                                             no_ozone_integrator))
                print(f"# {label}")
                where = "(%g,%g,%g)" % point
                for channel, column in CHANNELS:
                    err = relative_error(row[column], ours[column])
                    worst_by_channel[channel] = max(worst_by_channel[channel], err)
                    worst_convergence = max(worst_convergence,
                                            relative_error(ours[column], fine[column]))
                    ozone_effect = max(ozone_effect, relative_error(no_ozone[column], ours[column]))
                    flag = "  <-- over 1 %" if err > COMPARE_TOLERANCE else ""
                    print(f"{where:>26}  {channel:7}  {row[column]:14.8g}  {ours[column]:14.8g}  "
                          f"{err:10.2e}{flag}")
                    if err > worst[0]:
                        worst = (err, f"{where} {channel} (atmosphere {name}, eye {eye}, "
                                      f"sun {sun_text})")
    print()
    print("largest relative error per column: " + ", ".join(
        f"{channel} {err:.2e}" for channel, err in worst_by_channel.items()))
    print(f"worst relative error: {worst[0]:.2e} at {worst[1]} (tolerance {COMPARE_TOLERANCE:g})")
    print(f"independent integration, change when doubling the steps: {worst_convergence:.2e} "
          f"(must be <= {CONVERGENCE_TOLERANCE:g})")
    closed_form = closed_form_errors()
    print(f"independent integration against closed forms (vertical rays): {closed_form:.2e} "
          f"(must be <= {CONVERGENCE_TOLERANCE:g})")
    print(f"largest change of a value when the ozone is left out: {ozone_effect:.2e} "
          f"(must be > {COMPARE_TOLERANCE:g})")
    if closed_form > CONVERGENCE_TOLERANCE:
        print(f"{TOOL}: the independent integration misses its closed forms", file=sys.stderr)
        return 1
    if worst_convergence > CONVERGENCE_TOLERANCE:
        print(f"{TOOL}: the independent integration is not converged", file=sys.stderr)
        return 1
    if not ozone_effect > COMPARE_TOLERANCE:
        print(f"{TOOL}: the cases cannot tell a model without ozone", file=sys.stderr)
        return 1
    if worst[0] > COMPARE_TOLERANCE:
        print(f"{TOOL}: aerial-eval --model {MODEL} disagrees with the independent integration "
              f"by {worst[0]:.2e} at {worst[1]}", file=sys.stderr)
        return 1
    return 0


def load_earth():
    return {k: (list(v) if isinstance(v, list) else v) for k, v in EARTH.items()}


# ---- command line ----------------------------------------------------------------------------


class Parser(argparse.ArgumentParser):
    def error(self, message):
        raise BadInput(message)


def main(argv):
    parser = Parser(prog=TOOL, description=__doc__.split("\n\n", 1)[0],
                    formatter_class=argparse.RawDescriptionHelpFormatter,
                    epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("--compare", metavar="AERIAL_EVAL",
                        help="compare against this aerial-eval binary and exit")
    parser.add_argument("--preset", help="atmosphere preset (only 'earth')")
    parser.add_argument("--atmosphere", metavar="FILE.json", help="atmosphere JSON file")
    parser.add_argument("--eye", help="eye position X,Y,Z in metres")
    parser.add_argument("--sun", help="direction towards the sun X,Y,Z")
    parser.add_argument("--up", default="0,0,1", help="world up axis X,Y,Z (default 0,0,1)")
    parser.add_argument("--model", default=MODEL,
                        help=f"only '{MODEL}' (the default); 'reference' is refused")
    parser.add_argument("--points", metavar="FILE", help="points x,y,z (default: stdin)")
    parser.add_argument("--steps-scale", type=float, default=1.0,
                        help="multiplies the number of integration steps (default 1)")
    args = parser.parse_args(argv)

    if args.model == "reference":
        raise BadInput(f"--model: 'reference' includes multiple scattering, which this integrator "
                       f"does not compute; use --model {MODEL}")
    if args.model != MODEL:
        raise BadInput(f"--model: only '{MODEL}' is computed here, got '{args.model}'")
    if args.compare:
        return compare(args.compare)

    if args.preset is None and args.atmosphere is None:
        raise BadInput("--preset or --atmosphere is required")
    if args.preset is not None and args.atmosphere is not None:
        raise BadInput("--preset excludes --atmosphere")
    if args.preset is not None and args.preset != "earth":
        raise BadInput(f"--preset: only 'earth' is known here, got '{args.preset}'")
    if args.eye is None:
        raise BadInput("--eye is required")
    if args.sun is None:
        raise BadInput("--sun is required")
    if not (math.isfinite(args.steps_scale) and args.steps_scale > 0.0):
        raise BadInput("--steps-scale: expected a positive number")
    atmosphere = load_earth() if args.preset else load_atmosphere(args.atmosphere)
    eye = parse_vec3(args.eye, "--eye")
    sun = parse_direction(args.sun, "--sun")
    up = parse_direction(args.up, "--up")
    if args.points:
        try:
            with open(args.points, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise BadInput(f"--points {args.points}: cannot read ({e.strerror})") from None
        points = parse_points(text, args.points)
    else:
        points = parse_points(sys.stdin.read(), "stdin")

    integrator = Integrator(atmosphere, args.steps_scale)
    rows = [csv_row(p, *integrator.scatter(eye, p, sun, up)) for p in points]
    sys.stdout.write("\n".join([HEADER, *rows]) + "\n")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BadInput as e:
        print(f"{TOOL}: {e}", file=sys.stderr)
        sys.exit(2)
