// The skip bound of the height model's higher orders (see cache_bound.hpp and cache.cpp).
#include <algorithm>
#include <cmath>

#include "cache_bound.hpp"
#include "height_multiple_scattering.hpp"

namespace aerial::detail::bound {

namespace {

using S = detail::MultipleScatteringSlice;

/// A span of rows: of `shapes` over altitude, of `level` over the sun's cosine.
struct RowSpan {
    int lo = 0, hi = 0;
};
RowSpan shape_rows(const S& s, double h_lo, double h_hi) {
    const auto row = [&](double h) {
        return std::log1p(std::max(h, 0.0) * s.shape_inv_knee_m) * s.shape_altitude_scale;
    };
    RowSpan r;
    r.lo = std::clamp(int(std::floor(row(h_lo))), 0, S::kShapeAltitudeRows - 1);
    r.hi = std::clamp(int(std::ceil(row(h_hi))), r.lo, S::kShapeAltitudeRows - 1);
    return r;
}

/// What the bound needs of the shape over some altitude rows, one channel: its range, and its
/// largest steps between neighbouring rows of the view cosine, the azimuth and the altitude.
struct ShapeStats {
    double max = 0.0, min = kInfinity;
    double mu_step = 0.0, azimuth_step = 0.0, altitude_step = 0.0;
    double azimuth_range = 0.0;  ///< largest range over the azimuths at one view cosine
};
void add_shape_stats(const S& s, RowSpan rows, int c, ShapeStats& out) {
    for (int r = rows.lo; r <= rows.hi; ++r) {
        const glm::vec3* layer = s.shapes.data() + r * S::kShapeRows;
        for (int v = 0; v < S::kViewRows; ++v) {
            double lo = kInfinity, hi = 0.0;
            for (int k = 0; k < S::kAzimuthRows; ++k) {
                const int i = v * S::kAzimuthRows + k;
                const double x = layer[i][c];
                out.max = std::max(out.max, x);
                out.min = std::min(out.min, x);
                lo = std::min(lo, x);
                hi = std::max(hi, x);
                if (k + 1 < S::kAzimuthRows) {
                    out.azimuth_step = std::max(out.azimuth_step, std::abs(layer[i + 1][c] - x));
                }
                if (v + 1 < S::kViewRows) {
                    out.mu_step =
                        std::max(out.mu_step, std::abs(layer[i + S::kAzimuthRows][c] - x));
                }
                if (r < rows.hi) {
                    out.altitude_step =
                        std::max(out.altitude_step, std::abs(layer[i + S::kShapeRows][c] - x));
                }
            }
            out.azimuth_range = std::max(out.azimuth_range, hi - lo);
        }
    }
}

/// The sun rows of level the region's points can take: those around its sun cosines.
RowSpan sun_rows(const HeightRegion& region) {
    const auto row = [](double mu) {
        return std::acos(std::clamp(mu, -1.0, 1.0)) * (S::kSunRows - 1) / S::kMaxSunZenithRad;
    };
    RowSpan r;  // a higher cosine is a lower row
    r.lo = std::clamp(int(std::floor(row(region.mu_hi))), 0, S::kSunRows - 1);
    r.hi = std::clamp(int(std::ceil(row(region.mu_lo))), r.lo, S::kSunRows - 1);
    return r;
}

/// What the bound needs of level over some sun rows, one channel: its range and its largest
/// slopes over altitude (per m) and over the sun's cosine.
struct LevelStats {
    double max = 0.0, min = kInfinity, altitude_slope = 0.0, sun_slope = 0.0;
};
void add_level_stats(const S& s, const Atmosphere& atm, RowSpan rows, int c, LevelStats& out) {
    for (int k = rows.lo; k <= rows.hi; ++k) {
        // The cosine's step from row k to k + 1 (the rows are even in the angle).
        const double sun_step = std::cos(S::kMaxSunZenithRad * k / (S::kSunRows - 1)) -
                                std::cos(S::kMaxSunZenithRad * (k + 1) / (S::kSunRows - 1));
        for (int i = 0; i < S::kAltitudeRows; ++i) {
            const double x = s.level[k * S::kAltitudeRows + i][c];
            out.max = std::max(out.max, x);
            out.min = std::min(out.min, x);
            if (i + 1 < S::kAltitudeRows) {
                const double step = slice_row_altitude_m(atm, i + 1) - slice_row_altitude_m(atm, i);
                out.altitude_slope =
                    std::max(out.altitude_slope,
                             std::abs(s.level[k * S::kAltitudeRows + i + 1][c] - x) / step);
            }
            if (k < rows.hi) {
                out.sun_slope =
                    std::max(out.sun_slope,
                             std::abs(s.level[(k + 1) * S::kAltitudeRows + i][c] - x) / sun_step);
            }
        }
    }
}

}  // namespace

MultipleScatteringChange multiple_scattering_change(const Frame<double>& a, const Frame<double>& b,
                                                    const Geometry& g, const HeightRegion& region,
                                                    const ShadingKey& key, int c, double path_max,
                                                    double dh) {
    const S* sa = a.multiple_scattering.get();
    const S* sb = b.multiple_scattering.get();
    if (!sa && !sb) return {};
    const Atmosphere& atm = key.atmosphere;
    double amplitude = 0.0;  // sum_i beta_sc,i rho_i,max
    amplitude += atm.rayleigh_scattering[c] * std::exp(-region.h_lo / atm.rayleigh_scale_height_m);
    amplitude += atm.mie_scattering[c] * std::exp(-region.h_lo / atm.mie_scale_height_m);
    double level_diff = 0.0, shape_diff = 0.0;
    LevelStats level;
    ShapeStats shape;
    double altitude_scale = 0.0, knee = kInfinity;  // rows per unit of log(1 + h / knee)
    const double radius = atm.planet_radius_m;
    // The span of altitudes the region's segments reach (their nodes move by at most dh more).
    const double h_lo = std::max(0.0, std::min({region.h_lo, a.eye_altitude_m, b.eye_altitude_m}));
    const double h_hi = std::max({region.h_hi, a.eye_altitude_m, b.eye_altitude_m}) + dh;
    for (const S* s : {sa, sb}) {
        if (!s) continue;
        add_level_stats(*s, atm, sun_rows(region), c, level);
        // Only the altitude rows the shape is taken between: those around the region and the
        // eyes (the shape's altitude is a mean of the nodes' altitudes).
        add_shape_stats(*s, shape_rows(*s, h_lo, h_hi), c, shape);
        altitude_scale = std::max(altitude_scale, double(s->shape_altitude_scale));
        if (s->shape_inv_knee_m > 0.0f) knee = std::min(knee, 1.0 / double(s->shape_inv_knee_m));
    }
    if (sa && sb) {
        // level is the atmosphere's (the same rows in both frames); the shapes are cut per eye.
        const RowSpan rows = shape_rows(*sa, h_lo, h_hi);
        for (int i = rows.lo * S::kShapeRows; i < (rows.hi + 1) * S::kShapeRows; ++i) {
            shape_diff =
                std::max(shape_diff, std::abs(double(sa->shapes[i][c]) - sb->shapes[i][c]));
        }
    } else {
        level_diff = level.max;  // the term appears or goes: all of it
        shape_diff = shape.max;
    }
    const double mu_slope = shape.mu_step * 0.5 * (S::kViewRows - 1);  // per unit view cosine
    const double azimuth_slope = shape.azimuth_step * (S::kAzimuthRows - 1);  // per sin(phi / 2)
    const double h_span = std::max(region.h_hi - std::min(a.eye_altitude_m, b.eye_altitude_m),
                                   std::max(a.eye_altitude_m, b.eye_altitude_m) - region.h_lo);
    const double turn = (g.s_min > g.delta ? std::asin(g.delta / g.s_min) : kPi) + g.delta / radius;
    const double sun_sine = std::sqrt(std::max(0.0, 1.0 - region.mu_hi * region.mu_hi));
    // |d sin(phi / 2)| <= |d phi| / 2.
    const double azimuth_turn = region.view.sin_zenith_min > 0.0 && sun_sine > 0.0
                                    ? 0.5 * (turn / region.view.sin_zenith_min + g.alpha / sun_sine)
                                    : kInfinity;
    const double azimuth_change =
        azimuth_slope > 0.0 ? std::min(azimuth_slope * azimuth_turn, shape.azimuth_range) : 0.0;
    // The nodes move by at most delta / s_min of the segment (and never by more than all of it).
    const double node_move = dh + h_span * std::min(1.0, quotient(g.delta, g.s_min));
    // The shape is taken at the altitude the higher orders come from, a weighted mean of the
    // nodes' altitudes: it moves as they do, on rows even in log(1 + h / knee) (steepest at the
    // lowest altitude).
    const double altitude_change = shape.altitude_step * altitude_scale * node_move / (knee + h_lo);
    const double shape_change = mu_slope * turn + azimuth_change + shape_diff +
                                std::min(altitude_change, shape.max - shape.min);
    // The nodes' sun moves with the sun (alpha) and with the nodes over the curved planet.
    const double sun_move = g.alpha + (g.delta + node_move) / radius;
    const double level_change =
        level.altitude_slope * node_move + level.sun_slope * sun_move + level_diff;
    const double magnitude = amplitude * path_max;
    MultipleScatteringChange out;
    out.l_max = magnitude * level.max * shape.max;
    out.absolute = magnitude * (level_change * shape.max + level.max * shape_change);
    out.relative = (level.min > 0.0 ? level_change / level.min : kInfinity) +
                   (shape.min > 0.0 ? shape_change / shape.min : kInfinity);
    return out;
}

}  // namespace aerial::detail::bound
