// The SIMD block kernel: the hoffman-preetham and height models of scattering.cpp, vectorised with
// Google Highway and dispatched at run time to the best target the CPU offers (SSE4, AVX2,
// AVX-512, ...). Every branch of the scalar models is a mask here (IfThenElse); uniform
// per-frame decisions stay `if`s. Two precisions (batch_kernels.hpp):
//   accurate  Highway's Exp/Log/Expm1/Log1p (about 1 ulp);
//   fast      polynomial exp2/log2 with exponent bit manipulation (relative error 5.4e-6,
//             absolute 2e-6 in log2).
// Both take expm1(z) from its Taylor series for |z| < 1/2 and from an exp already computed
// beyond it where there is one (F_ex), which keeps the per-vertex cost at one exp per channel.
// The 2002 model, whose cost is all in the exponentials, has its own (Exp2EighthsParts): exp and
// expm1 from one range reduction in eighths of a binary order, a table of 2^(j/8) and a
// degree-4 (accurate) or degree-3 (fast) polynomial, and the distance and the Henyey–Greenstein
// power from reciprocal square root estimates and a Newton step; it also runs from positions
// straight to RGBA8 codes in one pass, 255 and the exposure folded into its constants
// (ShadeRgba8HoffmanPreetham; ShadeRgba8 takes the height model and the lit colour).
// The scaled complementary error function of the Chapman factor is the rational form of
// Numerical Recipes (erfcc, fractional error below 1.2e-7 for every y >= 0), kept in log form so
// that log(H Ch) costs one log and no exp.
//
// Where float rounding makes the scalar code ill-conditioned the kernel is more accurate than it
// (and closer to the double model): the Henyey–Greenstein base near either peak (see Phases),
// the planet-shadow test for planets whose radius float resolves to metres (see
// FrameConstants::shadow_*), and 1 / tau_total for subnormal depths.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/geometric.hpp>

#include "aerial/phase.hpp"
#include "batch_kernels.hpp"

// The kernels keep vectors in small arrays and structs, which scalable vectors (SVE, RVV) do not
// allow: those targets are not compiled (Arm gets NEON).
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SVE | HWY_SVE2 | HWY_SVE_256 | HWY_SVE2_128 | HWY_RVV)
#endif
// Highway re-includes this file once per SIMD target. The path is relative to module/include,
// the include directory every translation unit of aerial_core has.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "../src/core/batch_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>

#include <hwy/contrib/math/math-inl.h>

// ---- Target-independent part: per-frame constants, compiled once -----------------------------
#ifndef AERIAL_BATCH_SIMD_ONCE
#define AERIAL_BATCH_SIMD_ONCE

namespace aerial::detail::simd {

/// log of the sun's column (m) beyond which it counts as blocked (scattering.cpp).
constexpr float kBlockedLogColumn = 80.0f;
/// Smallest normal float: floor of every log argument (log(0) would be -inf or undefined).
constexpr float kTiny = std::numeric_limits<float>::min();

/// 3-point Gauss–Legendre on [0, 1] (scattering.cpp, height_model).
constexpr float kSunNodes[3] = {0.11270166537925831148f, 0.5f, 0.88729833462074168852f};
constexpr float kSunWeights[3] = {5.0f / 18.0f, 8.0f / 18.0f, 5.0f / 18.0f};

/// The bits of 2^(j/8) for j = 0..7 less j << 20, twice (Exp2EighthsParts adds n << 20 for
/// n = 8 m + j, which is m << 23 + j << 20: the exponent of 2^m and the j it does not want;
/// AVX-512 lookups read four index bits).
alignas(64) constexpr std::int32_t kExp2EighthsBits[16] = {
    0x3f800000, 0x3f7b95c2, 0x3f7837f0, 0x3f75fed7, 0x3f7504f3, 0x3f75672a, 0x3f7744fd, 0x3f7ac0c7,
    0x3f800000, 0x3f7b95c2, 0x3f7837f0, 0x3f75fed7, 0x3f7504f3, 0x3f75672a, 0x3f7744fd, 0x3f7ac0c7};
/// The same for 255 2^(j/8) (the float nearest to it): the one-pass codes take 255 F_ex and
/// 255 expm1 straight from the exponential.
alignas(64) constexpr std::int32_t kExp2Eighths255Bits[16] = {
    0x437f0000, 0x437b0a2c, 0x43779fb8, 0x437558d8, 0x43744fee, 0x4374a1c3, 0x43766db8, 0x4379d606,
    0x437f0000, 0x437b0a2c, 0x43779fb8, 0x437558d8, 0x43744fee, 0x4374a1c3, 0x43766db8, 0x4379d606};
/// 8 log2(e): natural exponents to eighths of a binary order (Exp2EighthsParts).
constexpr double kEighthsPerNat = 8.0 * 1.44269504088896340736;

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
    float k_r0, k_m0, k_total;  // G extinction at the eye per component and total, 1/m
    // in_planet_shadow of eye + d u without cancelling numbers of size R: with c = eye + R up
    // (from the planet centre), along(u) = c.sun + u d.sun and |across(u)|^2 - R^2 =
    // (|A|^2 - R^2) + 2 u A.d + u^2 (|d|^2 - (d.sun)^2), A = c - (c.sun) sun, the two constants
    // taken in double; A.d = A.d_perp since A is across the sun.
    float shadow_along_eye, shadow_excess_eye, shadow_across_eye[3];
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
    k.eye_lit = f.eye_log_chapman_rayleigh < kBlockedLogColumn;
    k.k_r0 = f.rayleigh_scattering.y * std::exp(-f.eye_altitude_m * f.inv_rayleigh_scale_height);
    k.k_m0 = f.mie_extinction.y * std::exp(-f.eye_altitude_m * f.inv_mie_scale_height);
    k.k_total = k.k_r0 + k.k_m0;
    const double radius = f.atmosphere.planet_radius_m;
    const glm::dvec3 centre_to_eye = glm::dvec3(f.eye_m) + f.view.up * radius;
    const double along_eye = glm::dot(centre_to_eye, f.view.sun_dir);
    const glm::dvec3 across_eye = centre_to_eye - f.view.sun_dir * along_eye;
    k.shadow_along_eye = float(along_eye);
    k.shadow_excess_eye = float(glm::dot(across_eye, across_eye) - radius * radius);
    for (int i = 0; i < 3; ++i) k.shadow_across_eye[i] = float(across_eye[i]);
    return k;
}

}  // namespace aerial::detail::simd

#endif  // AERIAL_BATCH_SIMD_ONCE

// ---- Per-target part --------------------------------------------------------------------------
HWY_BEFORE_NAMESPACE();
namespace aerial::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using simd::FrameConstants;
using simd::kBlockedLogColumn;
using simd::kTiny;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using MF = hn::Mask<DF>;

HWY_INLINE VF K(float value) { return hn::Set(DF(), value); }

// Lambdas with a large body called once per loop iteration: GCC leaves them out of line (and
// the loop's constants in memory behind the closure) unless told.
#if defined(__GNUC__)
#define AERIAL_INLINE_LAMBDA __attribute__((always_inline))
#else
#define AERIAL_INLINE_LAMBDA
#endif

// ---- Fast exp2 / log2 -------------------------------------------------------------------------

/// 2^x: x = n + f with n = round(x), f in [-1/2, 1/2]; 2^f = 1 + f Q(f), Q cubic minimax for
/// relative error (5.4e-6); 2^n from the exponent bits. 0 below 2^-126, saturates at 2^127.
HWY_INLINE VF FastExp2(VF x) {
    const DF d;
    const DI di;
    const VF clamped = hn::Min(hn::Max(x, K(-126.0f)), K(127.0f));
    // Adding 1.5 * 2^23 rounds to an integer and leaves n in the low mantissa bits, whose shift
    // by 23 (with the bias 127 added) is 2^n: no float-int conversions.
    const VF shifted = hn::Add(clamped, K(12582912.0f));
    const VF f = hn::Sub(clamped, hn::Sub(shifted, K(12582912.0f)));
    VF q = hn::MulAdd(f, K(9.676037117e-03f), K(5.600578838e-02f));
    q = hn::MulAdd(q, f, K(2.402216778e-01f));
    q = hn::MulAdd(q, f, K(6.931053341e-01f));
    const VF p = hn::MulAdd(q, f, K(1.0f));
    const VF scale =
        hn::BitCast(d, hn::ShiftLeft<23>(hn::Add(hn::BitCast(di, shifted), hn::Set(di, 127))));
    return hn::IfThenZeroElse(hn::Lt(x, K(-126.0f)), hn::Mul(p, scale));
}

/// log2(x) for x > 0: x = 2^e m with m in [sqrt(1/2), sqrt(2)) from the bits, log2(m) =
/// t Q(t) with t = m - 1, Q quintic minimax for absolute error (2.1e-6). Finite for any input
/// (about -127 at 0, 128 at +inf), so that no NaN can leave a masked-off lane.
HWY_INLINE VF FastLog2(VF x) {
    const DF d;
    const DI di;
    const auto kSqrtHalfBits = hn::Set(di, 0x3F3504F3);
    const auto bits = hn::Sub(hn::BitCast(di, x), kSqrtHalfBits);
    const VF e = hn::ConvertTo(d, hn::ShiftRight<23>(bits));
    const VF m = hn::BitCast(d, hn::Add(hn::And(bits, hn::Set(di, 0x007FFFFF)), kSqrtHalfBits));
    const VF t = hn::Sub(m, K(1.0f));
    VF q = hn::MulAdd(t, K(-2.065918143e-01f), K(3.221548210e-01f));
    q = hn::MulAdd(q, t, K(-3.674899679e-01f));
    q = hn::MulAdd(q, t, K(4.793480168e-01f));
    q = hn::MulAdd(q, t, K(-7.211318588e-01f));
    q = hn::MulAdd(q, t, K(1.442713481e+00f));
    return hn::MulAdd(t, q, e);
}

constexpr float kLog2E = 1.44269504088896340736f;
constexpr float kLn2 = 0.69314718055994530942f;

