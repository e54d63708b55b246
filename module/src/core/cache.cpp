// The per-mesh shading cache: a bound on how much the 8-bit outputs of a mesh can change between
// two shadings that differ only in eye position and sun direction. docs/models.md, "When shading
// can
// be skipped", gives the derivation in prose; the formulas are next to the code below.
//
// Notation (lengths in metres, angles in radians, coefficients in 1/m, per channel):
//   delta    |eye' - eye|, the eye's move
//   alpha    the angle the sun direction turned
//   s        |vertex - eye|, within [s_min, s_max] for every vertex and both eyes
//   theta    the phase angle, within [theta_lo, theta_hi] for every vertex and both shadings
//   gamma    how far a vertex's view direction turns: <= asin(delta / s) for delta < s (law of
//            sines: it is the angle opposite the shortest side), <= pi otherwise
//   beta     extinction; A(theta) = beta_R P_R + beta_Ms P_M (1/(m sr)) with A_max its sup and
//            D = sup |dA/dtheta| over [theta_lo, theta_hi]
//   E        sun irradiance; Phi(s) = (1 - e^{-beta s}) / beta (m), so that L = A E Phi(s)
// Outputs: F = F_ex (shown as it is), L = L_in and lit = albedo F (E_sun n + ambient),
// n = max(N.L, 0), shown through y = exposure x and a tone curve of slope <= 1.
//
// Every difference is split (mean-value theorem) into terms in which one quantity changes, each
// bounded by the sup of its derivative over the box of values both shadings can take, so that the
// straight path between them stays inside. Each such step of a radiance x gets two bounds and
// keeps the smaller:
//   absolute:  |d display| <= exposure |dx|                       (tone slope <= 1)
//   relative:  |d display| <= sup(y tone'(y)) |d ln x|            (<= min(1, y_max) for clamp,
//                                                                   <= 1/e for exponential)
// The relative one keeps the bound useful where radiance is bright (looking towards the sun
// through haze): a 1e-4 relative change of any radiance moves its display value by at most 1e-4
// (0.026 steps), however strong the exposure.
#include "aerial/cache.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "../common/error_text.hpp"
#include "aerial/phase.hpp"
#include "cache_bound.hpp"
#include "math.hpp"

