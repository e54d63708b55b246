// Internal: the numbers of the height model that its three implementations share: the scalar
// model (scattering.cpp), the SIMD kernels (kernel_height-inl.h) and the ARB program
// (gl/arb_program_height.cpp). Each is a double; the float paths take float(value), which is
// the float nearest to the decimal literal for every constant here.
#pragma once

namespace aerial::detail::height {

/// log of the sun's column (m) beyond which it counts as blocked by the planet; exp of it still
/// fits a float.
inline constexpr double kBlockedLogColumn = 80.0;

/// The largest natural exponent the model takes (exp(80) = 5.5e34 fits a float): the sun columns
/// and the quadrature weights are exp(min(x, kMaxExponent)), and so is the G extinction at the
/// segment's end relative to the eye's.
inline constexpr double kMaxExponent = 80.0;

/// The slope a of the one-exponential fit of the G extinction profile, k0 exp(-a u), is clamped
/// to +-kMaxFitSlope (natural units over the segment).
inline constexpr double kMaxFitSlope = kMaxExponent;

/// Below |a| = kLinearFitLimit the fit's quantile takes its first-order series (a division by a
/// would lose the digits there).
inline constexpr double kLinearFitLimit = 1e-4;

/// Below a total G optical depth of kLinearDepthLimit the fitted depth to a node is linear in it.
inline constexpr double kLinearDepthLimit = 1e-4;

/// 3-point Gauss–Legendre nodes and weights on [0, 1]: the sunlight quadrature along the segment.
inline constexpr double kSunNodes[3] = {0.11270166537925831148, 0.5, 0.88729833462074168852};
inline constexpr double kSunWeights[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

/// A straight segment sags below the line joining its end altitudes by u (1 - u) sag, sag =
/// s^2 / (2 R); the mean of u (1 - u) over [0, 1] is kMeanSagFraction.
inline constexpr double kMeanSagFraction = 1.0 / 6.0;

/// sqrt(pi / 2), of the asymptotic Chapman function H sqrt(pi x / 2) erfcx(sqrt(x / 2) |mu|).
inline constexpr double kSqrtHalfPi = 1.2533141373155002512;

/// Floor of the Chapman factor below the horizon, 2 Ch(x_t, 90 deg) - Ch(x, 180 deg - chi)
/// (relative to exp(-h/H)), which rounding can take to 0 or below.
inline constexpr double kMinChapmanFactor = 1e-30;

}  // namespace aerial::detail::height