/// Entry j of a table of 16 ints (kExp2EighthsBits, kExp2Eighths255Bits: eight entries twice) for
/// the low three bits j of each lane (the other bits are ignored): one lane permutation on AVX2
/// and AVX-512 (whose 16-lane permutation reads four index bits), two lookups and a select on
/// 4-lane targets.
HWY_INLINE hn::Vec<DI> LookUpEighth(const std::int32_t* table, hn::Vec<DI> bits) {
    const DI di;
#if HWY_TARGET == HWY_SCALAR
    return hn::Set(di, table[hn::GetLane(bits) & 7]);
#elif HWY_ARCH_X86 && HWY_TARGET == HWY_AVX2
    return hn::Vec<DI>{_mm256_permutevar8x32_epi32(hn::Load(di, table).raw, bits.raw)};
#elif HWY_ARCH_X86 && (HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL)
    return hn::Vec<DI>{_mm512_permutexvar_epi32(bits.raw, hn::Load(di, table).raw)};
#else
    if constexpr (hn::MaxLanes(di) >= 8) {
        return hn::TableLookupLanes(hn::Load(di, table),
                                    hn::IndicesFromVec(di, hn::And(bits, hn::Set(di, 7))));
    } else {
        const auto index = hn::IndicesFromVec(di, hn::And(bits, hn::Set(di, 3)));
        const auto low = hn::TableLookupLanes(hn::Load(di, table), index);
        const auto high = hn::TableLookupLanes(hn::Load(di, table + 4), index);
        return hn::IfThenElse(hn::Ne(hn::And(bits, hn::Set(di, 4)), hn::Zero(di)), high, low);
    }
#endif
}

/// The parts of 2^(y/8) for y <= 0 in eighths of a binary order (y = 8 log2(e) x for exp(x), x
/// minus an optical depth): y = 8 m + j + f with 8 m + j = round(y), j in 0..7, |f| <= 1/2
/// (exact); q = 2^(f/8) - 1 = e^r - 1, r = f ln2 / 8, |r| <= ln2 / 16, by its Taylor polynomial of
/// degree kDegree in f (truncation relative to q: 2.9e-8 for degree 4, 3.4e-6 for degree 3); and
/// scale = c 2^m 2^(j/8) from `table` (c = 1: kExp2EighthsBits; c = 255: kExp2Eighths255Bits)
/// and the exponent bits. Then c 2^(y/8) = scale q + scale and c (2^(y/8) - 1) = scale q +
/// (scale - c). Working in eighths of a binary order, the reduction is three additions (the
/// caller's one multiply gives y): against the natural form (multiply, fused multiply-add,
/// Cody–Waite in two more) it keeps the fused multiply-add units, the kernel's bottleneck, for
/// the polynomial. y carries the rounding of that multiply (relative 6e-8 of y, as the optical
/// depth does in the natural form): an absolute error of 2^(y/8) below 4.4e-8, at y/8 = -1.44
/// (tau = 1), and a relative error of expm1 below 1.2e-7 near y = 0. Below y = -1007.9 (x =
/// -87.33) the parts are those of -1007.9 (2^(y/8) = 1.2e-38: 0 to 8 bits and to any use of it
/// here); NaN gives those too. 2^m and j come from the bits of the rounding constant: no
/// float-int conversions.
template <int kDegree>
HWY_INLINE void Exp2EighthsParts(VF y, const std::int32_t* table, VF& scale, VF& q) {
    static_assert(kDegree == 3 || kDegree == 4, "degree 3 (fast) or 4 (accurate)");
    const DF d;
    const DI di;
    constexpr double kR = 0.69314718055994530942 / 8.0;  // r per unit of f
    const VF clamped = hn::Max(y, K(-1007.9f));
    // Adding 1.5 * 2^23 rounds to an integer n = 8 m + j and leaves it in the low mantissa bits.
    const VF shifted = hn::Add(clamped, K(12582912.0f));
    const VF f = hn::Sub(clamped, hn::Sub(shifted, K(12582912.0f)));
    VF p;
    if constexpr (kDegree == 4) {
        p = hn::MulAdd(f, K(float(kR * kR * kR * kR / 24.0)), K(float(kR * kR * kR / 6.0)));
        p = hn::MulAdd(p, f, K(float(kR * kR / 2.0)));
    } else {
        p = hn::MulAdd(f, K(float(kR * kR * kR / 6.0)), K(float(kR * kR / 2.0)));
    }
    q = hn::Mul(hn::MulAdd(p, f, K(float(kR))), f);
    const hn::Vec<DI> bits = hn::BitCast(di, shifted);
    // n << 20 = m << 23 + j << 20, the table entry has j << 20 taken off. The constant's own
    // bits leave the 32-bit lane.
    scale = hn::BitCast(d, hn::Add(LookUpEighth(table, bits), hn::ShiftLeft<20>(bits)));
}

/// exp and expm1 of x = y / (8 log2(e)) <= 0 from Exp2EighthsParts. Measured over x in
/// [-87.3, 0] for the float y nearest to 8 log2(e) x (test_core_batch_kernels): relative error
/// against 2^(y/8) 8.6e-8 (exp) and 2.1e-7 (expm1) for degree 4, 2.3e-7 and 3.5e-6 for degree
/// 3; the rounding of the table entry (6e-8 relative) grows in scale - 1 where it cancels
/// against scale q near y = -1/2.
template <int kDegree>
HWY_INLINE void ExpAndExpm1(VF y, VF& exp_x, VF& expm1_x) {
    VF scale, q;
    Exp2EighthsParts<kDegree>(y, simd::kExp2EighthsBits, scale, q);
    exp_x = hn::MulAdd(scale, q, scale);
    expm1_x = hn::MulAdd(scale, q, hn::Sub(scale, K(1.0f)));
}

/// 1 / sqrt(x) for normal x > 0: the hardware estimate and one Newton step (relative error
/// about 2e-7 where the estimate has 12 bits).
HWY_INLINE VF RefinedRsqrt(VF x) {
#if HWY_ARCH_X86 && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
    const VF r = hn::ApproximateReciprocalSqrt(x);
    return hn::Mul(r, hn::NegMulAdd(hn::Mul(K(0.5f), x), hn::Mul(r, r), K(1.5f)));
#else
    // Elsewhere the estimate may have 8 bits or fewer: one step would leave 2e-5.
    return hn::Div(K(1.0f), hn::Sqrt(x));
#endif
}

/// x^(-3/2) for normal x > 0. On x86 from the hardware estimate r of 1 / sqrt(x) (relative
/// error delta <= 2^-14 on AVX-512, 1.5 2^-12 on AVX2) and one Newton step on the cube: with
/// e = 1 - x r^2, r^3 (1 + 3/2 e) = x^(-3/2) (1 - 15/2 delta^2 + ...), relative error 3e-8 on
/// AVX-512 and 1.0e-6 at worst on AVX2 (RefinedRsqrt cubed: 9/2 delta^2, the same order); one
/// operation fewer than RefinedRsqrt cubed.
HWY_INLINE VF InversePow32FromEstimate(VF x) {
#if HWY_ARCH_X86 && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
    const VF r = hn::ApproximateReciprocalSqrt(x);
    const VF r2 = hn::Mul(r, r);
    const VF e = hn::NegMulAdd(x, r2, K(1.0f));
    const VF r3 = hn::Mul(r2, r);
    return hn::MulAdd(hn::Mul(e, K(1.5f)), r3, r3);
#else
    const VF r = RefinedRsqrt(x);
    return hn::Mul(r, hn::Mul(r, r));
#endif
}

// ---- The two precisions -----------------------------------------------------------------------

/// Highway's functions (about 1 ulp).
struct AccurateMath {
    static constexpr int kExpDegree = 4;  ///< of ExpAndExpm1
    /// Vectors ShadeRgba8HoffmanPreetham shades side by side. Measured on AVX2 (16 registers):
    /// 3 beats 2 by 8 % and 4 by 5 %; on AVX-512 (32 registers, vectors twice as wide) 2 beats 3
    /// and 4 by 3-4 %. FastMath, with the shorter exponential: 3.
#if HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL
    static constexpr int kInterleave = 2;
#else
    static constexpr int kInterleave = 3;
#endif
    static HWY_INLINE VF Exp(VF x) { return hn::Exp(DF(), x); }
    static HWY_INLINE VF Log(VF x) { return hn::Log(DF(), x); }
    static HWY_INLINE VF Expm1Far(VF x) { return hn::Expm1(DF(), x); }
    static HWY_INLINE VF Log1p(VF x) { return hn::Log1p(DF(), x); }
    static HWY_INLINE VF Reciprocal(VF x) { return hn::Div(K(1.0f), x); }
    /// x^(-3/2) for x > 0.
    static HWY_INLINE VF InversePow32(VF x) { return hn::Div(K(1.0f), hn::Mul(x, hn::Sqrt(x))); }
};

/// Polynomial exp2/log2; expm1 as exp - 1 beyond the series (relative error about 1e-5 there);
/// log1p with the rounding of 1 + x added back.
struct FastMath {
    static constexpr int kExpDegree = 3;   ///< of ExpAndExpm1
    static constexpr int kInterleave = 3;  ///< see AccurateMath
    static HWY_INLINE VF Exp(VF x) { return FastExp2(hn::Mul(x, K(kLog2E))); }
    static HWY_INLINE VF Log(VF x) { return hn::Mul(FastLog2(x), K(kLn2)); }
    static HWY_INLINE VF Expm1Far(VF x) { return hn::Sub(Exp(x), K(1.0f)); }
    static HWY_INLINE VF Log1p(VF x) {
        const VF u = hn::Add(x, K(1.0f));
        // log1p(x) = log(u) + (x - (u - 1)) / u to first order in the rounding error of u.
        const VF rounding = hn::Sub(x, hn::Sub(u, K(1.0f)));
        return hn::MulAdd(rounding, hn::ApproximateReciprocal(hn::Max(u, K(kTiny))), Log(u));
    }
    /// The hardware estimates and one Newton step (relative error about 1e-7 on x86; x^(-3/2):
    /// InversePow32FromEstimate).
    static HWY_INLINE VF Reciprocal(VF x) {
        const VF r = hn::ApproximateReciprocal(x);
        return hn::Mul(r, hn::NegMulAdd(x, r, K(2.0f)));
    }
    static HWY_INLINE VF InversePow32(VF x) { return InversePow32FromEstimate(x); }
};

// ---- Shared numerics (math.hpp, vectorised) ---------------------------------------------------

