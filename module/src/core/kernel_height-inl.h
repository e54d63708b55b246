// Internal, per SIMD target (Highway's -inl.h convention): the height model's kernel, the
// vector form of height_model() in scattering.cpp (the same constants: height_constants.hpp).
// Every branch of the scalar model is a mask here; uniform per-frame decisions stay `if`s.
#if defined(AERIAL_CORE_KERNEL_HEIGHT_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AERIAL_CORE_KERNEL_HEIGHT_INL_H_
#undef AERIAL_CORE_KERNEL_HEIGHT_INL_H_
#else
#define AERIAL_CORE_KERNEL_HEIGHT_INL_H_
#endif

#include <cstddef>
#include <limits>

#include <hwy/highway.h>

#include "batch_kernels.hpp"
#include "height_constants.hpp"
#include "simd_blocks-inl.h"
#include "simd_frame_constants.hpp"
#include "simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aerial::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using simd::FrameConstants;

/// Scaled position, offset from the eye and distance; invalid lanes (NaN, Inf, farther than
/// kMaxDistanceM) are moved onto the eye so that nothing downstream sees a NaN.
struct Segment {
    VF px, py, pz, dx, dy, dz, s;
    MF valid;
};

HWY_INLINE Segment MakeSegment(const FrameConstants& k, VF x, VF y, VF z) {
    const VF scale = K(k.meters_per_unit);
    const VF ex = K(k.eye[0]), ey = K(k.eye[1]), ez = K(k.eye[2]);
    const VF px = hn::Mul(x, scale), py = hn::Mul(y, scale), pz = hn::Mul(z, scale);
    const VF dx = hn::Sub(px, ex), dy = hn::Sub(py, ey), dz = hn::Sub(pz, ez);
    const VF s = hn::Sqrt(Dot(dx, dy, dz, dx, dy, dz));
    const MF valid = hn::Le(s, K(k.max_distance_m));  // false for NaN
    return Segment{hn::IfThenElse(valid, px, ex), hn::IfThenElse(valid, py, ey),
                   hn::IfThenElse(valid, pz, ez), hn::IfThenElseZero(valid, dx),
                   hn::IfThenElseZero(valid, dy), hn::IfThenElseZero(valid, dz),
                   hn::IfThenElseZero(valid, s),  valid};
}

/// Both phase functions (phase.hpp) of cos_theta = dot(d, sun) / s (1 at s = 0). The
/// Henyey–Greenstein base 1 + g^2 - 2 g cos_theta is written (1 - |g|)^2 + 2 |g| (1 - c') with
/// c' = sign(g) cos_theta, stable at either peak (phase.hpp's form cancels at the backward peak
/// when g < 0), and 1 - c' comes from the chord |d/s - sign(g) sun|^2 / 2, whose error shrinks
/// with the angle (1 - float(cos_theta) is off by 1e-7, 10 % of the base at |g| = 0.999).
template <class M>
HWY_INLINE void Phases(const FrameConstants& k, VF dx, VF dy, VF dz, VF s, VF& rayleigh, VF& mie) {
    const MF positive = hn::Gt(s, hn::Zero(DF()));
    const VF inv_s = M::Reciprocal(hn::IfThenElse(positive, s, K(1.0f)));
    const VF cx = hn::MulSub(dx, inv_s, K(k.hg_peak[0]));
    const VF cy = hn::MulSub(dy, inv_s, K(k.hg_peak[1]));
    const VF cz = hn::MulSub(dz, inv_s, K(k.hg_peak[2]));
    // At s = 0 the direction is the sun's: 1 - c' = 1 - sign(g).
    const VF one_minus_c =
        hn::IfThenElse(positive, Clamp(hn::Mul(Dot(cx, cy, cz, cx, cy, cz), K(0.5f)), 0.0f, 2.0f),
                       K(k.hg_one_minus_c_at_sun));
    const VF c = hn::Sub(K(1.0f), one_minus_c);  // +-cos_theta: the Rayleigh phase needs c^2
    rayleigh = hn::Mul(K(k.rayleigh_phase_scale), hn::MulAdd(c, c, K(1.0f)));
    const VF base = hn::MulAdd(K(k.hg_b), one_minus_c, K(k.hg_a));
    mie = hn::Mul(K(k.hg_numerator), M::InversePow32(base));
}

// ---- height -----------------------------------------------------------------------------------

