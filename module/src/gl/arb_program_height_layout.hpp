// Internal: the height program's parameter indices and layout tables (the one source of truth of
// its parameters: the program text declares them from these rows, arb_parameter_layout reports
// them, height_parameters fills them) and the constants the text and the parameters share.
#pragma once

#include <iterator>

#include "../core/height_multiple_scattering.hpp"
#include "arb_program_internal.hpp"

namespace aerial::detail::arb {

/// Indices of the height program's parameters, relative to parameter_base: the rows of the
/// layout tables below (kSharedLayout, then kLowerLayout or kFullLayout).
enum HeightParameterIndex {
    kHeightEye,
    kHeightScale,
    kHeightSun,
    kHeightCentre,
    kHeightPlanet,
    kHeightEyeAltitude,
    kHeightInverseScaleHeights,
    kHeightRayleighExtinction,
    kHeightMieExtinction,
    kHeightRayleigh,
    kHeightMie,
    kHeightPhase,
    kHeightSunColumn,
    kHeightSharedCount,
    // spec_minimum and exact_optical_depth:
    kHeightRayleighSlope = kHeightSharedCount,
    kHeightMieSlope,
    kHeightParameterCount,
    // full:
    kHeightTrueSun = kHeightSharedCount,
    kHeightChapmanX,
    kHeightChapmanH,
    kHeightFitClamp,
    kHeightFullParameterCount,
    // multiple_scattering: full's, then these, then the arrays lev and shp.
    kHeightZenith = kHeightFullParameterCount,
    kHeightShapeScale,
    kHeightMultipleRayleigh,
    kHeightMultipleMie,
    kHeightShapeAltitude,
    kHeightLevelRows,
    kHeightShapeRows = kHeightLevelRows + MultipleScatteringSlice::kLevelRows,
    kHeightMultipleParameterCount = kHeightShapeRows + MultipleScatteringSlice::kShapeAltitudeRows *
                                                           MultipleScatteringSlice::kShapeRows
};

/// The layout of every level (lengths in metres, log2 the base-2 logarithm, c = eye + R up
/// from the planet centre to the eye, h0 the eye's altitude, G the channel of the quadrature).
inline constexpr ParameterRow kSharedLayout[] = {
    {"eye", "xyz: eye (m, View::eye * meters_per_unit); w: -2^-20 (so that d.w = 2^-20)"},
    {"scale", "(meters_per_unit x3, 0)"},
    {"sun", "xyz: sun_dir (towards the sun), negated when g < 0; w: 0"},
    {"centre", "xyz: 2 c; w: |eye|^2 + 2 R eye.up (m^2)"},
    {"planet", "(R^2, R, frame.min_altitude_m, 1 / meters_per_unit)"},
    {"eyealt", "(h0, 1/(12 R), 1/(2 R), w): w = 1 if the sun reaches the eye (read by full)"},
    {"inv", "log2(e) (-1/H_R, -1/H_M, 1/H_R, 1/H_M)"},
    {"extr", "xyz: -log2(e) beta_R (<= -1e-30); w: 0"},
    {"extm", "xyz: -log2(e) beta_M,extinction (<= -1e-30); w: 0"},
    {"ray", "xyz: log2(e)^2 exposure E_sun0 beta_R 3/(16 pi); w: log2(e)^2 k_R,G(h0) (exact on)"},
    {"mie", "xyz: log2(e)^2 exposure E_sun0 beta_M (1-g^2)/(4 pi); w: log2(e)^2 k_M,G(h0) (same)"},
    {"hg", "(|g|, 1/4, (1 - |g|)^2, -1)"},
    {"sky",
     "xy: log2(e) eye's log Chapman factors (R, M; capped at 40 log2(e) below full, for "
     "full 0 where the eye's sun is blocked); zw: log2(beta_i,G / k_G(h0)) + 2^-10"},
};
/// spec_minimum and exact_optical_depth: the sun columns' change along the segment.
inline constexpr ParameterRow kLowerLayout[] = {
    {"slr", "xyz: gradient of sky.x along d = vertex - eye at the eye, per m (0 if blocked); w: 0"},
    {"slm", "xyz: the same for sky.y (Mie); w: 0"},
};
/// full: the sun's column factors at the vertex.
inline constexpr ParameterRow kFullLayout[] = {
    {"sunc", "xyz: sun_dir (not negated); w: c.sun_dir (m)"},
    {"chx", "(1/H_R, 1/H_M, R/H_R, R/H_M): x = (R + h)/H at altitude h"},
    {"chh", "(1, 1, 2, 2) sqrt(pi/2) (H_R, H_M, H_R, H_M) (m)"},
    {"fitc", "xy: sky.zw + (80 - h0/H_i) log2(e), the bound e^80 on the fit's end; zw: 0"},
};
/// multiple_scattering: the slice of the light scattered more than once
/// (core/height_multiple_scattering.hpp), and its scale.
inline constexpr ParameterRow kMultipleLayout[] = {
    {"msz", "xyz: the eye's unit zenith; w: the sun's cosine to it"},
    {"mss",
     "(sun's sine to the eye's zenith, (view rows - 1)/2, azimuth rows - 1, altitude "
     "rows per m of sqrt(h (2 R + h)))"},
    {"msr", "xyz: log2(e)^2 exposure beta_R; w: 0"},
    {"msm", "xyz: log2(e)^2 exposure beta_M (scattering); w: 0"},
    {"msq",
     "(1 / knee (1/m), ln 2 x shape altitude rows per unit of log(1 + h / knee), 0, 0): the "
     "shape's altitude rows"},
};
/// The arrays after them: one row per table entry.
inline constexpr ParameterRow kLevelRow = {
    "lev",
    "xyz: level(h, mu_s) at sun row i / altitude rows, altitude row i % altitude rows; w: 0"};
inline constexpr ParameterRow kShapeRow = {
    "shp",
    "xyz: shape at altitude row i / (view rows x azimuth rows), view row (i / azimuth rows) % view "
    "rows, azimuth row i % azimuth rows; w: 0"};
// sky.xy's cap: a blocked sun becomes a column of e^40 H_i exp(-h/H_i), out up to 100 km.
// slr, slm: d lf_i/d mu at the eye (the model's own factors, a central difference) times
// d mu/d d = (sun - mu0 c/|c|)/|c| (column_slopes).
static_assert(std::size(kSharedLayout) == kHeightSharedCount &&
                  kHeightSharedCount + std::size(kLowerLayout) == kHeightParameterCount &&
                  kHeightSharedCount + std::size(kFullLayout) == kHeightFullParameterCount,
              "the layout tables and the indices disagree");
static_assert(kHeightParameterCount == kArbHeightParameterCount, "layout and count disagree");
static_assert(kHeightFullParameterCount == kArbHeightFullParameterCount,
              "layout and count disagree");
static_assert(kHeightFullParameterCount + std::size(kMultipleLayout) == kHeightLevelRows &&
                  kHeightMultipleParameterCount == kArbHeightMultipleParameterCount,
              "layout and count disagree");

/// The slope b of the fitted extinction profile (log2 units over the segment) is kept at least
/// this far from 0, where the node placement would divide 0 by 0; a shift this small moves the
/// nodes by < 1e-3 of the segment.
inline constexpr double kMinFitSlope = 1.0 / 1024.0;
/// Below this log factor (natural units) the sun column at the eye is used as it is; a blocked sun
/// (factor >= 80) or a larger one is capped here: e^(40 + 40) still fits a float, and a column of
/// e^40 H_i exp(-h/H_i) puts the sun out up to 100 km.
inline constexpr double kMaxLogColumnFactor = 40.0;

}  // namespace aerial::detail::arb
