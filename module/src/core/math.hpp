// Internal: numerically stable scalar helpers shared by the models (templated on float/double).
#pragma once

#include <algorithm>
#include <cmath>

#include "height_constants.hpp"

namespace aerial::detail {

/// (1 - exp(-x)) / x for x >= 0, with its limit 1 at x = 0. Turns "beta_sc / beta_ex *
/// (1 - F_ex)" into "beta_sc * s * one_minus_exp_over_x(beta_ex * s)", which stays finite and
/// exact as beta_ex -> 0 (the limit of L_in is beta_sc * E * s).
template <class T>
T one_minus_exp_over_x(T x) {
    if (x < T(1e-3)) return T(1) - x * (T(0.5) - x * (T(1.0 / 6.0) - x * T(1.0 / 24.0)));
    return -std::expm1(-x) / x;
}

/// (1 - exp(-x)) / x for any x >= -80 (the mean of exp(-x u) over u in [0, 1]); x is clamped
/// there (height::kMaxExponent) so that float cannot overflow.
template <class T>
T exponential_average(T x) {
    if (x >= T(0)) return one_minus_exp_over_x(x);
    const T a = std::min(-x, T(height::kMaxExponent));
    return a < T(1e-3) ? one_minus_exp_over_x(x) : std::expm1(a) / a;
}

/// log((1 - exp(-x)) / x) for any finite x, without overflow: for x < 0 the ratio is
/// exp(|x|) (1 - exp(-|x|)) / |x|.
template <class T>
T log_one_minus_exp_over_x(T x) {
    if (x >= T(0)) return std::log(one_minus_exp_over_x(x));
    return -x + std::log(one_minus_exp_over_x(-x));
}

/// Mean of u over [0, 1] weighted by exp(-k u), for any finite k: 1/k - 1/(exp(k) - 1).
/// 1/2 at k = 0, towards 0 for large k (weight piled at the start), towards 1 for large -k.
template <class T>
T exponential_mean_fraction(T k) {
    const T a = std::abs(k);
    T m;  // the mean for |k|
    if (a < T(1e-2)) {
        m = T(0.5) - a * (T(1.0 / 12.0) - a * a * T(1.0 / 720.0));
    } else if (a > T(80)) {
        m = T(1) / a;  // exp(80) - 1 overflows float; the correction is below 1e-33
    } else {
        m = T(1) / a - T(1) / std::expm1(a);
    }
    return k >= T(0) ? m : T(1) - m;
}

/// Scaled complementary error function exp(y^2) erfc(y) for y >= 0, relative error below 2e-5
/// in float and double, no overflow: the asymptotic series beyond y = 5.
template <class T>
T erfcx(T y) {
    if (y < T(5)) return std::exp(y * y) * std::erfc(y);
    const T inv2 = T(1) / (y * y);
    constexpr double kInvSqrtPi = 0.56418958354775628695;
    return T(kInvSqrtPi) / y * (T(1) - inv2 * (T(0.5) - inv2 * (T(0.75) - inv2 * T(1.875))));
}

/// Cosine of the zenith angle of the planet's horizon seen from `altitude_m` (<= 0; 0 at and
/// below the ground): directions below it meet the planet.
inline double horizon_cosine(double planet_radius_m, double altitude_m) {
    const double ratio = planet_radius_m / (planet_radius_m + std::max(altitude_m, 0.0));
    return -std::sqrt(std::max(0.0, 1.0 - ratio * ratio));
}

}  // namespace aerial::detail