/// The height model's constants (height_constants.hpp) in float.
constexpr float kBlockedLogColumn = float(height::kBlockedLogColumn);
constexpr float kMaxExponent = float(height::kMaxExponent);
constexpr float kMaxFitSlope = float(height::kMaxFitSlope);
constexpr float kLinearFitLimit = float(height::kLinearFitLimit);
constexpr float kLinearDepthLimit = float(height::kLinearDepthLimit);
constexpr float kMeanSagFraction = float(height::kMeanSagFraction);
constexpr float kSqrtHalfPi = float(height::kSqrtHalfPi);
constexpr float kMinChapmanFactor = float(height::kMinChapmanFactor);

/// log_chapman_factor of scattering.cpp for both components at once (they share the geometry):
/// log(H Ch) at altitude h (already clamped to min_altitude) for a sun at cosine mu to the local
/// zenith; kBlockedLogColumn where the planet blocks the sun.
template <class M>
HWY_INLINE void LogChapmanFactors(const FrameConstants& k, VF h, VF cos_zenith, VF& log_r,
                                  VF& log_m) {
    constexpr float kSqrtHalf = 0.70710678118654752440f;
    const VF mu = Clamp(cos_zenith, -1.0f, 1.0f);
    const VF abs_mu = hn::Abs(mu);
    const VF r_plus_h = hn::Add(K(k.radius_m), h);
    // log(upward) = log(sqrt(pi/2) sqrt(x) erfcx(sqrt(x/2) |mu|)), x = (R + h) / H.
    auto log_upward = [&](float inv_h) {
        const VF root_x = hn::Sqrt(hn::Max(hn::Mul(r_plus_h, K(inv_h)), hn::Zero(DF())));
        const VF t = ErfcxT(hn::Mul(hn::Mul(root_x, K(kSqrtHalf)), abs_mu));
        return hn::Add(SafeLog<M>(hn::Mul(hn::Mul(K(kSqrtHalfPi), root_x), t)), ErfcxLogPoly(t));
    };
    const VF up_r = log_upward(k.inv_hr);
    const VF up_m = log_upward(k.inv_hm);
    log_r = hn::Add(up_r, K(k.log_hr));
    log_m = hn::Add(up_m, K(k.log_hm));
    const MF below = hn::Lt(mu, hn::Zero(DF()));
    if (HWY_LIKELY(hn::AllFalse(DF(), below))) return;

    // Below the horizon: 2 Ch(x_t, 90 deg) exp((h - h_t)/H) - Ch(x, 180 deg - chi), relative to
    // exp(-h/H), with h_t the tangent altitude; blocked when h_t is under the shadow floor.
    const VF mu2 = hn::Mul(mu, mu);
    const VF sin_chi = hn::Sqrt(hn::Max(hn::Sub(K(1.0f), mu2), hn::Zero(DF())));
    const VF tangent = hn::Sub(hn::Mul(h, sin_chi),
                               hn::Div(hn::Mul(K(k.radius_m), mu2), hn::Add(K(1.0f), sin_chi)));
    const MF blocked = hn::Lt(tangent, hn::Min(h, hn::Zero(DF())));
    const VF drop = hn::Sub(h, tangent);
    const VF r_plus_tangent = hn::Add(K(k.radius_m), tangent);
    auto below_factor = [&](VF log_up, float inv_h, float log_h) {
        const VF rise = hn::Mul(drop, K(inv_h));
        const VF horizontal = hn::Mul(
            K(kSqrtHalfPi), hn::Sqrt(hn::Max(hn::Mul(r_plus_tangent, K(inv_h)), hn::Zero(DF()))));
        const VF factor =
            hn::Max(hn::Sub(hn::Add(horizontal, horizontal), M::Exp(hn::Sub(log_up, rise))),
                    K(kMinChapmanFactor));
        const VF value =
            hn::Min(hn::Add(hn::Add(rise, K(log_h)), M::Log(factor)), K(kBlockedLogColumn));
        return hn::IfThenElse(blocked, K(kBlockedLogColumn), value);
    };
    log_r = hn::IfThenElse(below, below_factor(up_r, k.inv_hr, k.log_hr), log_r);
    log_m = hn::IfThenElse(below, below_factor(up_m, k.inv_hm, k.log_hm), log_m);
}

