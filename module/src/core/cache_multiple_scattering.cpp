// The skip bound of the height model's higher orders (see cache_bound.hpp and cache.cpp).
#include <algorithm>
#include <cmath>

#include "cache_bound.hpp"
#include "height_multiple_scattering.hpp"

namespace aerial::detail::bound {

MultipleScatteringChange multiple_scattering_change(const Frame<double>& a, const Frame<double>& b,
                                                    const Geometry& g, const HeightRegion& region,
                                                    const ShadingKey& key, int c, double path_max,
                                                    double dh) {
    using S = detail::MultipleScatteringSlice;
    const S* sa = a.multiple_scattering.get();
    const S* sb = b.multiple_scattering.get();
    if (!sa && !sb) return {};
    const Atmosphere& atm = key.atmosphere;
    double amplitude = 0.0;  // sum_i beta_sc,i rho_i,max
    amplitude += atm.rayleigh_scattering[c] * std::exp(-region.h_lo / atm.rayleigh_scale_height_m);
    amplitude += atm.mie_scattering[c] * std::exp(-region.h_lo / atm.mie_scale_height_m);
    double level_max = 0.0, shape_max = 0.0, level_diff = 0.0, shape_diff = 0.0;
    double level_min = kInfinity, shape_min = kInfinity;
    double level_slope = 0.0, mu_slope = 0.0, azimuth_slope = 0.0, azimuth_range = 0.0;
    const double radius = atm.planet_radius_m;
    for (const S* s : {sa, sb}) {
        if (!s) continue;
        for (int i = 0; i < S::kAltitudeRows; ++i) {
            level_max = std::max(level_max, double(s->level[i][c]));
            level_min = std::min(level_min, double(s->level[i][c]));
            if (i + 1 < S::kAltitudeRows) {
                const double step = slice_row_altitude_m(atm, i + 1) - slice_row_altitude_m(atm, i);
                level_slope = std::max(
                    level_slope, std::abs(double(s->level[i + 1][c]) - s->level[i][c]) / step);
            }
        }
        for (int v = 0; v < S::kViewRows; ++v) {
            double lo = kInfinity, hi = 0.0;
            for (int k = 0; k < S::kAzimuthRows; ++k) {
                const double x = s->shape[v * S::kAzimuthRows + k][c];
                shape_max = std::max(shape_max, x);
                shape_min = std::min(shape_min, x);
                lo = std::min(lo, x);
                hi = std::max(hi, x);
                if (k + 1 < S::kAzimuthRows) {
                    azimuth_slope = std::max(
                        azimuth_slope, std::abs(s->shape[v * S::kAzimuthRows + k + 1][c] - x));
                }
                if (v + 1 < S::kViewRows) {
                    mu_slope = std::max(mu_slope,
                                        std::abs(s->shape[(v + 1) * S::kAzimuthRows + k][c] - x));
                }
            }
            azimuth_range = std::max(azimuth_range, hi - lo);
        }
    }
    if (sa && sb) {
        for (int i = 0; i < S::kAltitudeRows; ++i) {
            level_diff = std::max(level_diff, std::abs(double(sa->level[i][c]) - sb->level[i][c]));
        }
        for (std::size_t i = 0; i < sa->shape.size(); ++i) {
            shape_diff = std::max(shape_diff, std::abs(double(sa->shape[i][c]) - sb->shape[i][c]));
        }
    } else {
        level_diff = level_max;  // the term appears or goes: all of it
        shape_diff = shape_max;
    }
    mu_slope *= 0.5 * (S::kViewRows - 1);          // per unit of the view cosine
    azimuth_slope *= double(S::kAzimuthRows - 1);  // per unit of sin(azimuth / 2)
    const double h_span = std::max(region.h_hi - std::min(a.eye_altitude_m, b.eye_altitude_m),
                                   std::max(a.eye_altitude_m, b.eye_altitude_m) - region.h_lo);
    const double turn = (g.s_min > g.delta ? std::asin(g.delta / g.s_min) : kPi) + g.delta / radius;
    const double sun_sine = std::sqrt(std::max(0.0, 1.0 - region.mu_hi * region.mu_hi));
    // |d sin(phi / 2)| <= |d phi| / 2.
    const double azimuth_turn = region.view.sin_zenith_min > 0.0 && sun_sine > 0.0
                                    ? 0.5 * (turn / region.view.sin_zenith_min + g.alpha / sun_sine)
                                    : kInfinity;
    const double azimuth_change =
        azimuth_slope > 0.0 ? std::min(azimuth_slope * azimuth_turn, azimuth_range) : 0.0;
    const double shape_change = mu_slope * turn + azimuth_change + shape_diff;
    // The nodes move by at most delta / s_min of the segment (and never by more than all of it).
    const double level_change =
        level_slope * (dh + h_span * std::min(1.0, quotient(g.delta, g.s_min))) + level_diff;
    const double magnitude = amplitude * path_max;
    MultipleScatteringChange out;
    out.l_max = magnitude * level_max * shape_max;
    out.absolute = magnitude * (level_change * shape_max + level_max * shape_change);
    out.relative = (level_min > 0.0 ? level_change / level_min : kInfinity) +
                   (shape_min > 0.0 ? shape_change / shape_min : kInfinity);
    return out;
}

}  // namespace aerial::detail::bound
