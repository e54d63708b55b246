// Internal: the per-frame constants of the SIMD kernels (batch_simd.cpp and its -inl.h files),
// taken from a Frame<float> once per block, target-independent (compiled once).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include <glm/geometric.hpp>

#include "aerial/phase.hpp"
#include "aerial/scattering.hpp"
#include "height_constants.hpp"
#include "height_multiple_scattering.hpp"

namespace aerial::detail::simd {

/// Everything the kernels need from a Frame<float>, computed once per block, in float like the
/// scalar models except where noted.
struct FrameConstants {
    float eye[3], sun[3], up[3];
    float meters_per_unit;
    bool unit_scale;     // meters_per_unit == 1
    float eye_units[3];  // the eye in engine units (View::eye)
    float max_distance_m;
    float max_distance_sq_m2;  // its square: the test on |d|^2, before any square root
    // Phase functions: Rayleigh 3/(16 pi) (1 + c^2); Henyey–Greenstein
    // hg_numerator / base^(3/2), base = hg_a + hg_b (1 - c'), c' = sign(g) c (see Phases).
    float rayleigh_phase_scale;
    float hg_a, hg_b, hg_numerator, hg_one_minus_c_at_sun;
    float hg_peak[3];  // sign(g) sun: the direction of the Henyey–Greenstein peak
    // hoffman-preetham: total extinction per channel (1/m), E_eye.
    float hp_extinction[3], sun_eye[3];
    // -beta_R E_eye 3/(16 pi) / beta_ex and -beta_Ms E_eye hg_numerator / beta_ex (in double; 0
    // where beta_ex is 0): L_in = (1 + c^2, base^(-3/2)) . (these) x expm1(-tau).
    float hp_rayleigh_path[3], hp_mie_path[3];
    // height.
    float rayleigh[3], mie_scattering[3], mie_extinction[3], sun_top[3];
    float radius_m, radius_sq_m2, two_radius_m, inv_two_radius;
    float eye_altitude_m, min_altitude_m;
    float inv_hr, inv_hm, log_hr, log_hm;  // 1/H (1/m), log(H / 1 m)
    float eye_log_chapman_r, eye_log_chapman_m;
    bool eye_lit;
    float k_r0, k_m0, k_total;               // G extinction at the eye per component and total, 1/m
    float k_r0_channel[3], k_m0_channel[3];  // the same per channel
    // in_planet_shadow of eye + d u without cancelling numbers of size R: with c = eye + R up
    // (from the planet centre), along(u) = c.sun + u d.sun and |across(u)|^2 - R^2 =
    // (|A|^2 - R^2) + 2 u A.d + u^2 (|d|^2 - (d.sun)^2), A = c - (c.sun) sun, the two constants
    // taken in double; A.d = A.d_perp since A is across the sun.
    float shadow_along_eye, shadow_excess_eye, shadow_across_eye[3];
    // height's light scattered more than once (height_multiple_scattering.hpp): the eye's
    // zenith, the sun's cosine and sine to it, and the slice's rows per channel (for gathers).
    bool multiple;
    float eye_zenith[3], eye_mu_s, eye_sin_s;
    float ms_altitude_scale, ms_two_radius;
    float ms_level[3][MultipleScatteringSlice::kLevelRows];
    float ms_shape_altitude_scale, ms_shape_inv_knee;
    float ms_shapes[3][MultipleScatteringSlice::kShapeAltitudeRows *
                       MultipleScatteringSlice::kShapeRows];
};

inline FrameConstants make_frame_constants(const Frame<float>& f) {
    FrameConstants k{};
    for (int i = 0; i < 3; ++i) {
        k.eye[i] = f.eye_m[i];
        k.sun[i] = f.sun_dir[i];
        k.up[i] = f.up[i];
        k.hg_peak[i] = f.mie_g < 0.0f ? -f.sun_dir[i] : f.sun_dir[i];
    }
    k.meters_per_unit = f.meters_per_unit;
    k.unit_scale = f.meters_per_unit == 1.0f;
    for (int i = 0; i < 3; ++i) k.eye_units[i] = float(f.view.eye[i]);
    k.max_distance_m = float(kMaxDistanceM);
    k.max_distance_sq_m2 = float(kMaxDistanceM * kMaxDistanceM);
    k.rayleigh_phase_scale = float(3.0 / (16.0 * kPi));
    // From g in double: near |g| = 1, 1 - |g| and 1 - g^2 lose digits in float.
    const double abs_g = std::abs(f.atmosphere.mie_g);
    k.hg_a = float((1.0 - abs_g) * (1.0 - abs_g));
    k.hg_b = float(2.0 * abs_g);
    k.hg_numerator = float((1.0 - abs_g) * (1.0 + abs_g) / (4.0 * kPi));
    k.hg_one_minus_c_at_sun = f.mie_g < 0.0f ? 2.0f : 0.0f;
    for (int c = 0; c < 3; ++c) {
        k.rayleigh[c] = f.rayleigh_scattering[c];
        k.mie_scattering[c] = f.mie_scattering[c];
        k.mie_extinction[c] = f.mie_extinction[c];
        k.sun_top[c] = f.sun_irradiance_top[c];
        k.sun_eye[c] = f.sun_irradiance_eye[c];
        k.hp_extinction[c] = f.rayleigh_scattering[c] + f.mie_extinction[c];
        const double extinction = double(f.rayleigh_scattering[c]) + f.mie_extinction[c];
        const double per_extinction =
            extinction > 0.0 ? -double(f.sun_irradiance_eye[c]) / extinction : 0.0;
        k.hp_rayleigh_path[c] =
            float(3.0 / (16.0 * kPi) * f.rayleigh_scattering[c] * per_extinction);
        k.hp_mie_path[c] = float((1.0 - abs_g) * (1.0 + abs_g) / (4.0 * kPi) * f.mie_scattering[c] *
                                 per_extinction);
    }
    k.radius_m = f.planet_radius_m;
    k.radius_sq_m2 = f.planet_radius_m * f.planet_radius_m;
    k.two_radius_m = 2.0f * f.planet_radius_m;
    k.inv_two_radius = 1.0f / (2.0f * f.planet_radius_m);
    k.eye_altitude_m = f.eye_altitude_m;
    k.min_altitude_m = f.min_altitude_m;
    k.inv_hr = f.inv_rayleigh_scale_height;
    k.inv_hm = f.inv_mie_scale_height;
    k.log_hr = std::log(1.0f / f.inv_rayleigh_scale_height);
    k.log_hm = std::log(1.0f / f.inv_mie_scale_height);
    k.eye_log_chapman_r = f.eye_log_chapman_rayleigh;
    k.eye_log_chapman_m = f.eye_log_chapman_mie;
    k.eye_lit = f.eye_log_chapman_rayleigh < float(height::kBlockedLogColumn);
    k.k_r0 = f.rayleigh_scattering.y * std::exp(-f.eye_altitude_m * f.inv_rayleigh_scale_height);
    k.k_m0 = f.mie_extinction.y * std::exp(-f.eye_altitude_m * f.inv_mie_scale_height);
    k.k_total = k.k_r0 + k.k_m0;
    for (int c = 0; c < 3; ++c) {
        k.k_r0_channel[c] =
            f.rayleigh_scattering[c] * std::exp(-f.eye_altitude_m * f.inv_rayleigh_scale_height);
        k.k_m0_channel[c] =
            f.mie_extinction[c] * std::exp(-f.eye_altitude_m * f.inv_mie_scale_height);
    }
    const double radius = f.atmosphere.planet_radius_m;
    const glm::dvec3 centre_to_eye = glm::dvec3(f.eye_m) + f.view.up * radius;
    const double along_eye = glm::dot(centre_to_eye, f.view.sun_dir);
    const glm::dvec3 across_eye = centre_to_eye - f.view.sun_dir * along_eye;
    k.shadow_along_eye = float(along_eye);
    k.shadow_excess_eye = float(glm::dot(across_eye, across_eye) - radius * radius);
    for (int i = 0; i < 3; ++i) k.shadow_across_eye[i] = float(across_eye[i]);
    k.multiple = f.multiple_scattering != nullptr;
    if (k.multiple) {
        const MultipleScatteringSlice& ms = *f.multiple_scattering;
        for (int i = 0; i < 3; ++i) k.eye_zenith[i] = f.eye_zenith[i];
        k.eye_mu_s = f.eye_cos_sun_zenith;
        k.eye_sin_s = std::sqrt(std::max(0.0f, 1.0f - k.eye_mu_s * k.eye_mu_s));
        k.ms_altitude_scale = ms.altitude_scale;
        k.ms_two_radius = ms.two_radius_m;
        k.ms_shape_altitude_scale = ms.shape_altitude_scale;
        k.ms_shape_inv_knee = ms.shape_inv_knee_m;
        for (int c = 0; c < 3; ++c) {
            for (std::size_t i = 0; i < ms.level.size(); ++i) k.ms_level[c][i] = ms.level[i][c];
            for (std::size_t i = 0; i < ms.shapes.size(); ++i) k.ms_shapes[c][i] = ms.shapes[i][c];
        }
    }
    return k;
}

}  // namespace aerial::detail::simd