/// transmittance_from_log_factors: sun transmittance per channel at altitude h.
template <class M>
HWY_INLINE void Transmittance(const FrameConstants& k, VF h, VF log_r, VF log_m, VF (&t)[3]) {
    const MF blocked =
        hn::Or(hn::Ge(log_r, K(kBlockedLogColumn)), hn::Ge(log_m, K(kBlockedLogColumn)));
    const VF column_r = M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hr), log_r), K(kMaxExponent)));
    const VF column_m = M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hm), log_m), K(kMaxExponent)));
    for (int c = 0; c < 3; ++c) {
        const VF tau =
            hn::MulAdd(K(k.rayleigh[c]), column_r, hn::Mul(K(k.mie_extinction[c]), column_m));
        t[c] = hn::IfThenZeroElse(blocked, M::Exp(hn::Neg(tau)));
    }
}

/// The altitudes along one vector of segments: h0 at the eye, h1 at the vertex (clamped like the
/// density), rise = h1 - h0, the sag s^2 / (2 R) and h_low, the altitude of the path-averaged
/// density (lowered by the mean sag).
struct HeightProfile {
    VF h0, h1, rise, sag, h_low, min_h;
};

HWY_INLINE HeightProfile MakeHeightProfile(const FrameConstants& k, const Segment& seg) {
    const VF zero = hn::Zero(DF());
    const VF s = seg.s;
    const VF min_h = K(k.min_altitude_m);
    const VF h0 = K(k.eye_altitude_m);
    // Altitude of the vertex above the sphere (altitude_above_sphere).
    const VF along_up = Dot(seg.px, seg.py, seg.pz, K(k.up[0]), K(k.up[1]), K(k.up[2]));
    const VF numerator = hn::MulAdd(K(k.two_radius_m), along_up,
                                    Dot(seg.px, seg.py, seg.pz, seg.px, seg.py, seg.pz));
    const VF to_centre = hn::Sqrt(hn::Max(hn::Add(numerator, K(k.radius_sq_m2)), zero));
    const VF h1 = hn::Max(hn::Div(numerator, hn::Add(to_centre, K(k.radius_m))), min_h);
    const VF rise = hn::Sub(h1, h0);
    const VF sag = hn::Mul(hn::Mul(s, s), K(k.inv_two_radius));
    const VF h_low = hn::Max(hn::NegMulAdd(sag, K(kMeanSagFraction), hn::Min(h0, h1)), min_h);
    return HeightProfile{h0, h1, rise, sag, h_low, min_h};
}

/// The log Chapman factors of the segment's ends as the quadrature interpolates them (a blocked
/// end borrows the other end's), and the lanes where the sun reaches either end.
struct EndFactors {
    VF lr0, lm0, lr1, lm1;
    MF active;
    VF mu1;  ///< the sun's zenith cosine at the vertex
};

// ---- The light scattered more than once (height_multiple_scattering.hpp) ----------------------

/// Splits coordinates into cells [0, rows - 2] and fractions (slice_cell).
HWY_INLINE VF SliceCell(VF coordinate, int rows, VF& fraction) {
    const VF clamped = Clamp(coordinate, 0.0f, float(rows - 1));
    const VF cell = hn::Min(hn::Floor(clamped), K(float(rows - 2)));
    fraction = hn::Sub(clamped, cell);
    return cell;
}

/// level(h, mu_s) per channel (slice_level).
HWY_INLINE void SliceLevel(const FrameConstants& k, VF h, VF mu_s, VF (&level)[3]) {
    using S = MultipleScatteringSlice;
    const DF d;
    const DI di;
    const VF above = hn::Max(h, hn::Zero(d));
    const VF rho = hn::Sqrt(hn::Mul(above, hn::Add(K(k.ms_two_radius), above)));
    VF f, g;
    const VF i = SliceCell(hn::Mul(rho, K(k.ms_altitude_scale)), S::kAltitudeRows, f);
    const VF row = SliceCell(hn::Mul(hn::Acos(d, Clamp(mu_s, -1.0f, 1.0f)),
                                     K(float((S::kSunRows - 1) / S::kMaxSunZenithRad))),
                             S::kSunRows, g);
    const hn::Vec<DI> i00 = hn::ConvertTo(di, hn::MulAdd(row, K(float(S::kAltitudeRows)), i));
    const hn::Vec<DI> i01 = hn::Add(i00, hn::Set(di, 1));
    const hn::Vec<DI> i10 = hn::Add(i00, hn::Set(di, S::kAltitudeRows));
    const hn::Vec<DI> i11 = hn::Add(i10, hn::Set(di, 1));
    for (int c = 0; c < 3; ++c) {
        const float* rows = k.ms_level[c];
        const VF v00 = hn::GatherIndex(d, rows, i00), v01 = hn::GatherIndex(d, rows, i01);
        const VF v10 = hn::GatherIndex(d, rows, i10), v11 = hn::GatherIndex(d, rows, i11);
        const VF lo = hn::MulAdd(hn::Sub(v01, v00), f, v00);
        const VF hi = hn::MulAdd(hn::Sub(v11, v10), f, v10);
        level[c] = hn::MulAdd(hn::Sub(hi, lo), g, lo);
    }
}

