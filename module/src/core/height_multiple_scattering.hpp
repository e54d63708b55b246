// Internal: the `height` model's light scattered more than once, per frame (docs/models.md, "The
// height model's higher orders").
//
// The `reference` tabulates J_ms(h, mu_s, view), the radiance per metre that air scatters towards
// the eye from every order n >= 2 (multiple_scattering.hpp). The height model takes a coarser
// table of the same solver, once per atmosphere, and per frame cuts from it what one eye needs:
// J_ms(x, v) ~ beta_s(h) * level(h, mu_s) * shape(h, v), with
//   level(h, mu_s) = the mean over view directions of J_ms / beta_s at altitude h with the sun
//              at zenith cosine mu_s there (E_sun0 included): the multiply scattered radiance
//              per unit scattering coefficient, 16 rows over altitude x 32 over mu_s, computed
//              once per atmosphere;
//   shape(h, v) = J_ms / beta_s / level with the eye's sun, over the view's zenith cosine and
//              its azimuth from the sun (a grid of kViewRows x kAzimuthRows), at 8 altitudes
//              (haze makes the light field more peaked above the ground than at it).
// The model integrates beta_s(h) level(h, mu_s) at its three quadrature nodes (each at its own
// sun, linear between the eye's and the vertex's), as it does the sunlight, and multiplies by
// shape(h, v) once per vertex at the altitude the higher orders come from (the nodes' altitudes
// weighted by their share). The same rows go to the SIMD kernels and the ARB program, so the
// three paths share one table.
#pragma once

#include <array>
#include <memory>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/scattering.hpp"

namespace aerial::detail {

struct MultipleScatteringSlice {
    static constexpr int kAltitudeRows = 16;  ///< evenly spaced in the distance to the horizon
    static constexpr int kSunRows = 32;  ///< sun zenith angles, evenly over [0, kMaxSunZenithRad]
    static constexpr int kLevelRows = kSunRows * kAltitudeRows;
    static constexpr int kViewRows = 17;    ///< view zenith cosines, evenly over [-1, 1]
    static constexpr int kAzimuthRows = 9;  ///< sin(azimuth / 2), evenly over [0, 1]
    /// 108 deg: the end of astronomical twilight, the table's last sun zenith angle (the rows
    /// are the table's own).
    static constexpr double kMaxSunZenithRad = 108.0 * 3.14159265358979323846 / 180.0;

    /// level(h, mu_s) at the rows, level[k * kAltitudeRows + i] for sun row k and altitude row i
    /// (1/sr radiance per unit scattering coefficient, times E_sun0): the same for every frame
    /// of an atmosphere; the model takes it at each point's own sun, which along a long ray
    /// through twilight is not the eye's.
    std::array<glm::vec3, kLevelRows> level{};
    static constexpr int kShapeAltitudeRows = 8;  ///< evenly in log(1 + h / knee), h in [0, top]
    static constexpr int kShapeRows = kViewRows * kAzimuthRows;

    /// shape(h, v): the shape at kShapeAltitudeRows altitudes, shapes[r * kShapeRows + a *
    /// kAzimuthRows + b] (slice_shape_row_altitude_m). The CPU paths take it at the altitude
    /// where a segment's higher orders come from.
    std::array<glm::vec3, kShapeAltitudeRows * kShapeRows> shapes{};
    /// altitude coordinate of `shapes` = log1p(h * shape_inv_knee_m) * shape_altitude_scale:
    /// smooth at the ground (a skip bound needs a finite slope), finer near it where haze
    /// changes the shape fastest.
    float shape_altitude_scale = 0.0f;
    float shape_inv_knee_m = 0.0f;
    /// altitude coordinate = sqrt(h (2 R + h)) * altitude_scale, rows 0 .. kAltitudeRows - 1
    float altitude_scale = 0.0f;
    float two_radius_m = 0.0f;
};

/// The altitude (m) of level row i: rows are evenly spaced in the distance to the horizon, from
/// the ground to the atmosphere's top.
double slice_row_altitude_m(const Atmosphere& atmosphere, int i);

/// The settings of the height model's tables: coarser than the reference's (docs/models.md gives
/// their cost and what the coarseness costs in accuracy).
MultipleScatteringSettings height_table_settings();

/// The slice for an eye with the sun at cosine `eye_cos_sun_zenith` to its
/// zenith; null when the atmosphere scatters nothing. Computes (or finds in the cache) the
/// atmosphere's table: the first frame of an atmosphere costs a fraction of a second.
std::shared_ptr<const MultipleScatteringSlice> multiple_scattering_slice(
    const Atmosphere& atmosphere, double eye_cos_sun_zenith);

/// The cell coordinate and fraction of a value on rows evenly spaced over [lo, hi].
template <class T>
inline void slice_cell(T coordinate, int rows, int& cell, T& fraction) {
    coordinate = coordinate < T(0) ? T(0) : (coordinate > T(rows - 1) ? T(rows - 1) : coordinate);
    cell = int(coordinate);
    if (cell > rows - 2) cell = rows - 2;
    fraction = coordinate - T(cell);
}

/// level(h, mu_s) for an altitude (m) and the sun's zenith cosine there, bilinear between rows.
template <class T>
glm::vec<3, T> slice_level(const MultipleScatteringSlice& s, T altitude_m, T mu_s);

/// shape(h, v) at altitude h (m) for a view cosine mu_v to the eye's zenith and the cosine of its
/// azimuth from the sun: trilinear between the rows.
template <class T>
glm::vec<3, T> slice_shape(const MultipleScatteringSlice& s, T altitude_m, T mu_v, T cos_azimuth);

/// The altitude (m) of row r of MultipleScatteringSlice::shapes.
double slice_shape_row_altitude_m(const Atmosphere& atmosphere, int r);

}  // namespace aerial::detail