/// expm1(z) / z by its Taylor series; float-exact for |z| <= 1/2 (truncation 2e-11).
HWY_INLINE VF ExpAverageSeries(VF z) {
    VF p = hn::MulAdd(z, K(1.0f / 3628800.0f), K(1.0f / 362880.0f));
    p = hn::MulAdd(p, z, K(1.0f / 40320.0f));
    p = hn::MulAdd(p, z, K(1.0f / 5040.0f));
    p = hn::MulAdd(p, z, K(1.0f / 720.0f));
    p = hn::MulAdd(p, z, K(1.0f / 120.0f));
    p = hn::MulAdd(p, z, K(1.0f / 24.0f));
    p = hn::MulAdd(p, z, K(1.0f / 6.0f));
    p = hn::MulAdd(p, z, K(0.5f));
    return hn::MulAdd(p, z, K(1.0f));
}

/// |z| below which expm1(z) and expm1(z) / z come from their Taylor series.
constexpr float kSeriesLimit = 0.5f;

HWY_INLINE MF NearZero(VF z) { return hn::Lt(hn::Abs(z), K(kSeriesLimit)); }

/// expm1(z) with full relative precision (z <= 88).
template <class M>
HWY_INLINE VF Expm1(VF z) {
    return hn::IfThenElse(NearZero(z), hn::Mul(z, ExpAverageSeries(z)), M::Expm1Far(z));
}

/// expm1(z) when exp(z) is already known: exp(z) - 1 beyond the series, where it loses at most
/// a factor 1.6 of exp's relative error (2 ulp for the accurate precision).
HWY_INLINE VF Expm1GivenExp(VF z, VF exp_z) {
    return hn::IfThenElse(NearZero(z), hn::Mul(z, ExpAverageSeries(z)), hn::Sub(exp_z, K(1.0f)));
}

/// expm1(z) / z from expm1(z): the mean of exp(z u) over u in [0, 1], 1 at z = 0. With
/// z = -x it is (1 - exp(-x)) / x (one_minus_exp_over_x, exponential_average).
HWY_INLINE VF ExpAverageFrom(VF z, VF expm1_z) {
    const MF near_zero = NearZero(z);
    return hn::IfThenElse(near_zero, ExpAverageSeries(z),
                          hn::Div(expm1_z, hn::IfThenElse(near_zero, K(1.0f), z)));
}

/// (1 - exp(-x)) / x for x >= -80 (exponential_average): z = min(-x, 80).
template <class M>
HWY_INLINE VF ExponentialAverage(VF x) {
    const VF z = hn::Min(hn::Neg(x), K(80.0f));
    return ExpAverageFrom(z, Expm1<M>(z));
}

template <class M>
HWY_INLINE VF SafeLog(VF x) {
    return M::Log(hn::Max(x, K(kTiny)));
}

HWY_INLINE VF Clamp(VF x, float lo, float hi) { return hn::Min(hn::Max(x, K(lo)), K(hi)); }

/// log(erfcx(y)) - log(t) with t = 1 / (1 + y/2): the exponent of Numerical Recipes' erfcc,
/// erfc(y) = t exp(-y^2 + P(t)), fractional error below 1.2e-7 for all y >= 0.
HWY_INLINE VF ErfcxLogPoly(VF t) {
    VF p = hn::MulAdd(t, K(0.17087277f), K(-0.82215223f));
    p = hn::MulAdd(p, t, K(1.48851587f));
    p = hn::MulAdd(p, t, K(-1.13520398f));
    p = hn::MulAdd(p, t, K(0.27886807f));
    p = hn::MulAdd(p, t, K(-0.18628806f));
    p = hn::MulAdd(p, t, K(0.09678418f));
    p = hn::MulAdd(p, t, K(0.37409196f));
    p = hn::MulAdd(p, t, K(1.00002368f));
    return hn::MulAdd(p, t, K(-1.26551223f));
}

HWY_INLINE VF ErfcxT(VF y) { return hn::Div(K(1.0f), hn::MulAdd(y, K(0.5f), K(1.0f))); }

/// exp(y^2) erfc(y) for y >= 0 (only the test hook needs the value itself).
template <class M>
HWY_INLINE VF Erfcx(VF y) {
    const VF t = ErfcxT(y);
    return hn::Mul(t, M::Exp(ErfcxLogPoly(t)));
}

HWY_INLINE VF Dot(VF ax, VF ay, VF az, VF bx, VF by, VF bz) {
    return hn::MulAdd(ax, bx, hn::MulAdd(ay, by, hn::Mul(az, bz)));
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

// ---- Block loop: full vectors from the caller's arrays, the tail through padded copies ---------

/// Most float lanes of any target.
constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(float);

/// Where one vector's results go: three arrays per quantity (null where the caller does not
/// want it), written at `offset`. Either the caller's arrays or the padded tail buffers.
struct VectorOut {
    float* const* extinction;
    float* const* in_scattering;
    float* const* sun_irradiance;
    std::size_t offset;

    static HWY_INLINE void Store(VF v, float* p, std::size_t offset) {
        if (p) hn::StoreU(v, DF(), p + offset);
    }
    HWY_INLINE void Extinction(int c, VF v) const { Store(v, extinction[c], offset); }
    HWY_INLINE void InScattering(int c, VF v) const { Store(v, in_scattering[c], offset); }
    HWY_INLINE void SunIrradiance(int c, VF v) const { Store(v, sun_irradiance[c], offset); }
};

/// Calls body(x, y, z, out) -> valid mask for each vector of the block; returns the number of
/// invalid vertices. Never reads or writes past block.count: the last, partial vector goes
/// through padded copies (the same code path, so the body is instantiated once).
template <class Body>
HWY_INLINE std::size_t ForEachVector(const KernelBlock& b, const Body& body) {
    const DF d;
    const std::size_t lanes = hn::Lanes(d);
    HWY_ALIGN float pad_in[3][kMaxLanes];
    HWY_ALIGN float pad_out[9][kMaxLanes];
    float* tail_out[9];
    for (int c = 0; c < 3; ++c) {
        tail_out[c] = b.extinction[c] ? pad_out[c] : nullptr;
        tail_out[3 + c] = b.in_scattering[c] ? pad_out[3 + c] : nullptr;
        tail_out[6 + c] = b.sun_irradiance[c] ? pad_out[6 + c] : nullptr;
    }
    const VectorOut caller{b.extinction, b.in_scattering, b.sun_irradiance, 0};
    const VectorOut tail{tail_out, tail_out + 3, tail_out + 6, 0};
    std::size_t invalid = 0;
    for (std::size_t i = 0; i < b.count; i += lanes) {
        const std::size_t n = std::min(lanes, b.count - i);
        const float* px = b.x + i;
        const float* py = b.y + i;
        const float* pz = b.z + i;
        VectorOut out = caller;
        out.offset = i;
        if (HWY_UNLIKELY(n < lanes)) {
            for (std::size_t j = 0; j < lanes; ++j) {
                pad_in[0][j] = j < n ? px[j] : 0.0f;
                pad_in[1][j] = j < n ? py[j] : 0.0f;
                pad_in[2][j] = j < n ? pz[j] : 0.0f;
            }
            px = pad_in[0];
            py = pad_in[1];
            pz = pad_in[2];
            out = tail;
        }
        const MF valid = body(hn::LoadU(d, px), hn::LoadU(d, py), hn::LoadU(d, pz), out);
        invalid += hn::CountTrue(d, hn::AndNot(valid, hn::FirstN(d, n)));
        if (HWY_UNLIKELY(n < lanes)) {
            for (int q = 0; q < 9; ++q) {
                float* const* caller_arrays = q < 3   ? b.extinction
                                              : q < 6 ? b.in_scattering
                                                      : b.sun_irradiance;
                if (caller_arrays[q % 3]) {
                    std::memcpy(caller_arrays[q % 3] + i, pad_out[q], n * sizeof(float));
                }
            }
        }
    }
    return invalid;
}

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

// ---- hoffman-preetham -------------------------------------------------------------------------

/// The 2002 model's per-frame constants as whole vectors, built once per call (or block): the
/// loops take them as memory operands instead of broadcasting them again in every iteration.
struct HoffmanPreethamConstants {
    VF eye_units[3];
    VF meters_per_unit;
    VF max_distance_sq_m2;
    VF hg_peak[3];
    VF hg_a, hg_b_half;
    VF log2_rate[3];  // -beta_ex 8 log2(e): y = log2_rate s (Exp2EighthsParts)
    VF rayleigh_path[3], mie_path[3];
    bool unit_scale;

    explicit HoffmanPreethamConstants(const FrameConstants& k)
        : meters_per_unit(K(k.meters_per_unit)),
          max_distance_sq_m2(K(k.max_distance_sq_m2)),
          hg_a(K(k.hg_a)),
          hg_b_half(K(0.5f * k.hg_b)),
          unit_scale(k.unit_scale) {
        for (int i = 0; i < 3; ++i) {
            eye_units[i] = K(k.eye_units[i]);
            hg_peak[i] = K(k.hg_peak[i]);
            log2_rate[i] = K(float(-double(k.hp_extinction[i]) * simd::kEighthsPerNat));
            rayleigh_path[i] = K(k.hp_rayleigh_path[i]);
            mie_path[i] = K(k.hp_mie_path[i]);
        }
    }
};

/// Calls f(std::integral_constant<int, c>()) for the channels c = 0, 1, 2 (so that c can be a
/// template argument, such as the shift of the channel's byte).
template <class F>
HWY_INLINE void ForEachChannel(const F& f) {
    f(std::integral_constant<int, 0>());
    f(std::integral_constant<int, 1>());
    f(std::integral_constant<int, 2>());
}

/// The 2002 model for kN vectors of positions at once (engine units): F_ex, and L_in when
/// kInScattering; invalid lanes (NaN, Inf, farther than kMaxDistanceM) get F_ex = 1, L_in = 0.
/// Sets valid[j] to the valid lanes of vector j and hands each channel's results to
/// sink(j, std::integral_constant<int, c>, F_ex, L_in) as soon as they are computed (L_in is 0
/// without kInScattering), so that the caller can turn them into codes before the next channel
/// needs the registers. The distance s and the direction d / s come from one refined reciprocal
/// square root of |d|^2 (no square root, no division); per channel one ExpAndExpm1 gives F_ex =
/// exp(-tau) and the path length s phi(tau) = -expm1(-tau) / beta_ex with tau = beta_ex s, exact
/// down to tau = 0 without a series; the phases are computed once per vertex (the
/// Henyey–Greenstein power with a second refined reciprocal square root).
///
/// Why kN vectors: one vector is a chain of dependent operations (square root, exponential
/// polynomial, codes) about as long as the out-of-order window of a core, so one vector at a
/// time leaves execution ports idle waiting on latency. Every step below is written for all kN
/// vectors before the next step, which puts independent work next to each other in program
/// order. Each lane's operations are the same for any kN: the results are bit for bit those of
/// kN = 1.
///
/// In two halves: HoffmanPreethamGeometry gives the valid lanes, s and the phases (over their
/// constants); HoffmanPreethamChannels the channels from them; HoffmanPreethamVectors calls both.
template <bool kInScattering, int kN, bool kMaskDirections = true>
HWY_INLINE void HoffmanPreethamGeometry(const HoffmanPreethamConstants& k, const VF (&x)[kN],
                                        const VF (&y)[kN], const VF (&z)[kN], MF (&valid)[kN],
                                        VF (&s)[kN], VF (&rayleigh)[kN], VF (&mie)[kN]) {
    // Offset from the eye in engine units, then scaled: the difference is exact near the eye
    // (Sterbenz), where scaling first would round both terms at the size of the distance to the
    // origin; and no fused operation, so that every target rounds alike.
    VF dx[kN], dy[kN], dz[kN], s2[kN], inv_s[kN];
#define AERIAL_EACH _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j)
    AERIAL_EACH {
        dx[j] = hn::Sub(x[j], k.eye_units[0]);
        dy[j] = hn::Sub(y[j], k.eye_units[1]);
        dz[j] = hn::Sub(z[j], k.eye_units[2]);
    }
    if (!k.unit_scale) {
        AERIAL_EACH {
            dx[j] = hn::Mul(dx[j], k.meters_per_unit);
            dy[j] = hn::Mul(dy[j], k.meters_per_unit);
            dz[j] = hn::Mul(dz[j], k.meters_per_unit);
        }
    }
    AERIAL_EACH s2[j] = Dot(dx[j], dy[j], dz[j], dx[j], dy[j], dz[j]);
    AERIAL_EACH valid[j] = hn::Le(s2[j], k.max_distance_sq_m2);  // false for NaN
    // Invalid lanes are moved onto the eye, where F_ex = exp(0) = 1 and L_in = 0 exactly.
    AERIAL_EACH s2[j] = hn::IfThenElseZero(valid[j], s2[j]);
    // |d|^2 below the smallest normal float (|d| < 1.1e-19 m, 0 at the eye) is raised to it
    // for the reciprocal square root: s = |d|^2 / |d| stays 0 at the eye and below 1.1e-19 m
    // elsewhere, and d / s finite.
    AERIAL_EACH inv_s[j] = RefinedRsqrt(hn::Max(s2[j], K(kTiny)));
    AERIAL_EACH s[j] = hn::Mul(s2[j], inv_s[j]);
    if constexpr (kInScattering) {
        // Phases (see Phases): 1 - c' from the chord |d/s - sign(g) sun|^2 / 2, at most 2 but
        // for rounding; the direction of invalid lanes is taken as 0 (their L_in is 0) when
        // kMaskDirections, else their phases are whatever they come out as (NaN, too) and the
        // caller must zero their L_in.
        if constexpr (kMaskDirections) {
            AERIAL_EACH {
                dx[j] = hn::IfThenElseZero(valid[j], dx[j]);
                dy[j] = hn::IfThenElseZero(valid[j], dy[j]);
                dz[j] = hn::IfThenElseZero(valid[j], dz[j]);
            }
        }
        AERIAL_EACH {
            const VF cx = hn::MulSub(dx[j], inv_s[j], k.hg_peak[0]);
            const VF cy = hn::MulSub(dy[j], inv_s[j], k.hg_peak[1]);
            const VF cz = hn::MulSub(dz[j], inv_s[j], k.hg_peak[2]);
            // chord = 2 (1 - c'); the halvings below are exact, so these are the values of
            // 1 - c' = min(chord / 2, 2), c = 1 - (1 - c') and hg_a + hg_b (1 - c').
            const VF chord = hn::Min(Dot(cx, cy, cz, cx, cy, cz), K(4.0f));
            const VF c = hn::NegMulAdd(chord, K(0.5f), K(1.0f));
            rayleigh[j] = hn::MulAdd(c, c, K(1.0f));  // over 3 / (16 pi)
            mie[j] = InversePow32FromEstimate(
                hn::MulAdd(k.hg_b_half, chord, k.hg_a));  // over hg_numerator
        }
    } else {
        (void)rayleigh;
        (void)mie;
    }
#undef AERIAL_EACH
}

/// The channels of HoffmanPreethamVectors from its geometry: per vector, per channel.
template <class M, bool kInScattering, int kN, class Sink>
HWY_INLINE void HoffmanPreethamChannels(const HoffmanPreethamConstants& k, const VF (&s)[kN],
                                        const VF (&rayleigh)[kN], const VF (&mie)[kN],
                                        const Sink& sink) {
    _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j) {
        ForEachChannel([&](auto channel) {
            constexpr int c = decltype(channel)::value;
            VF extinction, length;
            ExpAndExpm1<M::kExpDegree>(hn::Mul(k.log2_rate[c], s[j]), extinction, length);
            if constexpr (kInScattering) {
                // L = (beta_R P_R + beta_Ms P_M) E_eye s phi(tau), >= 0, with s phi(tau) =
                // -expm1(-tau) / beta_ex and the phase constants folded into hp_*_path (0 where
                // beta_ex is 0: then beta_R = beta_Ms = 0 and L_in is 0 anyway).
                sink(j, channel, extinction,
                     hn::Mul(hn::MulAdd(k.rayleigh_path[c], rayleigh[j],
                                        hn::Mul(k.mie_path[c], mie[j])),
                             length));
            } else {
                (void)length;
                (void)rayleigh;
                (void)mie;
                sink(j, channel, extinction, hn::Zero(DF()));
            }
        });
    }
}