/// The quadrature's sums of the light scattered more than once: per component and channel, and
/// the altitude the G channel's share comes from (its weighted sum of the nodes' altitudes).
struct MultipleSums {
    VF r[3], m[3];
    VF weight, altitude;
};

/// shape(h, v) per channel at the altitude h for the view along the segment
/// (multiple_scattering_shape).
template <class M>
HWY_INLINE void SliceShape(const FrameConstants& k, const Segment& seg, VF altitude,
                           VF (&shape)[3]) {
    using S = MultipleScatteringSlice;
    const DF d;
    const DI di;
    const MF positive = hn::Gt(seg.s, hn::Zero(d));
    const VF inv_s = hn::Div(K(1.0f), hn::IfThenElse(positive, seg.s, K(1.0f)));
    const VF mu_v = hn::IfThenElse(positive,
                                   Clamp(hn::Mul(Dot(seg.dx, seg.dy, seg.dz, K(k.eye_zenith[0]),
                                                     K(k.eye_zenith[1]), K(k.eye_zenith[2])),
                                                 inv_s),
                                         -1.0f, 1.0f),
                                   K(1.0f));
    const VF cos_theta = hn::IfThenElse(
        positive,
        hn::Mul(Dot(seg.dx, seg.dy, seg.dz, K(k.sun[0]), K(k.sun[1]), K(k.sun[2])), inv_s),
        K(1.0f));
    const VF across =
        hn::Mul(hn::Sqrt(hn::Max(hn::NegMulAdd(mu_v, mu_v, K(1.0f)), hn::Zero(d))), K(k.eye_sin_s));
    const MF wide = hn::Gt(across, K(1e-6f));
    const VF cos_azimuth =
        hn::IfThenElse(wide,
                       Clamp(hn::Div(hn::NegMulAdd(mu_v, K(k.eye_mu_s), cos_theta),
                                     hn::IfThenElse(wide, across, K(1.0f))),
                             -1.0f, 1.0f),
                       K(1.0f));
    const VF sin_half =
        hn::Sqrt(hn::Max(hn::Mul(hn::Sub(K(1.0f), cos_azimuth), K(0.5f)), hn::Zero(d)));
    VF fa, fb;
    const VF a =
        SliceCell(hn::Mul(hn::Add(mu_v, K(1.0f)), K(0.5f * (S::kViewRows - 1))), S::kViewRows, fa);
    const VF b = SliceCell(hn::Mul(sin_half, K(float(S::kAzimuthRows - 1))), S::kAzimuthRows, fb);
    VF fr;
    const VF r =
        SliceCell(hn::Mul(M::Log1p(hn::Mul(hn::Max(altitude, hn::Zero(d)), K(k.ms_shape_inv_knee))),
                          K(k.ms_shape_altitude_scale)),
                  S::kShapeAltitudeRows, fr);
    const hn::Vec<DI> i00 = hn::ConvertTo(
        di, hn::MulAdd(r, K(float(S::kShapeRows)), hn::MulAdd(a, K(float(S::kAzimuthRows)), b)));
    const hn::Vec<DI> one = hn::Set(di, 1), next_row = hn::Set(di, S::kAzimuthRows);
    const hn::Vec<DI> next_layer = hn::Set(di, S::kShapeRows);
    for (int c = 0; c < 3; ++c) {
        const float* rows = k.ms_shapes[c];
        // Bilinear in (view cosine, azimuth) on one altitude layer.
        const auto plane = [&](hn::Vec<DI> base) {
            const hn::Vec<DI> i10 = hn::Add(base, next_row);
            const VF v00 = hn::GatherIndex(d, rows, base);
            const VF v01 = hn::GatherIndex(d, rows, hn::Add(base, one));
            const VF v10 = hn::GatherIndex(d, rows, i10);
            const VF v11 = hn::GatherIndex(d, rows, hn::Add(i10, one));
            const VF lo = hn::MulAdd(hn::Sub(v01, v00), fb, v00);
            const VF hi = hn::MulAdd(hn::Sub(v11, v10), fb, v10);
            return hn::MulAdd(hn::Sub(hi, lo), fa, lo);
        };
        const VF below = plane(i00), above = plane(hn::Add(i00, next_layer));
        shape[c] = hn::MulAdd(hn::Sub(above, below), fr, below);
    }
}

