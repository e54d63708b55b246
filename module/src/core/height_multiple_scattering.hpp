// Internal: the `height` model's light scattered more than once, per frame (docs/models.md, "The
// height model's higher orders").
//
// The `reference` tabulates J_ms(h, mu_s, view), the radiance per metre that air scatters towards
// the eye from every order n >= 2 (multiple_scattering.hpp). The height model takes a coarser
// table of the same solver, once per atmosphere, and per frame cuts from it what one eye needs:
// J_ms(x, v) ~ beta_s(h) * level(h) * shape(v), with
//   level(h) = the mean over view directions of J_ms / beta_s at altitude h, at the eye's sun
//              zenith angle (E_sun0 included): the multiply scattered radiance per unit
//              scattering coefficient, 16 rows over altitude;
//   shape(v) = J_ms / beta_s / level at the eye, over the view's zenith cosine and its azimuth
//              from the sun (a grid of kViewRows x kAzimuthRows): exact at the eye.
// The model integrates beta_s(h) level(h) at its three quadrature nodes, as it does the sunlight,
// and multiplies by shape(v) once per vertex. The same rows go to the SIMD kernels and the ARB
// program, so the three paths share one table.
#pragma once

#include <array>
#include <memory>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/scattering.hpp"

namespace aerial::detail {

struct MultipleScatteringSlice {
    static constexpr int kAltitudeRows = 16;  ///< evenly spaced in the distance to the horizon
    static constexpr int kViewRows = 17;      ///< view zenith cosines, evenly over [-1, 1]
    static constexpr int kAzimuthRows = 9;    ///< sin(azimuth / 2), evenly over [0, 1]

    /// level(h) at the rows (1/sr radiance per unit scattering coefficient, times E_sun0).
    std::array<glm::vec3, kAltitudeRows> level{};
    /// shape(v), row-major in the view cosine: shape[a * kAzimuthRows + b].
    std::array<glm::vec3, kViewRows * kAzimuthRows> shape{};
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

/// The slice for an eye at `eye_altitude_m` with the sun at cosine `eye_cos_sun_zenith` to its
/// zenith; null when the atmosphere scatters nothing. Computes (or finds in the cache) the
/// atmosphere's table: the first frame of an atmosphere costs a fraction of a second.
std::shared_ptr<const MultipleScatteringSlice> multiple_scattering_slice(
    const Atmosphere& atmosphere, double eye_altitude_m, double eye_cos_sun_zenith);

/// The cell coordinate and fraction of a value on rows evenly spaced over [lo, hi].
template <class T>
inline void slice_cell(T coordinate, int rows, int& cell, T& fraction) {
    coordinate = coordinate < T(0) ? T(0) : (coordinate > T(rows - 1) ? T(rows - 1) : coordinate);
    cell = int(coordinate);
    if (cell > rows - 2) cell = rows - 2;
    fraction = coordinate - T(cell);
}

/// level(h), linear between rows.
template <class T>
glm::vec<3, T> slice_level(const MultipleScatteringSlice& s, T altitude_m);

/// shape(v) for a view cosine mu_v to the eye's zenith and the cosine of its azimuth from the sun.
template <class T>
glm::vec<3, T> slice_shape(const MultipleScatteringSlice& s, T mu_v, T cos_azimuth);

}  // namespace aerial::detail
