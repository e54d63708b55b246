// aerial/phase.hpp — phase functions, per steradian, each integrating to 1 over the sphere.
//
// How to use this:
//   1. cos_theta = dot(normalize(vertex - eye), sun_dir): 1 when looking straight at the sun.
//   2. rayleigh_phase(cos_theta) for air; henyey_greenstein_phase(cos_theta, g) for haze with
//      g > 0 meaning forward scattering (peak towards the sun).
//   3. Coming from the 2002 slides? Their g has the opposite sign and their numerator (1-g)^2 is
//      a misprint for (1-g^2): use mie_g_from_2002_slides(g) and the functions here.
//
// All functions accept any cos_theta (it is clamped to [-1, 1]) and |g| < 1, and are finite and
// non-negative for every such input, in float and in double.
#pragma once

#include <algorithm>
#include <cmath>

namespace aerial {

inline constexpr double kPi = 3.14159265358979323846;

/// Rayleigh phase function 3/(16 pi) (1 + cos^2 theta).
template <class T>
T rayleigh_phase(T cos_theta) {
    const T c = std::clamp(cos_theta, T(-1), T(1));
    return T(3.0 / (16.0 * kPi)) * (T(1) + c * c);
}

namespace detail {
/// 1 + g^2 - 2 g cos_theta, written as (1 - |g|)^2 + 2 |g| (1 - sign(g) cos_theta) so that it
/// stays accurate (and > 0) at the peak as |g| -> 1, where the naive form cancels
/// catastrophically in float (for either sign of g).
template <class T>
T hg_denominator_base(T cos_theta, T g) {
    const T c = std::clamp(cos_theta, T(-1), T(1));
    const T a = std::abs(g);
    const T one_minus_a = T(1) - a;
    return one_minus_a * one_minus_a + T(2) * a * (T(1) - (g < T(0) ? -c : c));
}
/// 1 - g^2 as (1 - |g|)(1 + |g|): no cancellation as |g| -> 1.
template <class T>
T one_minus_g_squared(T g) {
    const T a = std::abs(g);
    return (T(1) - a) * (T(1) + a);
}
}  // namespace detail

/// Normalised Henyey–Greenstein phase function (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^(3/2)).
/// g > 0 peaks at cos_theta = 1 (towards the sun). Requires |g| < 1.
template <class T>
T henyey_greenstein_phase(T cos_theta, T g) {
    const T base = detail::hg_denominator_base(cos_theta, g);
    return detail::one_minus_g_squared(g) / (T(4.0 * kPi) * base * std::sqrt(base));
}

/// Cornette–Shanks phase function (1992), a Henyey–Greenstein variant with a Rayleigh-like
/// (1 + cos^2) factor that fits real aerosol better near 90 degrees:
/// 3 (1 - g^2) (1 + cos^2) / (8 pi (2 + g^2) (1 + g^2 - 2 g cos)^(3/2)). Normalised.
template <class T>
T cornette_shanks_phase(T cos_theta, T g) {
    const T c = std::clamp(cos_theta, T(-1), T(1));
    const T base = detail::hg_denominator_base(c, g);
    return T(3.0 / (8.0 * kPi)) * detail::one_minus_g_squared(g) * (T(1) + c * c) /
           ((T(2) + g * g) * base * std::sqrt(base));
}

/// Maps the 2002 slides' Henyey–Greenstein g (negative = forward, with the angle measured the
/// other way) to this module's convention (positive = forward). Their g = -0.75 is our 0.75.
constexpr double mie_g_from_2002_slides(double g_2002) { return -g_2002; }

}  // namespace aerial