/// The quadrature of the sunlight scattered towards the eye (height_model's sunlit[]): 3 Gauss
/// nodes in the share of the G attenuation, mapped to u through the one-exponential fit of the
/// extinction profile, each weighted by the density, the exact over the fitted attenuation and
/// the sun transmittance there, and tested against the planet's shadow. Adds to sunlit_r and
/// sunlit_m (per channel).
template <class M>
HWY_INLINE void SunlitSums(const FrameConstants& k, const Segment& seg, const HeightProfile& p,
                           const EndFactors& ends, VF (&sunlit_r)[3], VF (&sunlit_m)[3],
                           MultipleSums& multiple) {
    const VF zero = hn::Zero(DF());
    const VF s = seg.s;
    const VF k_r0 = K(k.k_r0), k_m0 = K(k.k_m0);
    const VF a_r = hn::Mul(p.rise, K(k.inv_hr));
    const VF a_m = hn::Mul(p.rise, K(k.inv_hm));
    // G optical depth to the vertex and the extinction there, relative to the eye's.
    const VF z_r = hn::Min(hn::Neg(a_r), K(kMaxExponent));
    const VF z_m = hn::Min(hn::Neg(a_m), K(kMaxExponent));
    const VF exp_r = M::Exp(z_r), exp_m = M::Exp(z_m);
    const VF tau_total =
        hn::Mul(s, hn::MulAdd(k_r0, ExpAverageFrom(z_r, Expm1GivenExp(z_r, exp_r)),
                              hn::Mul(k_m0, ExpAverageFrom(z_m, Expm1GivenExp(z_m, exp_m)))));
    const VF k_end = hn::MulAdd(k_r0, exp_r, hn::Mul(k_m0, exp_m));
    const VF a_fit = Clamp(hn::IfThenElse(hn::Gt(k_end, zero),
                                          SafeLog<M>(hn::Min(hn::Div(K(k.k_total), k_end),
                                                             K(std::numeric_limits<float>::max()))),
                                          K(kMaxFitSlope)),
                           -kMaxFitSlope, kMaxFitSlope);
    // log_one_minus_exp_over_x(a_fit) + log_one_minus_exp_over_x(tau_total), as one log.
    const VF expm1_fit = Expm1<M>(hn::Neg(a_fit));
    const VF expm1_total = Expm1<M>(hn::Neg(tau_total));
    const VF log_scale = SafeLog<M>(hn::Mul(ExpAverageFrom(hn::Neg(a_fit), expm1_fit),
                                            ExpAverageFrom(hn::Neg(tau_total), expm1_total)));
    // Where tau_total < kLinearDepthLimit the fitted depth is linear in the node and the fraction
    // is the node itself; elsewhere 1 / tau_total is safe (it overflows for subnormals).
    const MF total_small = hn::Lt(tau_total, K(kLinearDepthLimit));
    const VF inv_total = hn::Div(K(1.0f), hn::Max(tau_total, K(kLinearDepthLimit)));
    const MF fit_small = hn::Lt(hn::Abs(a_fit), K(kLinearFitLimit));
    const VF inv_fit = hn::Div(K(1.0f), hn::IfThenElse(fit_small, K(1.0f), a_fit));
    // in_planet_shadow along the segment (FrameConstants::shadow_*), with the part of d
    // across the sun taken as a vector: |d|^2 - (d.sun)^2 cancels when d is along it.
    const VF sun_x = K(k.sun[0]), sun_y = K(k.sun[1]), sun_z = K(k.sun[2]);
    const VF d_sun = Dot(seg.dx, seg.dy, seg.dz, sun_x, sun_y, sun_z);
    const VF px = hn::NegMulAdd(sun_x, d_sun, seg.dx);
    const VF py = hn::NegMulAdd(sun_y, d_sun, seg.dy);
    const VF pz = hn::NegMulAdd(sun_z, d_sun, seg.dz);
    const VF perpendicular_sq = Dot(px, py, pz, px, py, pz);
    const VF across_d = hn::Mul(K(2.0f), Dot(px, py, pz, K(k.shadow_across_eye[0]),
                                             K(k.shadow_across_eye[1]), K(k.shadow_across_eye[2])));
    for (int n = 0; n < 3; ++n) {
        const VF node = K(float(height::kSunNodes[n]));
        // Fitted optical depth to the node, the fraction of the total, and the u where
        // the one-exponential fit reaches it (exponential_quantile).
        const VF tau_fit = hn::IfThenElse(total_small, hn::Mul(node, tau_total),
                                          hn::Neg(M::Log1p(hn::Mul(node, expm1_total))));
        const VF fraction =
            hn::IfThenElse(total_small, node, Clamp(hn::Mul(tau_fit, inv_total), 0.0f, 1.0f));
        const VF quantile_arg = hn::Mul(fraction, expm1_fit);
        const VF quantile =
            hn::IfThenElse(hn::Le(hn::Add(quantile_arg, K(1.0f)), zero), K(1.0f),
                           Clamp(hn::Mul(hn::Neg(M::Log1p(quantile_arg)), inv_fit), 0.0f, 1.0f));
        const VF series = hn::NegMulAdd(hn::Mul(a_fit, fraction),
                                        hn::Mul(hn::Sub(K(1.0f), fraction), K(0.5f)), fraction);
        const VF u = hn::IfThenElse(fit_small, series, quantile);
        // in_planet_shadow at eye + d u: on the night side, within the cylinder.
        const VF along = hn::MulAdd(u, d_sun, K(k.shadow_along_eye));
        const VF excess =
            hn::MulAdd(u, hn::MulAdd(u, perpendicular_sq, across_d), K(k.shadow_excess_eye));
        const MF shadow = hn::And(hn::Lt(along, zero), hn::Lt(excess, zero));
        const VF h = hn::Max(
            hn::NegMulAdd(hn::Mul(p.sag, u), hn::Sub(K(1.0f), u), hn::MulAdd(p.rise, u, p.h0)),
            p.min_h);
        // tau_to(u): G optical depth from the eye to u, from the mean densities over [0, u].
        const VF su = hn::Mul(s, u);
        const VF mean_r = ExponentialAverage<M>(hn::Mul(a_r, u));
        const VF mean_m = ExponentialAverage<M>(hn::Mul(a_m, u));
        const VF tau_u = hn::Mul(su, hn::MulAdd(k_r0, mean_r, hn::Mul(k_m0, mean_m)));
        // Each channel's own attenuation to the node relative to G's, with the Gauss weight.
        VF channel[3];
        for (int c : {0, 2}) {
            const VF tau_c = hn::Mul(su, hn::MulAdd(K(k.k_r0_channel[c]), mean_r,
                                                    hn::Mul(K(k.k_m0_channel[c]), mean_m)));
            channel[c] = hn::Mul(K(float(height::kSunWeights[n])),
                                 M::Exp(Clamp(hn::Sub(tau_u, tau_c), -kMaxExponent, kMaxExponent)));
        }
        channel[1] = K(float(height::kSunWeights[n]));
        const VF log_jacobian = hn::Add(hn::MulAdd(a_fit, u, hn::Sub(tau_fit, tau_u)), log_scale);
        const VF w_r =
            M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hr), log_jacobian), K(kMaxExponent)));
        const VF w_m =
            M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hm), log_jacobian), K(kMaxExponent)));
        if (k.multiple) {
            // The sun at the node: linear in its cosine between the eye's and the vertex's.
            const VF mu_node = hn::MulAdd(hn::Sub(ends.mu1, K(k.eye_mu_s)), u, K(k.eye_mu_s));
            VF level[3];
            SliceLevel(k, h, mu_node, level);
            for (int c = 0; c < 3; ++c) {
                const VF weighted = hn::Mul(channel[c], level[c]);
                multiple.r[c] = hn::MulAdd(w_r, weighted, multiple.r[c]);
                multiple.m[c] = hn::MulAdd(w_m, weighted, multiple.m[c]);
            }
            const VF share =
                hn::Mul(hn::MulAdd(K(k.rayleigh[1]), w_r, hn::Mul(K(k.mie_scattering[1]), w_m)),
                        hn::Mul(channel[1], level[1]));
            multiple.weight = hn::Add(multiple.weight, share);
            multiple.altitude = hn::MulAdd(share, h, multiple.altitude);
        }
        VF sun[3];
        Transmittance<M>(k, h, hn::MulAdd(hn::Sub(ends.lr1, ends.lr0), u, ends.lr0),
                         hn::MulAdd(hn::Sub(ends.lm1, ends.lm0), u, ends.lm0), sun);
        const MF lit = hn::AndNot(shadow, ends.active);
        for (int c = 0; c < 3; ++c) {
            const VF weighted = hn::IfThenElseZero(lit, hn::Mul(channel[c], sun[c]));
            sunlit_r[c] = hn::MulAdd(w_r, weighted, sunlit_r[c]);
            sunlit_m[c] = hn::MulAdd(w_m, weighted, sunlit_m[c]);
        }
    }
}