/// HoffmanPreethamGeometry, then HoffmanPreethamChannels.
template <class M, bool kInScattering, int kN, class Sink>
HWY_INLINE void HoffmanPreethamVectors(const HoffmanPreethamConstants& k, const VF (&x)[kN],
                                       const VF (&y)[kN], const VF (&z)[kN], MF (&valid)[kN],
                                       const Sink& sink) {
    VF s[kN], rayleigh[kN], mie[kN];
    HoffmanPreethamGeometry<kInScattering, kN>(k, x, y, z, valid, s, rayleigh, mie);
    HoffmanPreethamChannels<M, kInScattering, kN>(k, s, rayleigh, mie, sink);
}

/// Vectors the one-pass driver of the lit colour (HoffmanPreethamShader) shades together (see
/// HoffmanPreethamVectors); the F_ex and L_in driver takes M::kInterleave, tuned per target.
constexpr int kLitInterleave = 2;

template <class M, bool kInScattering>
std::size_t ShadeHoffmanPreetham(const FrameConstants& k, const KernelBlock& b) {
    const HoffmanPreethamConstants hp(k);
    return ForEachVector(b, [&k, &hp](VF x, VF y, VF z, const VectorOut& out) {
        const VF xs[1] = {x}, ys[1] = {y}, zs[1] = {z};
        MF valid[1];
        HoffmanPreethamVectors<M, kInScattering, 1>(
            hp, xs, ys, zs, valid, [&out](int, auto channel, VF extinction, VF in_scattering) {
                out.Extinction(decltype(channel)::value, extinction);
                if constexpr (kInScattering) {
                    out.InScattering(decltype(channel)::value, in_scattering);
                }
            });
        for (int c = 0; c < 3; ++c) {
            out.SunIrradiance(c, hn::IfThenElseZero(valid[0], K(k.sun_eye[c])));
        }
        return valid[0];
    });
}

// ---- hoffman-preetham straight to RGBA8 -------------------------------------------------------

/// float to int32 by truncation for values well inside the int32 range: the bare conversion
/// instruction on x86 (Highway's ConvertTo adds a fix-up for out-of-range values, five
/// operations per vector).
HWY_INLINE hn::Vec<DI> TruncateInRange(VF v) {
#if HWY_ARCH_X86 && HWY_TARGET == HWY_AVX2
    return hn::Vec<DI>{_mm256_cvttps_epi32(v.raw)};
#elif HWY_ARCH_X86 && (HWY_TARGET == HWY_SSE4 || HWY_TARGET == HWY_SSSE3)
    return hn::Vec<DI>{_mm_cvttps_epi32(v.raw)};
#elif HWY_ARCH_X86 && (HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL)
    return hn::Vec<DI>{_mm512_cvttps_epi32(v.raw)};
#else
    return hn::ConvertTo(DI(), v);
#endif
}

/// 8-bit codes of v by the batch API's rule floor(clamp(v, 0, 1) * 255 + 0.5), with the same
/// float operations as to_unorm8 (a multiply, then an add: the library is built without
/// contraction into fused multiply-adds), as 32-bit lanes. kNonNegative: v >= 0 is known (F_ex
/// from an exponential, L_in a product of non-negative factors), the lower clamp is left out.
/// kAtMostOne: v <= 1 is known too, the upper clamp is left out.
///
/// For v >= 0 the upper clamp is done on the integers, where it is cheaper: v > 1 gives
/// v 255 >= 255 (the rounding is monotonic), v 255 + 0.5 >= 255.5, and a truncation of 255 or
/// more (0x80000000 from the x86 conversion when it overflows, INT32_MAX from a saturating one:
/// either above 255 as an unsigned number), so the unsigned minimum with 255 is the code of
/// min(v, 1). Only for v that cannot be NaN (min(NaN, 1) is 1 in the float form, but the
/// conversion of NaN is target-specific).
template <bool kNonNegative = false, bool kAtMostOne = false>
HWY_INLINE hn::Vec<DI> Unorm8(VF v) {
    if constexpr (kNonNegative && !kAtMostOne) {
        const hn::RebindToUnsigned<DF> du;
        const auto code = hn::BitCast(du, TruncateInRange(hn::Add(hn::Mul(v, K(255.0f)), K(0.5f))));
        return hn::BitCast(DI(), hn::Min(code, hn::Set(du, 255u)));
    } else {
        // Max first: it gives 0 for NaN (the second operand), as to_unorm8 does.
        const VF lower = kNonNegative ? v : hn::Max(v, hn::Zero(DF()));
        const VF clamped = kAtMostOne ? lower : hn::Min(lower, K(1.0f));
        return TruncateInRange(hn::Add(hn::Mul(clamped, K(255.0f)), K(0.5f)));
    }
}