namespace aerial {
namespace {

using glm::dvec3;
using namespace detail::bound;

constexpr double kSteps = 255.0;  // 8-bit steps per unit of display value

bool same_vec(const dvec3& a, const dvec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
bool same_vec(const glm::vec3& a, const glm::vec3& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

/// Everything but the eye and the sun direction.
bool same_except_eye_and_sun(const ShadingKey& a, const ShadingKey& b) {
    return a.atmosphere == b.atmosphere && a.model == b.model &&
           a.display.exposure == b.display.exposure && a.display.tone == b.display.tone &&
           same_vec(a.ambient, b.ambient) && same_vec(a.albedo, b.albedo) &&
           same_vec(a.view.up, b.view.up) && a.view.meters_per_unit == b.view.meters_per_unit;
}

bool same_key(const ShadingKey& a, const ShadingKey& b) {
    return same_except_eye_and_sun(a, b) && same_vec(a.view.eye, b.view.eye) &&
           same_vec(a.view.sun_dir, b.view.sun_dir);
}

/// Angle between two non-zero vectors, accurate for tiny angles.
double angle_between(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// ---- Phase functions: sup of the value and of |d/dtheta| over [lo, hi] within [0, pi] --------

/// P_R = 3/(16 pi) (1 + cos^2): largest at the end farthest from pi/2.
double rayleigh_phase_max(const AngleRange& r) {
    const double c = std::max(std::abs(std::cos(r.lo)), std::abs(std::cos(r.hi)));
    return 3.0 / (16.0 * kPi) * (1.0 + c * c);
}

/// |dP_R/dtheta| = 3/(16 pi) |sin 2 theta|: peaks at pi/4 and 3 pi/4, monotone between.
double rayleigh_phase_slope_max(const AngleRange& r) {
    double m = std::max(std::abs(std::sin(2.0 * r.lo)), std::abs(std::sin(2.0 * r.hi)));
    if (r.contains(0.25 * kPi) || r.contains(0.75 * kPi)) m = 1.0;
    return 3.0 / (16.0 * kPi) * m;
}

/// Henyey–Greenstein in the frame where g >= 0 (theta -> pi - theta flips the sign of g).
AngleRange forward_frame(const AngleRange& r, double g) {
    return g >= 0.0 ? r : AngleRange{kPi - r.hi, kPi - r.lo};
}

/// Henyey–Greenstein decreases with theta for g >= 0: largest at the low end.
double hg_phase_max(const AngleRange& r, double g) {
    return henyey_greenstein_phase(std::cos(forward_frame(r, g).lo), std::abs(g));
}

/// |dP_HG/dtheta| = 3 g (1 - g^2) sin / (4 pi b^(5/2)), b = 1 + g^2 - 2 g cos, for g > 0. Zero at
/// 0 and pi with one maximum between, where 3 g cos^2 + (1 + g^2) cos - 5 g = 0.
double hg_phase_slope_max(const AngleRange& range, double g_signed) {
    const double g = std::abs(g_signed);
    if (g == 0.0) return 0.0;
    const AngleRange r = forward_frame(range, g_signed);
    auto slope = [g](double theta) {
        const double b = detail::hg_denominator_base(std::cos(theta), g);
        return 3.0 * g * (1.0 - g * g) * std::sin(theta) / (4.0 * kPi * b * b * std::sqrt(b));
    };
    const double p = 1.0 + g * g;
    const double cos_peak = (std::sqrt(p * p + 60.0 * g * g) - p) / (6.0 * g);
    const double peak = std::acos(std::clamp(cos_peak, -1.0, 1.0));
    return r.contains(peak) ? slope(peak) : std::max(slope(r.lo), slope(r.hi));
}

/// Smallest values over the range: Rayleigh nearest pi/2, Henyey–Greenstein at the end away from
/// its peak.
double rayleigh_phase_min(const AngleRange& r) {
    const double c =
        r.contains(0.5 * kPi) ? 0.0 : std::min(std::abs(std::cos(r.lo)), std::abs(std::cos(r.hi)));
    return 3.0 / (16.0 * kPi) * (1.0 + c * c);
}

double hg_phase_min(const AngleRange& r, double g) {
    return henyey_greenstein_phase(std::cos(forward_frame(r, g).hi), std::abs(g));
}

/// |d ln P_R / d theta| = |sin 2 theta| / (1 + cos^2 theta) = 2 |sin u| / (3 + cos u), u = 2 theta:
/// peaks at 1/sqrt(2) where cos 2 theta = -1/3, monotone between the peaks and 0, pi/2, pi.
double rayleigh_log_slope_max(const AngleRange& r) {
    auto f = [](double theta) {
        return std::abs(std::sin(2.0 * theta)) / (1.0 + std::cos(theta) * std::cos(theta));
    };
    const double peak = 0.5 * std::acos(-1.0 / 3.0);
    if (r.contains(peak) || r.contains(kPi - peak)) return 1.0 / std::sqrt(2.0);
    return std::max(f(r.lo), f(r.hi));
}

/// |d ln P_HG / d theta| = 3 g sin / b for g > 0: one peak, 3 g / (1 - g^2), at cos = 2g/(1+g^2).
double hg_log_slope_max(const AngleRange& range, double g_signed) {
    const double g = std::abs(g_signed);
    if (g == 0.0) return 0.0;
    const AngleRange r = forward_frame(range, g_signed);
    auto f = [g](double theta) {
        return 3.0 * g * std::sin(theta) / detail::hg_denominator_base(std::cos(theta), g);
    };
    const double peak = std::acos(2.0 * g / (1.0 + g * g));
    return r.contains(peak) ? 3.0 * g / (1.0 - g * g) : std::max(f(r.lo), f(r.hi));
}

/// sup over s in [s_min, s_max] of min(s, Phi(s_max)) * gamma(s), the phase term of an eye move
/// (metres x radians): gamma(s) = asin(delta / s) for s > delta, pi otherwise. Phi(s) <= s and
/// Phi <= Phi(s_max); s gamma(s) is at most pi delta below delta and decreases above it.
double view_turn_term(double s_min, double path_max, double delta) {
    if (delta == 0.0) return 0.0;
    const double turn = s_min > delta ? std::asin(delta / s_min) : kPi;
    const double s_turn = s_min > delta ? s_min * turn : kPi * delta;
    return std::min(path_max * turn, s_turn);
}

/// (1 - exp(-x)) / x.
double phi(double x) { return detail::one_minus_exp_over_x(std::max(x, 0.0)); }

/// sup of tau exp(-tau) over [lo, hi]: 1/e at tau = 1.
double sup_tau_exp(double lo, double hi) {
    if (hi < 1.0) return hi * std::exp(-hi);
    if (lo > 1.0) return lo * std::exp(-lo);
    return std::exp(-1.0);
}

/// sup of y tone'(y) over y in [0, y_max]: how far a relative change |d ln x| of a radiance can
/// move its display value (y = exposure x).
double tone_log_slope_max(ToneCurve tone, double y_max) {
    if (tone == ToneCurve::clamp) return std::min(1.0, y_max);
    return sup_tau_exp(0.0, y_max);  // d(1 - e^-y) / d ln y = y e^-y
}

// ---- Chapman columns (the height model's sun, for a sun above the horizon) -------------------

/// Ch(x, mu) = sqrt(pi x / 2) erfcx(sqrt(x / 2) mu) for mu >= 0: the same asymptotic Chapman
/// function the height model uses (scattering.cpp). x = (R + h) / H.
double chapman(double x, double mu) {
    return std::sqrt(0.5 * kPi * x) * detail::erfcx(std::sqrt(0.5 * x) * mu);
}

/// sup of |d ln Ch / d mu| over mu >= mu_lo > 0 and x' <= x. With y = sqrt(x/2) mu it is
/// sqrt(x/2) q(y), q(y) = 2 / (sqrt(pi) erfcx(y)) - 2 y. From erfcx(y) > 2 / (sqrt(pi)
/// (y + sqrt(y^2 + 2))) (Abramowitz & Stegun 7.1.13), y q(y) < 1, so q(y) < 1/y and
/// d ln Ch / dx = (1 - y q(y)) / (2 x) > 0: Ch grows with x. q decreases and y q(y) increases
/// (checked numerically on [0, 26]), so the sup is at (x, mu_lo). Beyond y = 5 the bound 1/mu
/// is within 4 % and avoids erfc's underflow.
double log_chapman_slope_max(double x, double mu_lo) {
    const double a = std::sqrt(0.5 * x);
    const double y = a * mu_lo;
    if (y >= 5.0) return 1.0 / mu_lo;
    const double q = 2.0 / (std::sqrt(kPi) * std::exp(y * y) * std::erfc(y)) - 2.0 * y;
    return a * q;
}

// ---- Where the vertices are: the sphere, and the box when known (metres) --------------------

struct Region {
    dvec3 centre{0.0};
    double radius = 0.0;
    bool has_box = false;
    dvec3 lo{0.0}, hi{0.0};
};

bool finite(const dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Region region_in_metres(const MeshBounds& bounds, double mpu) {
    Region r;
    r.centre = bounds.centre * mpu;
    r.radius = bounds.radius * mpu;
    r.has_box = finite(bounds.box_min) && finite(bounds.box_max) &&
                bounds.box_min.x <= bounds.box_max.x && bounds.box_min.y <= bounds.box_max.y &&
                bounds.box_min.z <= bounds.box_max.z;
    r.lo = bounds.box_min * mpu;
    r.hi = bounds.box_max * mpu;
    return r;
}

bool inside_box(const Region& r, const dvec3& p) {
    return glm::all(glm::lessThanEqual(r.lo, p)) && glm::all(glm::lessThanEqual(p, r.hi));
}

/// Nearest and farthest vertex distance from an eye: the sphere's, tightened by the box's.
void distance_range(const Region& r, const dvec3& eye, double& nearest, double& farthest) {
    const double to_centre = glm::length(r.centre - eye);
    nearest = std::max(0.0, to_centre - r.radius);
    farthest = to_centre + r.radius;
    if (!r.has_box) return;
    const dvec3 outside = glm::max(glm::max(r.lo - eye, eye - r.hi), dvec3(0.0));
    nearest = std::max(nearest, glm::length(outside));
    farthest =
        std::min(farthest, glm::length(glm::max(glm::abs(eye - r.lo), glm::abs(eye - r.hi))));
}

/// Whether the ray eye + t dir, t >= 0, meets the box (slab test).
bool ray_meets_box(const Region& r, const dvec3& eye, const dvec3& dir) {
    double t0 = 0.0, t1 = kInfinity;
    for (int k = 0; k < 3; ++k) {
        if (dir[k] == 0.0) {
            if (eye[k] < r.lo[k] || eye[k] > r.hi[k]) return false;
            continue;
        }
        const double a = (r.lo[k] - eye[k]) / dir[k], b = (r.hi[k] - eye[k]) / dir[k];
        t0 = std::max(t0, std::min(a, b));
        t1 = std::min(t1, std::max(a, b));
    }
    return t0 <= t1;
}

/// The box's corners seen from an eye outside it.
struct BoxView {
    dvec3 corner[8];       ///< corner - eye, m
    double inv_length[8];  ///< 1 / |corner - eye|
};

BoxView view_box(const Region& r, const dvec3& eye) {
    BoxView v;
    for (int bits = 0; bits < 8; ++bits) {
        v.corner[bits] = dvec3(bits & 1 ? r.hi.x : r.lo.x, bits & 2 ? r.hi.y : r.lo.y,
                               bits & 4 ? r.hi.z : r.lo.z) -
                         eye;
        v.inv_length[bits] = 1.0 / glm::length(v.corner[bits]);
    }
    return v;
}

/// Smallest angle between the unit vector `dir` and the directions from the eye (outside the box)
/// to the box: 0 if the ray meets it, else reached on the silhouette, i.e. on one of the 12 edges
/// (the directions to a convex body form a convex spherical region whose boundary is the image of
/// its edges). On an edge's great-circle arc the nearest direction is `dir` projected onto the
/// arc's plane, if that falls between the ends, else an end; compared by cosine.
double angle_to_box(const Region& r, const BoxView& v, const dvec3& eye, const dvec3& dir) {
    if (ray_meets_box(r, eye, dir)) return 0.0;
    double best = -1.0;  // largest cosine
    for (int k = 0; k < 8; ++k) best = std::max(best, glm::dot(v.corner[k], dir) * v.inv_length[k]);
    for (int k = 0; k < 8; ++k) {
        for (int axis = 1; axis < 8; axis <<= 1) {
            if (k & axis) continue;
            const dvec3& p = v.corner[k];
            const dvec3& q = v.corner[k | axis];
            const dvec3 n = glm::cross(p, q);
            const double n2 = glm::dot(n, n);
            if (!(n2 > 0.0)) continue;
            const dvec3 w = dir - n * (glm::dot(dir, n) / n2);  // cos(angle(w, dir)) = |w|
            if (glm::dot(glm::cross(p, w), n) >= 0.0 && glm::dot(glm::cross(w, q), n) >= 0.0) {
                best = std::max(best, glm::length(w));
            }
        }
    }
    // acos loses about 1e-8 rad near 0: keep the range on the safe side.
    return std::max(0.0, std::acos(std::min(1.0, best)) - 1e-7);
}

/// The phase angles of the vertices seen from `eye` with the sun `sun`: the cone the sphere
/// subtends (everything when the eye is inside), intersected with the box's exact range.
AngleRange phase_angles(const Region& r, const dvec3& eye, const dvec3& sun) {
    AngleRange range;
    const dvec3 to_centre = r.centre - eye;
    const double distance = glm::length(to_centre);
    if (distance > r.radius) {
        const double centre = angle_between(to_centre, sun);
        const double cone = std::asin(std::min(1.0, r.radius / distance));
        range = AngleRange{std::max(0.0, centre - cone), std::min(kPi, centre + cone)};
    }
    if (r.has_box && !inside_box(r, eye)) {
        const BoxView v = view_box(r, eye);
        range.lo = std::max(range.lo, angle_to_box(r, v, eye, sun));
        range.hi = std::min(range.hi, kPi - angle_to_box(r, v, eye, -sun));
    }
    return range;
}

/// Altitude range of the vertices (m): altitude is 1-Lipschitz (sphere); over the box,
/// p.up <= altitude(p) <= p.up + |p|^2 / (2 (R + p.up)) since |p + R up|^2 = (R + p.up)^2 +
/// |p_perp|^2.
void altitude_range(const Region& r, const dvec3& up, double planet_radius, double& lowest,
                    double& highest) {
    const double centre_altitude = altitude_above_sphere(r.centre, up, planet_radius);
    lowest = centre_altitude - r.radius;
    highest = centre_altitude + r.radius;
    if (!r.has_box) return;
    double up_lo = 0.0, up_hi = 0.0, far2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        up_lo += std::min(r.lo[k] * up[k], r.hi[k] * up[k]);
        up_hi += std::max(r.lo[k] * up[k], r.hi[k] * up[k]);
        far2 += std::max(r.lo[k] * r.lo[k], r.hi[k] * r.hi[k]);
    }
    lowest = std::max(lowest, up_lo);
    if (planet_radius + up_lo > 0.0) {
        highest = std::min(highest, up_hi + far2 / (2.0 * (planet_radius + up_lo)));
    }
}

/// Change of each output in display units (multiply by 255 for 8-bit steps), one channel.
struct Change {
    double extinction = 0.0, in_scattering = 0.0, lit = 0.0;
};

/// |ln(b / a)| for a, b >= 0: 0 when both are 0 (nothing to change), infinite when one is.
double log_ratio(double a, double b) {
    if (a == b) return 0.0;
    if (!(a > 0.0 && b > 0.0)) return kInfinity;
    return std::abs(std::log(b / a));
}

// ---- hoffman-preetham: F = e^{-beta s}, L = A(theta) E Phi(s), E = E_sun at the eye ----------
//
//   |dF|      <= beta e^{-beta s_min} delta                          (|dF/ds| = beta F)
//   absolute  |dL| <= D E_max (alpha Phi(s_max) + sup_s min(s, Phi(s_max)) gamma(s))   (theta)
//                   + A_max |E' - E| Phi(s_max)                      (E: exact from both frames)
//                   + A_max E_max e^{-beta s_min} delta              (|dL/ds| = A E e^{-beta s})
//             where s gamma(s) <= s_min asin(delta / s_min), or pi delta when s_min <= delta:
//             finite even for a vertex at the eye.
//   relative  |d ln L| <= sup|d ln A/d theta| (alpha + gamma(s_min)) + |ln(E'/E)|
//                       + delta beta / (e^{beta s_min} - 1)          (d ln Phi/ds <= 1/s)
//   lit       F part: min(absolute |dF| (E + ambient), relative beta delta)
//             + E part: min(absolute F_max |E' - E|, relative |ln(E'/E)|)
//             + N.L part: F_max E_max alpha                          (|dn| <= |d sun| <= alpha)
Change hoffman_preetham_change(const Frame<double>& a, const Frame<double>& b, const Geometry& g,
                               const ShadingKey& key, int c) {
    const Atmosphere& atm = key.atmosphere;
    const double exposure = double(key.display.exposure);
    const double albedo = double(key.albedo[c]), ambient = double(key.ambient[c]);
    const double beta = atm.extinction()[c];
    const double amplitude =
        atm.rayleigh_scattering[c] * g.phase_max[0] + atm.mie_scattering[c] * g.phase_max[1];
    const double slope =
        atm.rayleigh_scattering[c] * g.phase_slope[0] + atm.mie_scattering[c] * g.phase_slope[1];
    // d ln (x + y) is between d ln x and d ln y: the larger component slope bounds the sum's.
    const double log_slope = std::max(atm.rayleigh_scattering[c] > 0.0 ? g.phase_log_slope[0] : 0.0,
                                      atm.mie_scattering[c] > 0.0 ? g.phase_log_slope[1] : 0.0);
    const double e_a = a.sun_irradiance_eye[c], e_b = b.sun_irradiance_eye[c];
    const double e_max = std::max(e_a, e_b), e_change = std::abs(e_b - e_a);
    const double e_log_change = log_ratio(e_a, e_b);
    const double path_max = g.s_max * phi(beta * g.s_max);  // Phi(s_max), m
    const double f_max = std::exp(-beta * g.s_min);
    // delta d ln Phi / ds = delta beta / (e^{beta s} - 1), at most delta / s.
    const double path_log_slope = beta > 0.0 ? quotient(beta * g.delta, std::expm1(beta * g.s_min))
                                             : quotient(g.delta, g.s_min);

    Change out;
    out.extinction = beta * f_max * g.delta;
    // Each factor changed in turn: the smaller of its absolute and relative bound.
    const double cap =
        tone_log_slope_max(key.display.tone, exposure * amplitude * e_max * path_max);
    auto term = [&](double absolute, double relative) {
        return std::min(exposure * absolute, cap * relative);
    };
    out.in_scattering =
        term(slope * e_max * (g.alpha * path_max + view_turn_term(g.s_min, path_max, g.delta)),
             g.phase_change() * log_slope) +
        term(amplitude * e_change * path_max, e_log_change) +
        term(amplitude * e_max * f_max * g.delta, path_log_slope);

    const double lit_cap =
        tone_log_slope_max(key.display.tone, exposure * albedo * f_max * (e_max + ambient));
    const double f_part =
        std::min(exposure * albedo * out.extinction * (e_max + ambient), lit_cap * beta * g.delta);
    const double e_part = std::min(exposure * albedo * f_max * e_change, lit_cap * e_log_change);
    out.lit = f_part + e_part + exposure * albedo * f_max * e_max * g.alpha;
    return out;
}

// ---- height ----------------------------------------------------------------------------------
//
// The same structure with coefficients that hold over the whole region (the vertices, both eyes
// and the segments between, which sag up to s^2 / (8 R) below their ends): densities
// rho_i = exp(-h / H_i) at the lowest altitude h_lo (upper bounds) and at the highest h_hi (lower
// bounds), and the sun's transmittance T = exp(-tau_sun), tau_sun = sum_i beta_i H_i exp(-h/H_i)
// Ch(x_i, mu), bounded over the range [mu_lo, mu_hi] of the sun's zenith cosine. The model takes
// T from l_i = ln(H_i Ch_i) interpolated between the eye (exact in both frames) and the vertex,
// where l_i changes by at most alpha sup|d ln Ch / d mu| (the vertex does not move).
//   optical depth  tau = s beta_mean, beta_mean the model's mean of exp(-h/H) over a linear
//                  altitude profile from the eye to the vertex, lowered by the sag s^2 / (12 R).
//                  Moving one end of that profile by dh changes ln beta_mean by at most dh / H
//                  (absolutely by rho_max dh / (2 H)); the sag moves both ends. So, with
//                  dh = |h_eye' - h_eye| + (2 s_max + delta) delta / (8 R) and
//                  eps = dh / H_min + delta s_max / (6 R H_min):
//                    |d tau| <= sum_i beta_i rho_i,max (delta (1 + s_max^2 / (6 R H_i))
//                               + s_max dh / (2 H_i))                     (absolute)
//                    |d tau| <= beta_max delta + eps tau                  (relative)
//                  and |dF| <= min(F_max |d tau|_abs, F_max beta_max delta + eps sup tau e^-tau).
//   sun            |d ln T| <= sum_i tau_sun,i,max (d l_i + dh / H_i) (node altitudes move by
//                  (1 - u) dh at most), and |dT| <= min(T_max x that, sup(tau e^-tau) max_i(d l_i
//                  + dh / H_i)) (mean-value theorem on exp(-tau)).
//   L              physically E0 int_0^s a(t) T(t) e^{-tau(0,t)} dt, a = sum_i beta_sc,i rho_i P_i;
//                  the model computes it as E0 s phi(tau_c) / phi(tau_G) sum_i beta_sc,i P_i S_i,
//                  S_i a 3-node quadrature mean of rho_i T, its nodes at fixed shares y of the
//                  attenuation (u = -ln(1 - y (1 - e^-tau)) / tau, tau(0, u) <= 2.2 at the last).
//                  Four steps, each the smaller of an absolute and a relative bound:
//     eye end      E0 a_max T_max delta max(1, beta_max Phi)
//                  | d ln(s phi(tau)): min(delta / s_min + |d tau| / 2, beta_max delta e^-tau_min
//                    / (1 - e^-tau_min) + eps + dh / (2 H_min)), d ln phi(tau_G): min(|d tau_G| /
//                    2, beta_max delta / tau_min + eps), and the nodes' shift |du| <= delta / s_min
//                    + dh / (4 H_min) times |d ln(rho T) / du| <= kappa = h_span / H_min (1 +
//                    tau_sun,max) + tau_sun,max l_span (spans between eye and vertices)
//     phase angle  E0 D T_max (alpha Phi + sup_s min(s, Phi) gamma(s))
//                  | sup|d ln P_i / d theta| (alpha + gamma(s_min))
//     densities    E0 T_max Phi sum_i beta_sc,i rho_i,max P_i,max dh / H_i + L_max |d tau|_abs
//                  | sum_i w_i dh / H_i + min(|d tau|_abs, beta_max delta + 2.2 eps), w_i the
//                    share of component i in L, at most 1 / (1 + min X_j / max X_i) with X_i =
//                    beta_sc,i rho_i P_i (the larger dh / H_i gets the largest share it can have)
//     sun          E0 a_max Phi |dT| | |d ln T| (as above)
//                  with Phi = s_max phi(beta_min s_max) >= int_0^s e^{-tau(0,t)} dt, T_max =
//                  exp(-tau_sun,min), L_max = E0 a_max T_max Phi. The phase and sun steps follow
//                  the model exactly (P_i multiplies S_i; a sun turn moves no node). The eye end
//                  and densities steps get kQuadratureMargin for what the quadrature adds when the
//                  eye moves (its weights follow its nodes; measured by the tests).
//   lit            as for hoffman-preetham, with E_sun at the vertex: |d ln E| <= alpha sum_i
//                  tau_sun,i,max sup|d ln Ch_i / d mu|.
// The sun must be above the horizon at every point whose sun the model evaluates (mu_lo > 0):
// below it the model switches the sun off in a step (at sea level its red transmittance drops
// from e^-2 to 0 as it sets), and no finite bound exists.

/// Factor on the height model's eye-move terms for its quadrature (see above).
constexpr double kQuadratureMargin = 1.5;
/// Optical depth from the eye to the last quadrature node at most: -ln(1 - 0.8873).
constexpr double kLastNodeDepth = 2.2;

Change height_change(const Frame<double>& a, const Frame<double>& b, const Geometry& g,
                     const HeightRegion& region, const ShadingKey& key, int c) {
    const Atmosphere& atm = key.atmosphere;
    const double exposure = double(key.display.exposure);
    const double albedo = double(key.albedo[c]), ambient = double(key.ambient[c]);
    const double radius = atm.planet_radius_m;
    const double scale_height[2] = {atm.rayleigh_scale_height_m, atm.mie_scale_height_m};
    const double beta_ex[2] = {atm.rayleigh_scattering[c], atm.mie_extinction()[c]};
    const double beta_ex_g[2] = {atm.rayleigh_scattering.y, atm.mie_extinction().y};
    const double beta_sc[2] = {atm.rayleigh_scattering[c], atm.mie_scattering[c]};
    const double* phase_max = g.phase_max;
    const double* phase_min = g.phase_min;
    const double* phase_slope = g.phase_slope;
    const double* phase_log_slope = g.phase_log_slope;
    const double eye_log[2][2] = {{a.eye_log_chapman_rayleigh, a.eye_log_chapman_mie},
                                  {b.eye_log_chapman_rayleigh, b.eye_log_chapman_mie}};
    const double h_min = std::min(scale_height[0], scale_height[1]);
    const double dh = std::abs(b.eye_altitude_m - a.eye_altitude_m) +
                      (2.0 * g.s_max + g.delta) * g.delta / (8.0 * radius);
    const double eps = dh / h_min + g.delta * g.s_max / (6.0 * radius * h_min);
    // Largest altitude difference between an eye and a point of a segment, m.
    const double h_span = std::max(region.h_hi - std::min(a.eye_altitude_m, b.eye_altitude_m),
                                   std::max(a.eye_altitude_m, b.eye_altitude_m) - region.h_lo);

    double beta_max = 0.0, beta_min = 0.0, beta_max_g = 0.0, beta_min_g = 0.0;
    double amplitude = 0.0, slope = 0.0, log_slope = 0.0, density_term = 0.0;
    double tau_change = 0.0, tau_change_g = 0.0;  // |d tau|_abs, channel c and G
    double tau_sun_lo = 0.0, tau_sun_hi = 0.0, sun_log_change = 0.0, vertex_log_slope = 0.0;
    // Per component: d ln tau_sun,i at the nodes, its sum weighted by tau_sun,i at most, and the
    // same at the vertex for a sun turn.
    double sun_weighted_change = 0.0, vertex_weighted_slope = 0.0;
    double scattering_min[2], scattering_max[2];  // beta_sc,i rho_i P_i over the region
    double log_span = 0.0;
    for (int i = 0; i < 2; ++i) {
        const double hs = scale_height[i];
        const double rho_max = std::exp(-region.h_lo / hs), rho_min = std::exp(-region.h_hi / hs);
        beta_max += beta_ex[i] * rho_max;
        beta_min += beta_ex[i] * rho_min;
        beta_max_g += beta_ex_g[i] * rho_max;
        beta_min_g += beta_ex_g[i] * rho_min;
        amplitude += beta_sc[i] * rho_max * phase_max[i];
        slope += beta_sc[i] * rho_max * phase_slope[i];
        if (beta_sc[i] > 0.0) log_slope = std::max(log_slope, phase_log_slope[i]);
        const double column_change =
            rho_max *
            (g.delta * (1.0 + g.s_max * g.s_max / (6.0 * radius * hs)) + g.s_max * dh / (2.0 * hs));
        tau_change += beta_ex[i] * column_change;
        tau_change_g += beta_ex_g[i] * column_change;
        density_term += beta_sc[i] * rho_max * phase_max[i] * dh / hs;
        scattering_max[i] = beta_sc[i] * rho_max * phase_max[i];
        scattering_min[i] = beta_sc[i] * rho_min * phase_min[i];
        // Sun columns ln(H Ch) over the vertices (Ch grows with x and falls with mu) and eyes.
        const double x_lo = (radius + region.h_lo) / hs, x_hi = (radius + region.h_hi) / hs;
        const double log_lo =
            std::min({std::log(hs * chapman(x_lo, region.mu_hi)), eye_log[0][i], eye_log[1][i]});
        const double log_hi =
            std::max({std::log(hs * chapman(x_hi, region.mu_lo)), eye_log[0][i], eye_log[1][i]});
        log_span = std::max(log_span, log_hi - log_lo);
        tau_sun_lo += beta_ex[i] * std::exp(log_lo - region.h_hi / hs);
        const double tau_i_hi = beta_ex[i] * std::exp(log_hi - region.h_lo / hs) * (1.0 + 1e-4);
        tau_sun_hi += tau_i_hi;
        const double vertex_slope = log_chapman_slope_max(x_hi, region.mu_lo);
        vertex_log_slope = std::max(vertex_log_slope, vertex_slope);
        const double eye_change = std::abs(eye_log[1][i] - eye_log[0][i]);
        const double change_i = std::max(eye_change, vertex_slope * g.alpha) + dh / hs;
        sun_log_change = std::max(sun_log_change, change_i);
        sun_weighted_change += tau_i_hi * change_i;
        vertex_weighted_slope += tau_i_hi * vertex_slope;
    }
    // Ch is evaluated here through erfcx, whose relative error is below 2e-5.
    tau_sun_lo *= 1.0 - 1e-4;
    const double e0 = atm.sun_irradiance[c];
    const double sun_max = std::exp(-tau_sun_lo);
    const double sun_slope = sup_tau_exp(tau_sun_lo, tau_sun_hi);  // sup |dT / d ln tau|
    const double path_max = g.s_max * phi(beta_min * g.s_max);
    const double f_max = std::exp(-beta_min * g.s_min);
    const double l_max = e0 * amplitude * sun_max * path_max;
    const double tau_min = beta_min * g.s_min, tau_min_g = beta_min_g * g.s_min;

    Change out;
    out.extinction =
        std::min(f_max * tau_change,
                 f_max * beta_max * g.delta +
                     eps * sup_tau_exp(tau_min, beta_max * (g.s_max + g.delta) * (1.0 + eps)));

    const double path_log =
        std::min(quotient(g.delta, g.s_min) + 0.5 * tau_change,
                 quotient(beta_max * g.delta * std::exp(-tau_min), -std::expm1(-tau_min)) + eps +
                     dh / (2.0 * h_min));
    const double path_g_log =
        std::min(0.5 * tau_change_g, quotient(beta_max_g * g.delta, tau_min_g) + eps);
    // Densities: component i's share of L is at most 1 / (1 + min X_j / max X_i), X the
    // scattering per steradian; the larger relative change dh / H goes to the larger share.
    const int big = scale_height[0] < scale_height[1] ? 0 : 1;  // the smaller scale height
    const double big_share = scattering_max[big] > 0.0
                                 ? 1.0 / (1.0 + scattering_min[1 - big] / scattering_max[big])
                                 : 0.0;
    const double density_log =
        big_share * dh / scale_height[big] + (1.0 - big_share) * dh / scale_height[1 - big];
    const double kappa = h_span / h_min * (1.0 + tau_sun_hi) + tau_sun_hi * log_span;
    const double node_log = kappa * (quotient(g.delta, g.s_min) + dh / (4.0 * h_min));
    const double node_depth_change =
        std::min(tau_change, beta_max * g.delta + kLastNodeDepth * eps);
    // Each factor changed in turn: the smaller of its absolute and relative bound (relative to
    // all of L, the higher orders' included).
    const MultipleScatteringChange ms =
        multiple_scattering_change(a, b, g, region, key, c, path_max, dh);
    const double quadrature_relative =
        kQuadratureMargin * (path_log + path_g_log + node_log + density_log + node_depth_change);
    const double cap = tone_log_slope_max(key.display.tone, exposure * (l_max + ms.l_max));
    auto term = [&](double absolute, double relative) {
        return std::min(exposure * absolute, cap * relative);
    };
    out.in_scattering =
        kQuadratureMargin *
            (term(e0 * amplitude * sun_max * g.delta * std::max(1.0, beta_max * path_max),
                  path_log + path_g_log + node_log) +
             term(e0 * sun_max * path_max * density_term + l_max * tau_change,
                  density_log + node_depth_change)) +
        term(e0 * slope * sun_max *
                 (g.alpha * path_max + view_turn_term(g.s_min, path_max, g.delta)),
             g.phase_change() * log_slope) +
        term(e0 * amplitude * path_max *
                 std::min(sun_slope * sun_log_change, sun_max * sun_weighted_change),
             sun_weighted_change);

    // The higher orders: their weights and path change as the sunlight's do (relatively), and
    // their own rows and lookups (multiple_scattering_change).
    const double ms_per_path = path_max > 0.0 ? ms.l_max / path_max : 0.0;
    const double ms_quadrature =
        kQuadratureMargin * (ms_per_path * g.delta * std::max(1.0, beta_max * path_max) +
                             ms.l_max * (dh / h_min + tau_change));
    out.in_scattering += term(ms_quadrature, quadrature_relative) + term(ms.absolute, ms.relative);

    const double e_max = e0 * sun_max;
    const double lit_cap =
        tone_log_slope_max(key.display.tone, exposure * albedo * f_max * (e_max + ambient));
    const double f_part =
        std::min(exposure * albedo * out.extinction * (e_max + ambient), lit_cap * tau_change);
    const double e_part =
        std::min(exposure * albedo * f_max * e0 *
                     std::min(sun_slope * vertex_log_slope, sun_max * vertex_weighted_slope),
                 lit_cap * vertex_weighted_slope) *
        g.alpha;
    out.lit = f_part + e_part + exposure * albedo * f_max * e_max * g.alpha;
    return out;
}

/// Cosine of the sun's zenith angle at a point (metres), for a sun direction.
double sun_cos_zenith(const Frame<double>& f, const dvec3& p_m) {
    const dvec3 from_centre = p_m + f.view.up * f.atmosphere.planet_radius_m;
    return glm::dot(from_centre, f.view.sun_dir) / glm::length(from_centre);
}

std::optional<Error> validate_display(const Display& display) {
    if (std::isfinite(display.exposure) && display.exposure > 0.0f) return std::nullopt;
    return detail::invalid("prepare_shading_key", "display.exposure", "a finite value > 0",
                           detail::number(display.exposure));
}

bool valid(const ShadingKey& key) {
    return !validate_display(key.display) && !validate(key.atmosphere) && !validate(key.view);
}

}  // namespace

Result<PreparedShadingKey> prepare_shading_key(const ShadingKey& key) {
    if (auto e = validate_display(key.display)) return *e;
    auto frame = prepare_frame<double>(key.atmosphere, key.view, key.model);
    if (!frame) return detail::from("prepare_shading_key", frame.error());
    return PreparedShadingKey{key, std::move(frame).value()};
}

double max_change_lsb(const PreparedShadingKey& before, const PreparedShadingKey& now,
                      const MeshBounds& bounds) {
    const ShadingKey& key = now.key;
    if (!same_except_eye_and_sun(before.key, key)) return kInfinity;
    if (same_key(before.key, key)) return 0.0;
    if (bounds.radius < 0.0) return 0.0;  // no finite vertex: every output is constant
    if (is_numerical(key.model)) return kInfinity;
    if (!finite(bounds.centre) || !std::isfinite(bounds.radius)) return kInfinity;

    const Frame<double>& a = before.frame;
    const Frame<double>& b = now.frame;
    const Region region = region_in_metres(bounds, key.view.meters_per_unit);
    Geometry g;
    // shade_into works from prepare_frame<float>, which rounds the eye (m) and the sun direction
    // to float: a move can look up to 2 sqrt(3) 2^-24 |eye| longer, a turn 2 sqrt(3) 2^-24 rad
    // larger, there. A key that did not move them rounds them alike.
    constexpr double kFloatRounding = 2.0 * 1.7320508075688772 / 16777216.0;
    g.delta = glm::length(b.eye_m - a.eye_m);
    if (g.delta > 0.0) {
        g.delta += kFloatRounding * std::max(glm::length(a.eye_m), glm::length(b.eye_m));
    }
    g.alpha = angle_between(a.view.sun_dir, b.view.sun_dir);
    if (!same_vec(a.view.sun_dir, b.view.sun_dir)) g.alpha += kFloatRounding;
    double near_a, far_a, near_b, far_b;
    distance_range(region, a.eye_m, near_a, far_a);
    distance_range(region, b.eye_m, near_b, far_b);
    g.s_min = std::min(near_a, near_b);
    g.s_max = std::max(far_a, far_b);
    // Vertices beyond kMaxDistanceM are not positions: their outputs jump to F = 1, L = 0.
    if (!(g.s_max * (1.0 + 1e-6) < kMaxDistanceM)) return kInfinity;
    const AngleRange phase_a = phase_angles(region, a.eye_m, a.view.sun_dir);
    const AngleRange phase_b = phase_angles(region, b.eye_m, b.view.sun_dir);
    g.phase = AngleRange{std::min(phase_a.lo, phase_b.lo), std::max(phase_a.hi, phase_b.hi)};
    const double mie_g = key.atmosphere.mie_g;
    g.phase_max[0] = rayleigh_phase_max(g.phase);
    g.phase_max[1] = hg_phase_max(g.phase, mie_g);
    g.phase_min[0] = rayleigh_phase_min(g.phase);
    g.phase_min[1] = hg_phase_min(g.phase, mie_g);
    g.phase_slope[0] = rayleigh_phase_slope_max(g.phase);
    g.phase_slope[1] = hg_phase_slope_max(g.phase, mie_g);
    g.phase_log_slope[0] = rayleigh_log_slope_max(g.phase);
    g.phase_log_slope[1] = hg_log_slope_max(g.phase, mie_g);

    HeightRegion height;
    if (key.model == Model::height) {
        const double radius = key.atmosphere.planet_radius_m;
        // Sun zenith cosines: exact at the eyes; over the sphere, the local zenith turns by at
        // most asin(r / |centre - planet centre|) from the centre's.
        const dvec3 from_centre = region.centre + a.view.up * radius;
        const double centre_distance = glm::length(from_centre);
        if (!(region.radius < centre_distance)) return kInfinity;
        const double spread = std::asin(region.radius / centre_distance);
        const double mu_a = sun_cos_zenith(a, a.eye_m), mu_b = sun_cos_zenith(b, b.eye_m);
        height.mu_lo = std::min(mu_a, mu_b);
        height.mu_hi = std::max(mu_a, mu_b);
        for (const Frame<double>* f : {&a, &b}) {
            const double zenith = angle_between(from_centre, f->view.sun_dir);
            height.mu_lo = std::min(height.mu_lo, std::cos(std::min(kPi, zenith + spread)));
            height.mu_hi = std::max(height.mu_hi, std::cos(std::max(0.0, zenith - spread)));
        }
        if (!(height.mu_lo > 0.0)) return kInfinity;
        // Altitudes of the vertices and eyes; segments sag by up to s^2 / (8 R) below their ends.
        double mesh_lo, mesh_hi;
        altitude_range(region, a.view.up, radius, mesh_lo, mesh_hi);
        height.h_hi = std::max({a.eye_altitude_m, b.eye_altitude_m, mesh_hi});
        height.h_lo = std::min({a.eye_altitude_m, b.eye_altitude_m, mesh_lo}) -
                      g.s_max * g.s_max / (8.0 * radius);
        // The model clamps altitudes at kMinAltitudeM or above.
        height.h_lo = std::max(height.h_lo, kMinAltitudeM);
        // The view directions' smallest angle to either eye's zenith or nadir: from the cone
        // around the region's bounding sphere, or from the altitudes (a vertex s >= s_min away
        // is at most |h - h_eye| plus the sphere's drop s^2 / (2 R) above or below the eye).
        double vertical = 0.0;
        for (const Frame<double>* f : {&a, &b}) {
            vertical = std::max({vertical, std::abs(height.h_hi - f->eye_altitude_m),
                                 std::abs(f->eye_altitude_m - height.h_lo)});
        }
        vertical += g.s_max * g.s_max / (2.0 * radius);
        const double by_altitude =
            g.s_min > vertical ? std::sqrt(1.0 - (vertical / g.s_min) * (vertical / g.s_min)) : 0.0;
        height.view.sin_zenith_min = 1.0;
        for (const Frame<double>* f : {&a, &b}) {
            const dvec3 to_centre = region.centre - f->eye_m;
            const double distance = glm::length(to_centre);
            if (!(distance > region.radius)) {
                height.view.sin_zenith_min = 0.0;
                break;
            }
            const double half = std::asin(region.radius / distance);
            const double zenith = angle_between(to_centre, dvec3(f->eye_zenith));
            const double lo = zenith - half, hi = zenith + half;
            height.view.sin_zenith_min =
                (lo <= 0.0 || hi >= kPi)
                    ? 0.0
                    : std::min({height.view.sin_zenith_min, std::sin(lo), std::sin(hi)});
        }
        height.view.sin_zenith_min = std::max(height.view.sin_zenith_min, by_altitude);
    }

    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        const Change change = key.model == Model::hoffman_preetham
                                  ? hoffman_preetham_change(a, b, g, key, c)
                                  : height_change(a, b, g, height, key, c);
        worst = std::max({worst, change.extinction, change.in_scattering, change.lit});
    }
    const double lsb = kSteps * worst;
    return std::isnan(lsb) ? kInfinity : lsb;
}

double max_change_lsb(const ShadingKey& before, const ShadingKey& now, const MeshBounds& bounds) {
    if (!same_except_eye_and_sun(before, now)) return kInfinity;
    if (same_key(before, now)) return valid(now) ? 0.0 : kInfinity;
    auto a = prepare_shading_key(before);
    auto b = prepare_shading_key(now);
    if (!a || !b) return kInfinity;
    return max_change_lsb(*a, *b, bounds);
}

bool ShadingCache::needs_update(const PreparedShadingKey& now) const {
    return !shaded_with || !(max_change_lsb(*shaded_with, now, bounds) < kSkipBelowLsb);
}

bool ShadingCache::needs_update(const ShadingKey& now) const {
    if (!shaded_with) return true;
    auto prepared = prepare_shading_key(now);
    return !prepared || needs_update(*prepared);
}

void ShadingCache::mark_shaded(const ShadingKey& now) {
    auto prepared = prepare_shading_key(now);
    if (prepared) {
        shaded_with = std::move(prepared).value();
    } else {
        shaded_with.reset();
    }
}

}  // namespace aerial