/// L_in per channel from the quadrature's sums (each channel's own attenuation included): the
/// phases, the higher orders' shape and the segment's length.
template <class M, class Out>
HWY_INLINE void HeightInScattering(const FrameConstants& k, const Segment& seg,
                                   const VF (&sunlit_r)[3], const VF (&sunlit_m)[3],
                                   const MultipleSums& multiple, VF eye_altitude, const Out& out) {
    const VF s = seg.s;
    VF phase_r, phase_m;
    Phases<M>(k, seg.dx, seg.dy, seg.dz, s, phase_r, phase_m);
    VF shape[3] = {hn::Zero(DF()), hn::Zero(DF()), hn::Zero(DF())};
    if (k.multiple) {
        // The altitude the higher orders come from (the eye's where there are none).
        const MF some = hn::Gt(multiple.weight, hn::Zero(DF()));
        const VF altitude = hn::IfThenElse(
            some, hn::Div(multiple.altitude, hn::IfThenElse(some, multiple.weight, K(1.0f))),
            eye_altitude);
        SliceShape<M>(k, seg, altitude, shape);
    }
    for (int c = 0; c < 3; ++c) {
        const VF scattering =
            hn::MulAdd(hn::Mul(K(k.rayleigh[c]), phase_r), sunlit_r[c],
                       hn::Mul(hn::Mul(K(k.mie_scattering[c]), phase_m), sunlit_m[c]));
        const VF higher = hn::Mul(hn::MulAdd(K(k.rayleigh[c]), multiple.r[c],
                                             hn::Mul(K(k.mie_scattering[c]), multiple.m[c])),
                                  shape[c]);
        const VF value = hn::Mul(hn::MulAdd(scattering, K(k.sun_top[c]), higher), s);
        out.InScattering(c, hn::IfThenElseZero(seg.valid, value));
    }
}