/// R, G, B codes and alpha 255 as little-endian RGBA8 words.
HWY_INLINE hn::Vec<DI> PackWords(hn::Vec<DI> r, hn::Vec<DI> g, hn::Vec<DI> b) {
    const DI di;
    return hn::Or(hn::Or(r, hn::ShiftLeft<8>(g)),
                  hn::Or(hn::ShiftLeft<16>(b), hn::Set(di, static_cast<int32_t>(0xFF000000u))));
}

/// Stores one vector of words at `out` (stride bytes apart), the first n lanes only when
/// n < lanes.
HWY_INLINE void StoreWords(hn::Vec<DI> words, std::uint8_t* out, std::size_t stride,
                           std::size_t n) {
    const DI di;
    const std::size_t lanes = hn::Lanes(di);
    if (stride == 4 && n == lanes) {
        hn::StoreU(words, di, reinterpret_cast<int32_t*>(out));
        return;
    }
    HWY_ALIGN int32_t buffer[kMaxLanes] = {};
    hn::Store(words, di, buffer);
    for (std::size_t j = 0; j < n; ++j) std::memcpy(out + j * stride, &buffer[j], 4);
}

// ---- height -----------------------------------------------------------------------------------

/// log_chapman_factor of scattering.cpp for both components at once (they share the geometry):
/// log(H Ch) at altitude h (already clamped to min_altitude) for a sun at cosine mu to the local
/// zenith; kBlockedLogColumn where the planet blocks the sun.
template <class M>
HWY_INLINE void LogChapmanFactors(const FrameConstants& k, VF h, VF cos_zenith, VF& log_r,
                                  VF& log_m) {
    constexpr float kSqrtHalfPi = 1.2533141373155002512f;
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
        const VF factor = hn::Max(
            hn::Sub(hn::Add(horizontal, horizontal), M::Exp(hn::Sub(log_up, rise))), K(1e-30f));
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
    const VF column_r = M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hr), log_r), K(80.0f)));
    const VF column_m = M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hm), log_m), K(80.0f)));
    for (int c = 0; c < 3; ++c) {
        const VF tau =
            hn::MulAdd(K(k.rayleigh[c]), column_r, hn::Mul(K(k.mie_extinction[c]), column_m));
        t[c] = hn::IfThenZeroElse(blocked, M::Exp(hn::Neg(tau)));
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
    const VF h_low = hn::Max(hn::NegMulAdd(sag, K(1.0f / 6.0f), hn::Min(h0, h1)), min_h);

    // Path-averaged densities and the extinction.
    const VF dh = hn::Abs(rise);
    const VF rho_r = hn::Mul(M::Exp(hn::Mul(h_low, K(-k.inv_hr))),
                             ExponentialAverage<M>(hn::Mul(dh, K(k.inv_hr))));
    const VF rho_m = hn::Mul(M::Exp(hn::Mul(h_low, K(-k.inv_hm))),
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
    LogChapmanFactors<M>(k, h1, mu1, lf_r1, lf_m1);
    if constexpr (kSunIrradiance) {
        VF sun[3];
        Transmittance<M>(k, h1, lf_r1, lf_m1, sun);
        for (int c = 0; c < 3; ++c) {
            out.SunIrradiance(c, hn::IfThenElseZero(seg.valid, hn::Mul(K(k.sun_top[c]), sun[c])));
        }
    }
    if constexpr (!kInScattering) return seg.valid;

    // A blocked end borrows the other end's factor; the shadow is tested per node.
    const MF lit1 =
        hn::And(hn::Lt(lf_r1, K(kBlockedLogColumn)), hn::Lt(lf_m1, K(kBlockedLogColumn)));
    const VF lr0 = k.eye_lit ? K(k.eye_log_chapman_r) : lf_r1;
    const VF lm0 = k.eye_lit ? K(k.eye_log_chapman_m) : lf_m1;
    const VF lr1 = hn::IfThenElse(lit1, lf_r1, lr0);
    const VF lm1 = hn::IfThenElse(lit1, lf_m1, lm0);
    const MF active = k.eye_lit ? hn::Eq(zero, zero) : lit1;

    VF sunlit_r[3] = {zero, zero, zero};
    VF sunlit_m[3] = {zero, zero, zero};
    if (k.k_total > 0.0f && !hn::AllFalse(d, hn::And(active, seg.valid))) {
        const VF k_r0 = K(k.k_r0), k_m0 = K(k.k_m0);
        const VF a_r = hn::Mul(rise, K(k.inv_hr));
        const VF a_m = hn::Mul(rise, K(k.inv_hm));
        // G optical depth to the vertex and the extinction there, relative to the eye's.
        const VF z_r = hn::Min(hn::Neg(a_r), K(80.0f));
        const VF z_m = hn::Min(hn::Neg(a_m), K(80.0f));
        const VF exp_r = M::Exp(z_r), exp_m = M::Exp(z_m);
        const VF tau_total =
            hn::Mul(s, hn::MulAdd(k_r0, ExpAverageFrom(z_r, Expm1GivenExp(z_r, exp_r)),
                                  hn::Mul(k_m0, ExpAverageFrom(z_m, Expm1GivenExp(z_m, exp_m)))));
        const VF k_end = hn::MulAdd(k_r0, exp_r, hn::Mul(k_m0, exp_m));
        const VF a_fit =
            Clamp(hn::IfThenElse(hn::Gt(k_end, zero),
                                 SafeLog<M>(hn::Min(hn::Div(K(k.k_total), k_end),
                                                    K(std::numeric_limits<float>::max()))),
                                 K(80.0f)),
                  -80.0f, 80.0f);
        // log_one_minus_exp_over_x(a_fit) + log_one_minus_exp_over_x(tau_total), as one log.
        const VF expm1_fit = Expm1<M>(hn::Neg(a_fit));
        const VF expm1_total = Expm1<M>(hn::Neg(tau_total));
        const VF log_scale = SafeLog<M>(hn::Mul(ExpAverageFrom(hn::Neg(a_fit), expm1_fit),
                                                ExpAverageFrom(hn::Neg(tau_total), expm1_total)));
        // Where tau_total < 1e-4 the fitted depth is linear in the node and the fraction is
        // the node itself; elsewhere 1 / tau_total is safe (it overflows for subnormals).
        const MF total_small = hn::Lt(tau_total, K(1e-4f));
        const VF inv_total = hn::Div(K(1.0f), hn::Max(tau_total, K(1e-4f)));
        const MF fit_small = hn::Lt(hn::Abs(a_fit), K(1e-4f));
        const VF inv_fit = hn::Div(K(1.0f), hn::IfThenElse(fit_small, K(1.0f), a_fit));
        // in_planet_shadow along the segment (FrameConstants::shadow_*), with the part of d
        // across the sun taken as a vector: |d|^2 - (d.sun)^2 cancels when d is along it.
        const VF sun_x = K(k.sun[0]), sun_y = K(k.sun[1]), sun_z = K(k.sun[2]);
        const VF d_sun = Dot(seg.dx, seg.dy, seg.dz, sun_x, sun_y, sun_z);
        const VF px = hn::NegMulAdd(sun_x, d_sun, seg.dx);
        const VF py = hn::NegMulAdd(sun_y, d_sun, seg.dy);
        const VF pz = hn::NegMulAdd(sun_z, d_sun, seg.dz);
        const VF perpendicular_sq = Dot(px, py, pz, px, py, pz);
        const VF across_d =
            hn::Mul(K(2.0f), Dot(px, py, pz, K(k.shadow_across_eye[0]), K(k.shadow_across_eye[1]),
                                 K(k.shadow_across_eye[2])));
        for (int n = 0; n < 3; ++n) {
            const VF node = K(simd::kSunNodes[n]);
            // Fitted optical depth to the node, the fraction of the total, and the u where
            // the one-exponential fit reaches it (exponential_quantile).
            const VF tau_fit = hn::IfThenElse(total_small, hn::Mul(node, tau_total),
                                              hn::Neg(M::Log1p(hn::Mul(node, expm1_total))));
            const VF fraction =
                hn::IfThenElse(total_small, node, Clamp(hn::Mul(tau_fit, inv_total), 0.0f, 1.0f));
            const VF quantile_arg = hn::Mul(fraction, expm1_fit);
            const VF quantile = hn::IfThenElse(
                hn::Le(hn::Add(quantile_arg, K(1.0f)), zero), K(1.0f),
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
                hn::NegMulAdd(hn::Mul(sag, u), hn::Sub(K(1.0f), u), hn::MulAdd(rise, u, h0)),
                min_h);
            // tau_to(u): G optical depth from the eye to u.
            const VF tau_u = hn::Mul(
                hn::Mul(s, u), hn::MulAdd(k_r0, ExponentialAverage<M>(hn::Mul(a_r, u)),
                                          hn::Mul(k_m0, ExponentialAverage<M>(hn::Mul(a_m, u)))));
            const VF log_jacobian =
                hn::Add(hn::MulAdd(a_fit, u, hn::Sub(tau_fit, tau_u)), log_scale);
            const VF w_r = M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hr), log_jacobian), K(80.0f)));
            const VF w_m = M::Exp(hn::Min(hn::NegMulAdd(h, K(k.inv_hm), log_jacobian), K(80.0f)));
            VF sun[3];
            Transmittance<M>(k, h, hn::MulAdd(hn::Sub(lr1, lr0), u, lr0),
                             hn::MulAdd(hn::Sub(lm1, lm0), u, lm0), sun);
            const MF lit = hn::AndNot(shadow, active);
            for (int c = 0; c < 3; ++c) {
                const VF weighted =
                    hn::IfThenElseZero(lit, hn::Mul(K(simd::kSunWeights[n]), sun[c]));
                sunlit_r[c] = hn::MulAdd(w_r, weighted, sunlit_r[c]);
                sunlit_m[c] = hn::MulAdd(w_m, weighted, sunlit_m[c]);
            }
        }
    }

    // Per channel: phases, the closed-form path factor s phi(tau_c) / phi(tau_G), L_in.
    VF phase_r, phase_m;
    Phases<M>(k, seg.dx, seg.dy, seg.dz, s, phase_r, phase_m);
    VF path[3];
    for (int c = 0; c < 3; ++c) {
        const VF minus_tau = hn::Neg(tau[c]);
        path[c] = ExpAverageFrom(minus_tau, Expm1GivenExp(minus_tau, extinction[c]));
    }
    const VF inv_green = hn::Div(s, hn::Max(path[1], K(kTiny)));
    for (int c = 0; c < 3; ++c) {
        const VF scattering =
            hn::MulAdd(hn::Mul(K(k.rayleigh[c]), phase_r), sunlit_r[c],
                       hn::Mul(hn::Mul(K(k.mie_scattering[c]), phase_m), sunlit_m[c]));
        const VF value = hn::Mul(hn::Mul(scattering, K(k.sun_top[c])), hn::Mul(path[c], inv_green));
        out.InScattering(c, hn::IfThenElseZero(seg.valid, value));
    }
    return seg.valid;
}

