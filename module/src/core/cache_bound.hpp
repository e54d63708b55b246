// Internal: what the skip bound's files share (cache.cpp: the bound of each model;
// cache_multiple_scattering.cpp: the height model's higher orders).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "aerial/cache.hpp"
#include "aerial/phase.hpp"
#include "aerial/scattering.hpp"

namespace aerial::detail::bound {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// A range of angles within [0, pi].
struct AngleRange {
    double lo = 0.0, hi = kPi;
    bool contains(double theta) const { return lo <= theta && theta <= hi; }
};

/// What both shadings share about where the vertices are, seen from both eyes.
struct Geometry {
    double delta = 0.0;  ///< eye move, m
    double alpha = 0.0;  ///< sun turn, rad
    double s_min = 0.0;  ///< m
    double s_max = 0.0;  ///< m
    AngleRange phase;    ///< phase angles of both shadings
    /// Rayleigh [0] and Mie [1] phase functions over `phase`: sup and inf of the value, sup of
    /// |dP/dtheta| and of |d ln P/dtheta|.
    double phase_max[2] = {0.0, 0.0}, phase_min[2] = {0.0, 0.0};
    double phase_slope[2] = {0.0, 0.0}, phase_log_slope[2] = {0.0, 0.0};
    /// The phase angle of any vertex changes by at most this (rad): alpha + gamma(s_min).
    double phase_change() const {
        return std::min(kPi, alpha + (s_min > delta ? std::asin(delta / s_min) : kPi));
    }
};

/// x / y for x, y >= 0, with 0 / 0 = 0 (nothing moved, nothing changes).
inline double quotient(double x, double y) { return x == 0.0 ? 0.0 : x / y; }

/// What the region's view directions need for the higher orders' shape: the sine of their
/// smallest angle to the eye's zenith or nadir (0 when the cone of directions holds either).
struct ViewCone {
    double sin_zenith_min = 0.0;
};

/// What the height model's bound needs about the region, from both frames.
struct HeightRegion {
    double mu_lo = 0.0, mu_hi = 0.0;  ///< sun zenith cosines at the vertices and eyes
    double h_lo = 0.0, h_hi = 0.0;    ///< altitudes, m (h_lo includes the sag)
    ViewCone view;                    ///< the view directions from both eyes
};

// The higher orders (height_multiple_scattering.hpp): L_ms = path sum_i beta_sc,i S'_i shape(v),
// S'_i the sunlight's quadrature with level(h) in place of E0 T, shape(v) in place of P. Bounded
// with the sunlight term's relative changes of the path and the weights (`relative`), plus what
// is its own: each slice is cut at its frame's eye, so the rows differ between the frames (their
// largest difference); the nodes' altitudes move by at most dh + h_span delta / s_min, through
// level's largest slope over altitude; the view turns by at most asin(delta / s_min) (and the
// eye's zenith by delta / R), through shape's largest slope over the view cosine, and its
// azimuth from the sun turns by that over the sine of the view's zenith angle plus the sun's
// turn over the sine of the sun's, through shape's slope over azimuth, or by no more than shape's
// range within a view row (next to the zenith, where the azimuth is ill-conditioned).
/// The higher orders' largest L (before the exposure) and their own change: absolute, and
/// relative to their smallest value (infinite where that is 0).
struct MultipleScatteringChange {
    double l_max = 0.0;
    double absolute = 0.0, relative = 0.0;
};
MultipleScatteringChange multiple_scattering_change(const Frame<double>& a, const Frame<double>& b,
                                                    const Geometry& g, const HeightRegion& region,
                                                    const ShadingKey& key, int c, double path_max,
                                                    double dh);

}  // namespace aerial::detail::bound