/// The height model for one vector of positions (engine units), its results handed to `out`
/// (VectorOut: arrays; RegisterOut: registers): F_ex always, L_in when kInScattering, E_sun at the
/// vertex when kSunIrradiance. Returns the valid lanes.
template <class M, bool kInScattering, bool kSunIrradiance, class Out>
HWY_INLINE MF HeightVector(const FrameConstants& k, VF x, VF y, VF z, const Out& out) {
    const DF d;
    const VF zero = hn::Zero(d);
    const Segment seg = MakeSegment(k, x, y, z);
    const VF s = seg.s;
    const HeightProfile profile = MakeHeightProfile(k, seg);

    // Path-averaged densities and the extinction.
    const VF dh = hn::Abs(profile.rise);
    const VF rho_r = hn::Mul(M::Exp(hn::Mul(profile.h_low, K(-k.inv_hr))),
                             ExponentialAverage<M>(hn::Mul(dh, K(k.inv_hr))));
    const VF rho_m = hn::Mul(M::Exp(hn::Mul(profile.h_low, K(-k.inv_hm))),
                             ExponentialAverage<M>(hn::Mul(dh, K(k.inv_hm))));
    VF tau[3], extinction[3];
    for (int c = 0; c < 3; ++c) {
        const VF beta = hn::MulAdd(K(k.rayleigh[c]), rho_r, hn::Mul(K(k.mie_extinction[c]), rho_m));
        tau[c] = hn::Mul(beta, s);
        extinction[c] = M::Exp(hn::Neg(tau[c]));
        out.Extinction(c, hn::IfThenElse(seg.valid, extinction[c], K(1.0f)));
    }
    if constexpr (!kInScattering && !kSunIrradiance) return seg.valid;

    // Sun at the vertex: log Chapman factors, and E_sun.
    const VF cx = hn::MulAdd(K(k.up[0]), K(k.radius_m), seg.px);
    const VF cy = hn::MulAdd(K(k.up[1]), K(k.radius_m), seg.py);
    const VF cz = hn::MulAdd(K(k.up[2]), K(k.radius_m), seg.pz);
    const VF centre_distance = hn::Sqrt(Dot(cx, cy, cz, cx, cy, cz));
    const MF off_centre = hn::Gt(centre_distance, zero);
    const VF mu1 = hn::IfThenElse(off_centre,
                                  hn::Div(Dot(cx, cy, cz, K(k.sun[0]), K(k.sun[1]), K(k.sun[2])),
                                          hn::IfThenElse(off_centre, centre_distance, K(1.0f))),
                                  K(1.0f));
    VF lf_r1, lf_m1;
    LogChapmanFactors<M>(k, profile.h1, mu1, lf_r1, lf_m1);
    if constexpr (kSunIrradiance) {
        VF sun[3];
        Transmittance<M>(k, profile.h1, lf_r1, lf_m1, sun);
        for (int c = 0; c < 3; ++c) {
            out.SunIrradiance(c, hn::IfThenElseZero(seg.valid, hn::Mul(K(k.sun_top[c]), sun[c])));
        }
    }
    if constexpr (!kInScattering) return seg.valid;

    // A blocked end borrows the other end's factor; the shadow is tested per node.
    const MF lit1 =
        hn::And(hn::Lt(lf_r1, K(kBlockedLogColumn)), hn::Lt(lf_m1, K(kBlockedLogColumn)));
    EndFactors ends;
    ends.lr0 = k.eye_lit ? K(k.eye_log_chapman_r) : lf_r1;
    ends.lm0 = k.eye_lit ? K(k.eye_log_chapman_m) : lf_m1;
    ends.lr1 = hn::IfThenElse(lit1, lf_r1, ends.lr0);
    ends.lm1 = hn::IfThenElse(lit1, lf_m1, ends.lm0);
    ends.active = k.eye_lit ? hn::Eq(zero, zero) : lit1;
    ends.mu1 = mu1;

    VF sunlit_r[3] = {zero, zero, zero};
    VF sunlit_m[3] = {zero, zero, zero};
    MultipleSums multiple{{zero, zero, zero}, {zero, zero, zero}, zero, zero};
    // The light scattered more than once also reaches segments the sun does not.
    const MF needed = k.multiple ? seg.valid : hn::And(ends.active, seg.valid);
    if (k.k_total > 0.0f && !hn::AllFalse(d, needed)) {
        SunlitSums<M>(k, seg, profile, ends, sunlit_r, sunlit_m, multiple);
    }
    HeightInScattering<M>(k, seg, sunlit_r, sunlit_m, multiple, profile.h0, out);
    return seg.valid;
}