template <class M, bool kInScattering, bool kSunIrradiance>
std::size_t ShadeHeight(const FrameConstants& k, const KernelBlock& b) {
    return ForEachVector(b, [&k](VF x, VF y, VF z, const VectorOut& out) {
        return HeightVector<M, kInScattering, kSunIrradiance>(k, x, y, z, out);
    });
}

// ---- Straight to RGBA8: either model, F_ex, lit colour and L_in ------------------------------

/// x, y, z of lanes() packed vertices at `xyz` (x0 y0 z0 x1 ...). On AVX2 and AVX-512 per
/// output two blends and one lane permutation of the three loaded vectors a, b, c: the
/// elements 3 i + k (k = 0 for x) lie in distinct lanes (3 i + k) mod lanes of a, b and c, so
/// blending puts them all in one vector, which the permutation sorts. Elsewhere Highway's
/// LoadInterleaved3.
HWY_INLINE void LoadXyz(const float* HWY_RESTRICT xyz, VF& x, VF& y, VF& z) {
    const DF d;
#if HWY_ARCH_X86 && HWY_TARGET == HWY_AVX2
    const __m256 a = _mm256_loadu_ps(xyz), b = _mm256_loadu_ps(xyz + 8),
                 c = _mm256_loadu_ps(xyz + 16);
    x.raw = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(a, b, 0x92), c, 0x24),
                                     _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    y.raw = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(a, b, 0x24), c, 0x49),
                                     _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    z.raw = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(a, b, 0x49), c, 0x92),
                                     _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    (void)d;
#elif HWY_ARCH_X86 && (HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL)
    const __m512 a = _mm512_loadu_ps(xyz), b = _mm512_loadu_ps(xyz + 16),
                 c = _mm512_loadu_ps(xyz + 32);
    x.raw = _mm512_permutexvar_ps(
        _mm512_setr_epi32(0, 3, 6, 9, 12, 15, 2, 5, 8, 11, 14, 1, 4, 7, 10, 13),
        _mm512_mask_blend_ps(0x2492, _mm512_mask_blend_ps(0x4924, a, b), c));
    y.raw = _mm512_permutexvar_ps(
        _mm512_setr_epi32(1, 4, 7, 10, 13, 0, 3, 6, 9, 12, 15, 2, 5, 8, 11, 14),
        _mm512_mask_blend_ps(0x4924, _mm512_mask_blend_ps(0x9249, a, b), c));
    z.raw = _mm512_permutexvar_ps(
        _mm512_setr_epi32(2, 5, 8, 11, 14, 1, 4, 7, 10, 13, 0, 3, 6, 9, 12, 15),
        _mm512_mask_blend_ps(0x9249, _mm512_mask_blend_ps(0x2492, a, b), c));
    (void)d;
#else
    hn::LoadInterleaved3(d, xyz, x, y, z);
#endif
}

/// The positions of vertices i .. i + n of the job as kN vectors: the caller's arrays when n fills
/// them (deinterleaved when job.packed_xyz, else three arrays), else (the last, partial step) the
/// n vertices left, then zeros (the eye's neighbourhood, finite).
template <int kN>
HWY_INLINE void LoadPositions(const Rgba8Job& job, std::size_t i, std::size_t n, VF (&x)[kN],
                              VF (&y)[kN], VF (&z)[kN]) {
    const DF d;
    const std::size_t lanes = hn::Lanes(d);
    if (HWY_LIKELY(n == kN * lanes)) {
        for (int j = 0; j < kN; ++j) {
            const std::size_t at = i + j * lanes;
            if (job.packed_xyz) {
                LoadXyz(job.x + 3 * at, x[j], y[j], z[j]);
            } else {
                x[j] = hn::LoadU(d, job.x + at);
                y[j] = hn::LoadU(d, job.y + at);
                z[j] = hn::LoadU(d, job.z + at);
            }
        }
        return;
    }
    HWY_ALIGN float pad[3][kN * kMaxLanes] = {};
    for (std::size_t q = 0; q < n; ++q) {
        const std::size_t at = i + q;
        pad[0][q] = job.packed_xyz ? job.x[3 * at] : job.x[at];
        pad[1][q] = job.packed_xyz ? job.x[3 * at + 1] : job.y[at];
        pad[2][q] = job.packed_xyz ? job.x[3 * at + 2] : job.z[at];
    }
    for (int j = 0; j < kN; ++j) {
        x[j] = hn::Load(d, pad[0] + j * lanes);
        y[j] = hn::Load(d, pad[1] + j * lanes);
        z[j] = hn::Load(d, pad[2] + j * lanes);
    }
}

/// A vector sink (like VectorOut) that keeps the results in registers.
struct RegisterOut {
    VF* extinction;
    VF* in_scattering;
    VF* sun_irradiance;
    HWY_INLINE void Extinction(int c, VF v) const { extinction[c] = v; }
    HWY_INLINE void InScattering(int c, VF v) const { in_scattering[c] = v; }
    HWY_INLINE void SunIrradiance(int c, VF v) const { sun_irradiance[c] = v; }
};

/// The 2002 model for the one-pass driver: kLitInterleave vectors at a time
/// (HoffmanPreethamVectors), E_sun = E_eye on the valid lanes when kSun. F_ex = exp(-tau) is in
/// [0, 1] (ExpAndExpm1 of x <= 0) and L_in >= 0, so their codes need fewer clamps.
template <class M, bool kInScattering, bool kSun>
struct HoffmanPreethamShader {
    static constexpr int kN = kLitInterleave;
    static constexpr bool kExtinctionInUnitInterval = true;
    static constexpr bool kInScatteringNonNegative = true;
    const FrameConstants& k;
    const HoffmanPreethamConstants hp;
    explicit HoffmanPreethamShader(const FrameConstants& frame) : k(frame), hp(frame) {}
    HWY_INLINE void operator()(const VF (&x)[kN], const VF (&y)[kN], const VF (&z)[kN],
                               MF (&valid)[kN], VF (&extinction)[kN][3], VF (&in_scattering)[kN][3],
                               VF (&sun)[kN][3]) const {
        HoffmanPreethamVectors<M, kInScattering, kN>(
            hp, x, y, z, valid, [&](int j, auto channel, VF f_ex, VF l_in) {
                extinction[j][decltype(channel)::value] = f_ex;
                in_scattering[j][decltype(channel)::value] = l_in;
            });
        if constexpr (kSun) {
            for (int j = 0; j < kN; ++j) {
                for (int c = 0; c < 3; ++c) {
                    sun[j][c] = hn::IfThenElseZero(valid[j], K(k.sun_eye[c]));
                }
            }
        }
    }
};

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

/// From positions to the caller's RGBA8 arrays in one pass: positions loaded (deinterleaved
/// when job.packed_xyz, else three arrays), F_ex, the lit colour (kLit) and L_in (kInScattering)
/// computed in registers by the Shader and stored as codes, no float arrays in between; the last,
/// partial step goes through zero-padded copies. `exposure` multiplies L_in and the lit colour
/// before the clamp (ToneCurve::clamp). The codes are those of the float path (the block kernels,
/// then batch.cpp's lit colour and the 8-bit rule), bit for bit: the same operations in the same
/// order, no fused multiply-adds where batch.cpp has none.
template <class M, class Shader, bool kInScattering, bool kLit>
std::size_t ShadeRgba8(const FrameConstants& constants, const Rgba8Job& work) {
    // Local copies: the byte stores below cannot alias them, so the constants stay in registers.
    const FrameConstants k = constants;
    const Rgba8Job job = work;
    const Shader shader(k);
    constexpr int kN = Shader::kN;
    const DF d;
    const VF zero = hn::Zero(d);
    const std::size_t lanes = hn::Lanes(d);
    const std::size_t step = kN * lanes;
    const VF exposure = K(job.exposure);
    // Codes of vector j of a step, n lanes of it stored from vertex `first`.
    auto store = [&](const VF(&extinction)[3], const VF(&in_scattering)[3], const VF(&sun)[3],
                     std::size_t first, std::size_t n) {
        constexpr bool kUnit = Shader::kExtinctionInUnitInterval;
        if (job.extinction) {
            StoreWords(
                PackWords(Unorm8<kUnit, kUnit>(extinction[0]), Unorm8<kUnit, kUnit>(extinction[1]),
                          Unorm8<kUnit, kUnit>(extinction[2])),
                job.extinction + first * job.extinction_stride, job.extinction_stride, n);
        }
        if constexpr (kLit) {
            // F_ex x albedo x (E_sun max(N.L, 0) + ambient), as batch.cpp's general path: N.L
            // summed left to right, std::max's NaN rule (a NaN normal gives a NaN colour, 0).
            HWY_ALIGN float normal[3][kMaxLanes] = {};
            for (std::size_t q = 0; q < n; ++q) {
                const auto* bytes = reinterpret_cast<const unsigned char*>(job.normals) +
                                    (first + q) * job.normal_stride;
                float xyz[3];
                std::memcpy(xyz, bytes, sizeof(xyz));
                normal[0][q] = xyz[0];
                normal[1][q] = xyz[1];
                normal[2][q] = xyz[2];
            }
            const VF n_dot_l_raw = hn::Add(hn::Add(hn::Mul(hn::Load(d, normal[0]), K(k.sun[0])),
                                                   hn::Mul(hn::Load(d, normal[1]), K(k.sun[1]))),
                                           hn::Mul(hn::Load(d, normal[2]), K(k.sun[2])));
            const VF n_dot_l = hn::IfThenZeroElse(hn::Lt(n_dot_l_raw, zero), n_dot_l_raw);
            hn::Vec<DI> code[3];
            for (int c = 0; c < 3; ++c) {
                const VF lit = hn::Mul(hn::Mul(extinction[c], K(job.albedo[c])),
                                       hn::Add(hn::Mul(sun[c], n_dot_l), K(job.ambient[c])));
                code[c] = Unorm8(hn::Mul(lit, exposure));
            }
            StoreWords(PackWords(code[0], code[1], code[2]), job.lit + first * job.lit_stride,
                       job.lit_stride, n);
        }
        if constexpr (kInScattering) {
            constexpr bool kPositive = Shader::kInScatteringNonNegative;
            StoreWords(PackWords(Unorm8<kPositive>(hn::Mul(in_scattering[0], exposure)),
                                 Unorm8<kPositive>(hn::Mul(in_scattering[1], exposure)),
                                 Unorm8<kPositive>(hn::Mul(in_scattering[2], exposure))),
                       job.in_scattering + first * job.in_scattering_stride,
                       job.in_scattering_stride, n);
        }
    };
    std::size_t invalid = 0;
    for (std::size_t i = 0; i < job.count; i += step) {
        const std::size_t n = std::min(step, job.count - i);
        VF x[kN], y[kN], z[kN];
        LoadPositions(job, i, n, x, y, z);
        MF valid[kN];
        VF extinction[kN][3], in_scattering[kN][3], sun[kN][3];
        shader(x, y, z, valid, extinction, in_scattering, sun);
        for (int j = 0; j < kN && j * lanes < n; ++j) {
            const std::size_t m = std::min(lanes, n - j * lanes);
            invalid += hn::CountTrue(d, hn::AndNot(valid[j], hn::FirstN(d, m)));
            store(extinction[j], in_scattering[j], sun[j], i + j * lanes, m);
        }
    }
    return invalid;
}

