// Internal: numerically stable scalar helpers shared by the models (templated on float/double).
#pragma once

#include <cmath>

namespace aerial::detail {

/// (1 - exp(-x)) / x for x >= 0, with its limit 1 at x = 0. Turns "beta_sc / beta_ex *
/// (1 - F_ex)" into "beta_sc * s * one_minus_exp_over_x(beta_ex * s)", which stays finite and
/// exact as beta_ex -> 0 (the limit of L_in is beta_sc * E * s).
template <class T>
T one_minus_exp_over_x(T x) {
    if (x < T(1e-3)) return T(1) - x * (T(0.5) - x * (T(1.0 / 6.0) - x * T(1.0 / 24.0)));
    return -std::expm1(-x) / x;
}

/// Mean of u over [0, x] weighted by exp(-u), for x >= 0: 1 - x / (exp(x) - 1). Goes from x/2
/// (no fall-off across the interval) to 1 (the fall-off is much faster than the interval).
template <class T>
T exponential_mean_fraction(T x) {
    if (x < T(1e-2)) return x * (T(0.5) - x * T(1.0 / 12.0));
    if (x > T(80)) return T(1);  // exp(80) - 1 overflows float; x / that is below 1e-33
    return T(1) - x / std::expm1(x);
}

/// Scaled complementary error function exp(y^2) erfc(y) for y >= 0, relative error below 2e-5
/// in float and double, no overflow: the asymptotic series beyond y = 5.
template <class T>
T erfcx(T y) {
    if (y < T(5)) return std::exp(y * y) * std::erfc(y);
    const T inv2 = T(1) / (y * y);
    constexpr double kInvSqrtPi = 0.56418958354775628695;
    return T(kInvSqrtPi) / y *
           (T(1) - inv2 * (T(0.5) - inv2 * (T(0.75) - inv2 * T(1.875))));
}

}  // namespace aerial::detail