template <class M, bool kInScattering, bool kSunIrradiance>
std::size_t ShadeHeight(const FrameConstants& k, const KernelBlock& b) {
    return ForEachVector(b, [&k](VF x, VF y, VF z, const VectorOut& out) {
        return HeightVector<M, kInScattering, kSunIrradiance>(k, x, y, z, out);
    });
}

/// The height model for the one-pass driver, one vector at a time (HeightVector).
template <class M, bool kInScattering, bool kSun>
struct HeightShader {
    static constexpr int kN = 1;
    static constexpr bool kExtinctionInUnitInterval = false;
    static constexpr bool kInScatteringNonNegative = false;
    const FrameConstants& k;
    explicit HeightShader(const FrameConstants& frame) : k(frame) {}
    HWY_INLINE void operator()(const VF (&x)[1], const VF (&y)[1], const VF (&z)[1], MF (&valid)[1],
                               VF (&extinction)[1][3], VF (&in_scattering)[1][3],
                               VF (&sun)[1][3]) const {
        valid[0] = HeightVector<M, kInScattering, kSun>(
            k, x[0], y[0], z[0], RegisterOut{extinction[0], in_scattering[0], sun[0]});
    }
};

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace aerial::detail
HWY_AFTER_NAMESPACE();

#endif  // AERIAL_CORE_KERNEL_HEIGHT_INL_H_