/// The 2002 model from positions to F_ex and L_in codes (no lit colour), with less work around
/// the model than ShadeRgba8: the same 8-bit rule on the same model, but 255 and the exposure are
/// folded into the exponential's table and the per-call constants, and each code comes from one
/// fused multiply-add (see `words`), so a code may differ from ShadeRgba8's by one where the
/// value lies within float rounding of a rounding boundary (both are within half a step of the
/// exact value there). kN vectors per step (HoffmanPreethamGeometry); each channel's codes go
/// into the RGBA8 words as soon as the channel is computed, so that only the words stay live
/// across channels; the L_in words of invalid lanes are set to alpha alone at the end (instead
/// of masking their directions: one operation for three). Full steps store the words straight
/// from registers, the last, partial step goes through zero-padded copies and StoreWords.
/// kExtinction / kInScattering: which codes are wanted (at least one).
template <class M, bool kExtinction, bool kInScattering, int kN>
std::size_t ShadeRgba8HoffmanPreetham(const FrameConstants& frame, const Rgba8Job& work) {
    static_assert(kExtinction || kInScattering, "no output");
    // Local copies: the byte stores below cannot alias them, so the constants stay put.
    const HoffmanPreethamConstants k(frame);
    const Rgba8Job job = work;
    const DF d;
    const DI di;
    const std::size_t lanes = hn::Lanes(d);
    const std::size_t step = kN * lanes;
    const bool packed_words = (!kExtinction || job.extinction_stride == 4) &&
                              (!kInScattering || job.in_scattering_stride == 4);
    // A step's geometry: the valid lanes, s and the phases of kN vectors of positions.
    struct Geometry {
        MF valid[kN];
        VF s[kN], rayleigh[kN], mie[kN];
    };
    auto geometry = [&](std::size_t at, std::size_t n, Geometry& g) AERIAL_INLINE_LAMBDA {
        VF x[kN], y[kN], z[kN];
        LoadPositions(job, at, n, x, y, z);
        HoffmanPreethamGeometry<kInScattering, kN, false>(k, x, y, z, g.valid, g.s, g.rayleigh,
                                                          g.mie);
    };
    // Its words: per channel, y = log2_rate s, its parts with the table of 255 2^(j/8)
    // (Exp2EighthsParts), then the codes with one fused multiply-add each:
    //   F_ex  255 F + 1/2 = scale q + (scale + 1/2);
    //   L_in  255 exposure L + 1/2 = t 255 expm1(-tau) + 1/2, 255 expm1 = scale q + (scale -
    //         255), t = exposure (hp_rayleigh_path P_R + hp_mie_path P_M) (exposure folded into
    //         the per-call constants; their sign makes t 255 expm1 >= 0).
    // F_ex codes need no clamp (255 F + 1/2 is in [1/2, 255.5]); L_in codes are clamped on the
    // integers (Unorm8). The caller has checked that t cannot overflow (FoldedInScattering).
    VF in_rayleigh[3], in_mie[3];
    for (int c = 0; c < 3; ++c) {
        in_rayleigh[c] = K(float(double(frame.hp_rayleigh_path[c]) * job.exposure));
        in_mie[c] = K(float(double(frame.hp_mie_path[c]) * job.exposure));
    }
    auto words = [&](const Geometry& g, hn::Vec<DI>(&extinction_words)[kN],
                     hn::Vec<DI>(&in_scattering_words)[kN]) AERIAL_INLINE_LAMBDA {
        const auto alpha = hn::Set(di, static_cast<int32_t>(0xFF000000u));
        const hn::RebindToUnsigned<DF> du;
        for (int j = 0; j < kN; ++j) extinction_words[j] = in_scattering_words[j] = alpha;
        _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j) {
            ForEachChannel([&](auto channel) {
                constexpr int c = decltype(channel)::value;
                constexpr int kShift = 8 * c;
                VF scale, q;
                Exp2EighthsParts<M::kExpDegree>(hn::Mul(k.log2_rate[c], g.s[j]),
                                                simd::kExp2Eighths255Bits, scale, q);
                if constexpr (kExtinction) {
                    const auto code =
                        TruncateInRange(hn::MulAdd(scale, q, hn::Add(scale, K(0.5f))));
                    extinction_words[j] = hn::Or(extinction_words[j], hn::ShiftLeft<kShift>(code));
                }
                if constexpr (kInScattering) {
                    const VF expm1_255 = hn::MulAdd(scale, q, hn::Sub(scale, K(255.0f)));
                    const VF t =
                        hn::MulAdd(in_rayleigh[c], g.rayleigh[j], hn::Mul(in_mie[c], g.mie[j]));
                    const auto code =
                        hn::BitCast(du, TruncateInRange(hn::MulAdd(t, expm1_255, K(0.5f))));
                    in_scattering_words[j] = hn::Or(
                        in_scattering_words[j],
                        hn::ShiftLeft<kShift>(hn::BitCast(di, hn::Min(code, hn::Set(du, 255u)))));
                }
            });
        }
        if constexpr (kInScattering) {
            for (int j = 0; j < kN; ++j) {
                in_scattering_words[j] =
                    hn::IfThenElse(hn::RebindMask(di, g.valid[j]), in_scattering_words[j], alpha);
            }
        }
    };
    std::size_t invalid = 0;
    std::size_t i = 0;
    // Full steps, words stored straight from registers. (Computing the next step's geometry
    // before this step's channels, software pipelining, was 2-4 % slower on AVX2 and AVX-512
    // with these kernels: the geometry is carried in memory.)
    auto store_step = [&](std::size_t at, const Geometry& g, const hn::Vec<DI>(&e)[kN],
                          const hn::Vec<DI>(&l)[kN]) AERIAL_INLINE_LAMBDA {
        _Pragma("GCC unroll 8") for (int j = 0; j < kN; ++j) {
            const std::size_t vertex = at + j * lanes;
            invalid += hn::CountTrue(d, hn::Not(g.valid[j]));
            if constexpr (kExtinction) {
                hn::StoreU(e[j], di, reinterpret_cast<int32_t*>(job.extinction + 4 * vertex));
            }
            if constexpr (kInScattering) {
                hn::StoreU(l[j], di, reinterpret_cast<int32_t*>(job.in_scattering + 4 * vertex));
            }
        }
    };
    if (packed_words) {
        for (; i + step <= job.count; i += step) {
            Geometry g;
            geometry(i, step, g);
            hn::Vec<DI> extinction_words[kN], in_scattering_words[kN];
            words(g, extinction_words, in_scattering_words);
            store_step(i, g, extinction_words, in_scattering_words);
        }
    }
    auto shade = [&](std::size_t at, std::size_t n, MF(&valid)[kN],
                     hn::Vec<DI>(&extinction_words)[kN], hn::Vec<DI>(&in_scattering_words)[kN])
                     AERIAL_INLINE_LAMBDA {
                         Geometry g;
                         geometry(at, n, g);
                         words(g, extinction_words, in_scattering_words);
                         for (int j = 0; j < kN; ++j) valid[j] = g.valid[j];
                     };
    // Strided words, and the last, partial step (LoadPositions zero-pads it).
    for (; i < job.count; i += step) {
        const std::size_t n = std::min(step, job.count - i);
        MF valid[kN];
        hn::Vec<DI> extinction_words[kN], in_scattering_words[kN];
        shade(i, n, valid, extinction_words, in_scattering_words);
        for (int j = 0; j < kN && j * lanes < n; ++j) {
            const std::size_t at = i + j * lanes;
            const std::size_t m = std::min(lanes, n - j * lanes);
            invalid += hn::CountTrue(d, hn::AndNot(valid[j], hn::FirstN(d, m)));
            if constexpr (kExtinction) {
                StoreWords(extinction_words[j], job.extinction + at * job.extinction_stride,
                           job.extinction_stride, m);
            }
            if constexpr (kInScattering) {
                StoreWords(in_scattering_words[j],
                           job.in_scattering + at * job.in_scattering_stride,
                           job.in_scattering_stride, m);
            }
        }
    }
    return invalid;
}

/// Whether ShadeRgba8HoffmanPreetham may fold the exposure into its L_in constants: t =
/// exposure (hp_rayleigh_path P_R + hp_mie_path P_M) must stay finite for every direction
/// (P_R = 1 + c^2 <= 2, P_M = base^(-3/2) <= hg_a^(-3/2)), else an infinite t times a zero path
/// at the eye would give NaN instead of 0. Only for exposures and irradiances near the float
/// range; ShadeRgba8 (the rule on the float values) takes those.
inline bool FoldedInScattering(const FrameConstants& k, float exposure) {
    if (!(k.hg_a > 0.0f)) return false;
    const double mie_max = std::pow(double(k.hg_a), -1.5);
    for (int c = 0; c < 3; ++c) {
        const double t = double(exposure) * (2.0 * std::abs(double(k.hp_rayleigh_path[c])) +
                                             std::abs(double(k.hp_mie_path[c])) * mie_max);
        if (!(t < 1e37)) return false;
    }
    return true;
}

