// The height program's per-frame parameters and its layout (the program text is in
// arb_program_height.cpp; the layout tables in arb_program_height_layout.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "../core/height_constants.hpp"
#include "aerial/phase.hpp"
#include "aerial/scattering.hpp"
#include "arb_program_height_layout.hpp"
#include "arb_program_internal.hpp"

namespace aerial::detail::arb {

using height::kBlockedLogColumn;
using height::kMaxExponent;

std::vector<ParameterRow> height_layout(ArbHeightFidelity fidelity) {
    std::vector<ParameterRow> rows(std::begin(kSharedLayout), std::end(kSharedLayout));
    if (fidelity == ArbHeightFidelity::full || fidelity == ArbHeightFidelity::multiple_scattering) {
        rows.insert(rows.end(), std::begin(kFullLayout), std::end(kFullLayout));
        if (fidelity == ArbHeightFidelity::multiple_scattering) {
            rows.insert(rows.end(), std::begin(kMultipleLayout), std::end(kMultipleLayout));
            rows.insert(rows.end(), kHeightShapeRows - kHeightLevelRows, kLevelRow);
            rows.insert(rows.end(), kHeightMultipleParameterCount - kHeightShapeRows, kShapeRow);
        }
    } else {
        rows.insert(rows.end(), std::begin(kLowerLayout), std::end(kLowerLayout));
    }
    return rows;
}

namespace {

/// The change of the log2 sun column factors (Rayleigh, Mie) per metre of d = vertex - eye, to
/// first order: d lf/d mu at the eye times d mu/d d = (sun - mu0 c/|c|)/|c|, c = eye + R up.
std::array<glm::dvec3, 2> column_slopes(const Frame<float>& frame, bool eye_lit) {
    if (!eye_lit) return {glm::dvec3(0), glm::dvec3(0)};
    const glm::dvec3 up = frame.view.up, sun = frame.view.sun_dir;
    const glm::dvec3 eye = frame.view.eye * frame.view.meters_per_unit;
    const glm::dvec3 c = eye + double(frame.planet_radius_m) * up;
    const double length = glm::length(c);
    const glm::dvec3 zenith = c / length;
    const double mu0 = glm::dot(zenith, sun);
    const glm::dvec3 side = sun - mu0 * zenith;  // the sun's horizontal direction at the eye
    const double side_length = glm::length(side);
    const glm::dvec3 horizontal = side_length > 1e-9 ? side / side_length : glm::dvec3(0);
    // The log factors of a sun at zenith cosine mu (same eye), by the model's own code.
    const auto factors = [&](double mu) {
        Frame<float> f = frame;
        const double m = std::clamp(mu, -1.0, 1.0);
        f.view.sun_dir = m * zenith + std::sqrt(std::max(0.0, 1.0 - m * m)) * horizontal;
        f.sun_dir = glm::vec3(f.view.sun_dir);
        const Frame<float> g = frame_with_eye(f, eye);
        return glm::dvec2(g.eye_log_chapman_rayleigh, g.eye_log_chapman_mie);
    };
    const double step = 1e-3;
    const double lo = std::max(mu0 - step, -1.0), hi = std::min(mu0 + step, 1.0);
    glm::dvec2 derivative = (factors(hi) - factors(lo)) / (hi - lo);
    const glm::dvec2 f_lo = factors(lo), f_hi = factors(hi);
    if (f_lo.x >= kBlockedLogColumn || f_hi.x >= kBlockedLogColumn || f_lo.y >= kBlockedLogColumn ||
        f_hi.y >= kBlockedLogColumn) {
        derivative = glm::dvec2(0);
    }
    const glm::dvec3 dmu = (sun - mu0 * zenith) / length;
    return {kLog2E * derivative.x * dmu, kLog2E * derivative.y * dmu};
}

/// The multiple_scattering level's rows: the frame's slice (zero where it has none, as the CPU
/// model then adds nothing).
void multiple_scattering_parameters(const Frame<float>& frame, double exposure,
                                    std::vector<std::array<double, 4>>& p) {
    using S = MultipleScatteringSlice;
    const double mu_s = frame.eye_cos_sun_zenith;
    p[kHeightZenith] = {frame.eye_zenith.x, frame.eye_zenith.y, frame.eye_zenith.z, mu_s};
    const S* slice = frame.multiple_scattering.get();
    p[kHeightShapeScale] = {std::sqrt(std::max(0.0, 1.0 - mu_s * mu_s)), 0.5 * (S::kViewRows - 1),
                            double(S::kAzimuthRows - 1), slice ? slice->altitude_scale : 0.0};
    for (int c = 0; c < 3; ++c) {
        const double light = kLog2E * kLog2E * exposure;
        p[kHeightMultipleRayleigh][c] = light * frame.rayleigh_scattering[c];
        p[kHeightMultipleMie][c] = light * frame.mie_scattering[c];
    }
    if (!slice) return;
    p[kHeightShapeAltitude] = {slice->shape_inv_knee_m, slice->shape_altitude_scale / kLog2E, 0.0,
                               0.0};
    for (std::size_t i = 0; i < slice->level.size(); ++i) {
        for (int c = 0; c < 3; ++c) p[kHeightLevelRows + i][c] = slice->level[i][c];
    }
    for (std::size_t i = 0; i < slice->shapes.size(); ++i) {
        for (int c = 0; c < 3; ++c) p[kHeightShapeRows + i][c] = slice->shapes[i][c];
    }
}

}  // namespace

Result<std::vector<std::array<float, 4>>> height_parameters(const Frame<float>& frame,
                                                            const Display& display,
                                                            ArbHeightFidelity fidelity) {
    const bool multiple = fidelity == ArbHeightFidelity::multiple_scattering;
    const bool full = fidelity == ArbHeightFidelity::full || multiple;
    const glm::dvec3 up = frame.view.up;
    const glm::dvec3 sun = frame.view.sun_dir;
    const double mpu = frame.view.meters_per_unit;
    const glm::dvec3 eye = frame.view.eye * mpu;  // metres
    const double r = frame.planet_radius_m;
    const double g = frame.mie_g;
    const double exposure = display.exposure;
    const glm::dvec3 centre = eye + r * up;  // from the planet centre to the eye
    const double h0 = frame.eye_altitude_m;

    // The sun column factors at the eye, capped (natural log units).
    // `full` takes them as they are where the sun reaches the eye, and its eyealt.w says whether
    // it does (the model's blocked value is kBlockedLogColumn for both components).
    const bool eye_lit = double(frame.eye_log_chapman_rayleigh) < kBlockedLogColumn &&
                         double(frame.eye_log_chapman_mie) < kBlockedLogColumn;
    const double cap = full ? kBlockedLogColumn : kMaxLogColumnFactor;
    double lf[2] = {std::min(double(frame.eye_log_chapman_rayleigh), cap),
                    std::min(double(frame.eye_log_chapman_mie), cap)};
    if (full && !eye_lit) lf[0] = lf[1] = 0.0;
    // G extinction at the eye without the sag (the model's k_total), for the fitted profile.
    const double beta_g[2] = {std::max(double(frame.rayleigh_scattering.y), 1e-30),
                              std::max(double(frame.mie_extinction.y), 1e-30)};
    const double k0_rayleigh =
        double(frame.rayleigh_scattering.y) * std::exp(-h0 * frame.inv_rayleigh_scale_height);
    const double k0_mie =
        double(frame.mie_extinction.y) * std::exp(-h0 * frame.inv_mie_scale_height);
    const double k0 = k0_rayleigh + k0_mie;
    const double log2_k0 = std::log2(std::max(k0, 1e-300));

    const double sign = g < 0.0 ? -1.0 : 1.0;
    std::vector<std::array<double, 4>> p(multiple ? kHeightMultipleParameterCount
                                         : full   ? kHeightFullParameterCount
                                                  : kHeightParameterCount);
    // d = world * scale - eye: d.w = 0 - (-2^-20), whatever the world position's w.
    p[kHeightEye] = {eye.x, eye.y, eye.z, -kEpsilon};
    p[kHeightScale] = {mpu, mpu, mpu, 0.0};
    p[kHeightSun] = {sign * sun.x, sign * sun.y, sign * sun.z, 0.0};
    p[kHeightCentre] = {2.0 * centre.x, 2.0 * centre.y, 2.0 * centre.z,
                        glm::dot(eye, eye) + 2.0 * r * glm::dot(eye, up)};
    p[kHeightPlanet] = {r * r, r, frame.min_altitude_m, 1.0 / mpu};
    p[kHeightEyeAltitude] = {h0, 1.0 / (12.0 * r), 1.0 / (2.0 * r), full && eye_lit ? 1.0 : 0.0};
    const double inv_r = frame.inv_rayleigh_scale_height, inv_m = frame.inv_mie_scale_height;
    p[kHeightInverseScaleHeights] = {-kLog2E * inv_r, -kLog2E * inv_m, kLog2E * inv_r,
                                     kLog2E * inv_m};
    const double rayleigh_constant = 3.0 / (16.0 * kPi);
    const double mie_constant = (1.0 - g * g) / (4.0 * kPi);
    for (std::size_t c = 0; c < 3; ++c) {
        const int i = static_cast<int>(c);
        // Strictly negative, so that an overflowing column gives -inf, never 0 * inf.
        p[kHeightRayleighExtinction][c] = std::min(-kLog2E * frame.rayleigh_scattering[i], -1e-30);
        p[kHeightMieExtinction][c] = std::min(-kLog2E * frame.mie_extinction[i], -1e-30);
        const double light = kLog2E * kLog2E * exposure * frame.sun_irradiance_top[i];
        p[kHeightRayleigh][c] = light * frame.rayleigh_scattering[i] * rayleigh_constant;
        p[kHeightMie][c] = light * frame.mie_scattering[i] * mie_constant;
    }
    // The G extinction of each component at the eye (log2(e)^2 per metre), for the optical depth
    // of the exact_optical_depth and full levels; in the w of two vectors whose w is otherwise
    // unused.
    p[kHeightRayleigh][3] = kLog2E * kLog2E * k0_rayleigh;
    p[kHeightMie][3] = kLog2E * kLog2E * k0_mie;
    const double abs_g = std::abs(g);
    p[kHeightPhase] = {abs_g, 0.25, (1.0 - abs_g) * (1.0 - abs_g), -1.0};
    p[kHeightSunColumn] = {kLog2E * lf[0], kLog2E * lf[1],
                           std::log2(beta_g[0]) - log2_k0 + kMinFitSlope,
                           std::log2(beta_g[1]) - log2_k0 + kMinFitSlope};
    if (!full) {
        const std::array<glm::dvec3, 2> slope = column_slopes(frame, eye_lit);
        p[kHeightRayleighSlope] = {slope[0].x, slope[0].y, slope[0].z, 0.0};
        p[kHeightMieSlope] = {slope[1].x, slope[1].y, slope[1].z, 0.0};
    }
    if (full) {
        const double hr = frame.rayleigh_scale_height_m, hm = frame.mie_scale_height_m;
        const double root = std::sqrt(0.5 * kPi);
        p[kHeightTrueSun] = {sun.x, sun.y, sun.z, glm::dot(centre, sun)};
        p[kHeightChapmanX] = {1.0 / hr, 1.0 / hm, r / hr, r / hm};
        p[kHeightChapmanH] = {root * hr, root * hm, 2.0 * root * hr, 2.0 * root * hm};
        // The model's k_end takes exp(min(-rise/H_i, kMaxExponent)): the same bound on the exponent
        // of sky.zw's fitted end, log2(beta_i/k0) + eps + (80 - h0/H_i) log2(e).
        p[kHeightFitClamp] = {p[kHeightSunColumn][2] + (kMaxExponent - h0 * inv_r) * kLog2E,
                              p[kHeightSunColumn][3] + (kMaxExponent - h0 * inv_m) * kLog2E, 0.0,
                              0.0};
    }
    if (multiple) multiple_scattering_parameters(frame, exposure, p);
    return to_float_parameters(p);
}

}  // namespace aerial::detail::arb