/// The driver for the job's model, precision and outputs.
template <class M>
std::size_t ShadeRgba8For(const FrameConstants& k, Model model, const Rgba8Job& job) {
    const bool in_scattering = job.in_scattering != nullptr;
    const bool lit = job.lit != nullptr;
    if (model == Model::hoffman_preetham) {
        if (lit) {
            return in_scattering
                       ? ShadeRgba8<M, HoffmanPreethamShader<M, true, true>, true, true>(k, job)
                       : ShadeRgba8<M, HoffmanPreethamShader<M, false, true>, false, true>(k, job);
        }
        if (!in_scattering) {
            return ShadeRgba8HoffmanPreetham<M, true, false, M::kInterleave>(k, job);
        }
        if (!FoldedInScattering(k, job.exposure)) {
            return ShadeRgba8<M, HoffmanPreethamShader<M, true, false>, true, false>(k, job);
        }
        return job.extinction ? ShadeRgba8HoffmanPreetham<M, true, true, M::kInterleave>(k, job)
                              : ShadeRgba8HoffmanPreetham<M, false, true, M::kInterleave>(k, job);
    }
    if (lit) {
        return in_scattering ? ShadeRgba8<M, HeightShader<M, true, true>, true, true>(k, job)
                             : ShadeRgba8<M, HeightShader<M, false, true>, false, true>(k, job);
    }
    return in_scattering ? ShadeRgba8<M, HeightShader<M, true, false>, true, false>(k, job)
                         : ShadeRgba8<M, HeightShader<M, false, false>, false, false>(k, job);
}

// ---- Per-target entry points ------------------------------------------------------------------

template <class M>
std::size_t ShadeWith(const FrameConstants& k, Model model, const KernelBlock& b) {
    const bool in_scattering = b.in_scattering[0] || b.in_scattering[1] || b.in_scattering[2];
    const bool sun = b.sun_irradiance[0] || b.sun_irradiance[1] || b.sun_irradiance[2];
    if (model == Model::hoffman_preetham) {
        return in_scattering ? ShadeHoffmanPreetham<M, true>(k, b)
                             : ShadeHoffmanPreetham<M, false>(k, b);
    }
    if (in_scattering) {
        return sun ? ShadeHeight<M, true, true>(k, b) : ShadeHeight<M, true, false>(k, b);
    }
    return sun ? ShadeHeight<M, false, true>(k, b) : ShadeHeight<M, false, false>(k, b);
}

std::size_t ShadeBlockSimd(const Frame<float>& frame, const KernelBlock& block, bool fast) {
    if (block.count == 0) return 0;
    const FrameConstants k = simd::make_frame_constants(frame);
    return fast ? ShadeWith<FastMath>(k, frame.model, block)
                : ShadeWith<AccurateMath>(k, frame.model, block);
}

std::size_t ShadeRgba8Simd(const Frame<float>& frame, const Rgba8Job& job, bool fast) {
    if (job.count == 0) return 0;
    const FrameConstants k = simd::make_frame_constants(frame);
    return fast ? ShadeRgba8For<FastMath>(k, frame.model, job)
                : ShadeRgba8For<AccurateMath>(k, frame.model, job);
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

/// Applies a vector function to n floats (any n), through padded copies for the tail.
template <class F>
void ApplyToArray(const float* in, float* out, std::size_t n, const F& f) {
    const DF d;
    const std::size_t lanes = hn::Lanes(d);
    HWY_ALIGN float pad[kMaxLanes] = {};
    for (std::size_t i = 0; i < n; i += lanes) {
        const std::size_t m = std::min(lanes, n - i);
        std::memcpy(pad, in + i, m * sizeof(float));
        hn::Store(f(hn::Load(d, pad)), d, pad);
        std::memcpy(out + i, pad, m * sizeof(float));
    }
}

void ErfcxArray(const float* in, float* out, std::size_t n) {
    ApplyToArray(in, out, n, [](VF y) { return Erfcx<AccurateMath>(y); });
}
void FastExp2Array(const float* in, float* out, std::size_t n) {
    ApplyToArray(in, out, n, [](VF x) { return FastExp2(x); });
}
void FastLog2Array(const float* in, float* out, std::size_t n) {
    ApplyToArray(in, out, n, [](VF x) { return FastLog2(x); });
}
void ExpAndExpm1Array(const float* in, float* exp_out, float* expm1_out, std::size_t n, bool fast) {
    ApplyToArray(in, exp_out, n, [fast](VF x) {
        VF e, m;
        fast ? ExpAndExpm1<FastMath::kExpDegree>(x, e, m)
             : ExpAndExpm1<AccurateMath::kExpDegree>(x, e, m);
        return e;
    });
    ApplyToArray(in, expm1_out, n, [fast](VF x) {
        VF e, m;
        fast ? ExpAndExpm1<FastMath::kExpDegree>(x, e, m)
             : ExpAndExpm1<AccurateMath::kExpDegree>(x, e, m);
        return m;
    });
}

/// RGBA8 words (R in the lowest byte, A = 255) of three channels, each scaled by `scale` then
/// coded by the batch API's 8-bit rule floor(clamp(v, 0, 1) * 255 + 0.5), with the same float
/// operations as to_unorm8 (a multiply then an add, no fused multiply-add) so both agree bit for
/// bit. Inputs are the kernels' finite outputs.
void PackRgba8(const float* HWY_RESTRICT r, const float* HWY_RESTRICT g,
               const float* HWY_RESTRICT b, std::size_t n, float scale,
               std::uint32_t* HWY_RESTRICT out) {
    const DF d;
    const hn::RebindToUnsigned<DF> du;
    const std::size_t lanes = hn::Lanes(d);
    const VF vscale = hn::Set(d, scale);
    const auto alpha = hn::Set(du, 0xFF000000u);
    auto code = [&](const float* p) {
        return hn::BitCast(du, Unorm8(hn::Mul(hn::LoadU(d, p), vscale)));
    };
    std::size_t i = 0;
    for (; i + lanes <= n; i += lanes) {
        const auto word = hn::Or(hn::Or(code(r + i), hn::ShiftLeft<8>(code(g + i))),
                                 hn::Or(hn::ShiftLeft<16>(code(b + i)), alpha));
        hn::StoreU(word, du, out + i);
    }
    for (; i < n; ++i) {
        auto scalar_code = [scale](float v) {
            v = std::min(std::max(v * scale, 0.0f), 1.0f);
            return static_cast<std::uint32_t>(static_cast<int>(v * 255.0f + 0.5f));
        };
        out[i] = scalar_code(r[i]) | scalar_code(g[i]) << 8 | scalar_code(b[i]) << 16 | 0xFF000000u;
    }
}

/// Splits n tightly packed x, y, z float triples into three arrays.
void Deinterleave3(const float* HWY_RESTRICT xyz, std::size_t n, float* HWY_RESTRICT x,
                   float* HWY_RESTRICT y, float* HWY_RESTRICT z) {
    const DF d;
    const std::size_t lanes = hn::Lanes(d);
    std::size_t i = 0;
    for (; i + lanes <= n; i += lanes) {
        VF vx, vy, vz;
        LoadXyz(xyz + 3 * i, vx, vy, vz);
        hn::StoreU(vx, d, x + i);
        hn::StoreU(vy, d, y + i);
        hn::StoreU(vz, d, z + i);
    }
    for (; i < n; ++i) {
        x[i] = xyz[3 * i];
        y[i] = xyz[3 * i + 1];
        z[i] = xyz[3 * i + 2];
    }
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace aerial::detail
HWY_AFTER_NAMESPACE();

// ---- Dispatch ---------------------------------------------------------------------------------
#if HWY_ONCE
namespace aerial::detail {

HWY_EXPORT(ShadeBlockSimd);
HWY_EXPORT(ShadeRgba8Simd);
HWY_EXPORT(TargetName);
HWY_EXPORT(PackRgba8);
HWY_EXPORT(Deinterleave3);
HWY_EXPORT(ErfcxArray);
HWY_EXPORT(FastExp2Array);
HWY_EXPORT(FastLog2Array);
HWY_EXPORT(ExpAndExpm1Array);

std::size_t shade_block_simd(const Frame<float>& frame, const KernelBlock& block,
                             KernelPrecision precision) {
    if (frame.model != Model::hoffman_preetham && frame.model != Model::height) {
        return shade_block_scalar(frame, block);  // the reference model has no SIMD kernel
    }
    return HWY_DYNAMIC_DISPATCH(ShadeBlockSimd)(frame, block, precision == KernelPrecision::fast);
}

std::size_t shade_rgba8(const Frame<float>& frame, const Rgba8Job& job, KernelPrecision precision) {
    return HWY_DYNAMIC_DISPATCH(ShadeRgba8Simd)(frame, job, precision == KernelPrecision::fast);
}

const char* simd_target_name() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

void pack_rgba8(const float* r, const float* g, const float* b, std::size_t n, float scale,
                std::uint32_t* out) {
    HWY_DYNAMIC_DISPATCH(PackRgba8)(r, g, b, n, scale, out);
}

void deinterleave3(const float* xyz, std::size_t n, float* x, float* y, float* z) {
    HWY_DYNAMIC_DISPATCH(Deinterleave3)(xyz, n, x, y, z);
}

// Test hooks (declared by tests/core/test_batch_kernels.cpp): the dispatched target's building
// blocks applied to arrays, for accuracy tests against the standard library in double.
void simd_erfcx(const float* y, float* out, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(ErfcxArray)(y, out, n);
}
void simd_fast_exp2(const float* x, float* out, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(FastExp2Array)(x, out, n);
}
void simd_fast_log2(const float* x, float* out, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(FastLog2Array)(x, out, n);
}
void simd_exp_and_expm1(const float* x, float* exp_out, float* expm1_out, std::size_t n,
                        bool fast) {
    HWY_DYNAMIC_DISPATCH(ExpAndExpm1Array)(x, exp_out, expm1_out, n, fast);
}

// Test hooks: the targets compiled here that this CPU runs, and forcing one of them (an empty
// name goes back to the best), so that the tests cover every code path a user's CPU may take.
std::vector<std::string> simd_test_targets() {
    std::vector<std::string> names;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        names.emplace_back(hwy::TargetName(target));
    }
    return names;
}
bool simd_test_use_target(const std::string& name) {
    hwy::SetSupportedTargetsForTest(0);
    if (name.empty()) return true;
    for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
        if (name == hwy::TargetName(target)) {
            hwy::SetSupportedTargetsForTest(target);
            return true;
        }
    }
    return false;
}

}  // namespace aerial::detail
#endif  // HWY_ONCE
