// Internal, per SIMD target (Highway's -inl.h convention): the vector maths of the SIMD kernels,
// the vector types and the two precisions. Fast exp2/log2 from exponent bits; exp and expm1 of
// the 2002 model from one range reduction in eighths of a binary order (Exp2EighthsParts);
// reciprocal square roots from the hardware estimate; expm1, (1 - exp(-x)) / x and the
// Numerical Recipes erfcc in log form, as math.hpp and scattering.cpp use them.

// Target-independent part, compiled once.
#ifndef AERIAL_CORE_SIMD_MATH_ONCE_
#define AERIAL_CORE_SIMD_MATH_ONCE_

#include <cstdint>
#include <limits>

namespace aerial::detail::simd {

/// Smallest normal float: floor of every log argument (log(0) would be -inf or undefined).
constexpr float kTiny = std::numeric_limits<float>::min();

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

}  // namespace aerial::detail::simd

#endif  // AERIAL_CORE_SIMD_MATH_ONCE_

// Lambdas with a large body called once per loop iteration: GCC leaves them out of line (and
// the loop's constants in memory behind the closure) unless told.
#ifndef AERIAL_INLINE_LAMBDA
#if defined(__GNUC__)
#define AERIAL_INLINE_LAMBDA __attribute__((always_inline))
#else
#define AERIAL_INLINE_LAMBDA
#endif
#endif

#if defined(AERIAL_CORE_SIMD_MATH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AERIAL_CORE_SIMD_MATH_INL_H_
#undef AERIAL_CORE_SIMD_MATH_INL_H_
#else
#define AERIAL_CORE_SIMD_MATH_INL_H_
#endif

#include <cstdint>

#include <hwy/highway.h>

#include <hwy/contrib/math/math-inl.h>

#include "height_constants.hpp"

HWY_BEFORE_NAMESPACE();
namespace aerial::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using simd::kTiny;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using MF = hn::Mask<DF>;

HWY_INLINE VF K(float value) { return hn::Set(DF(), value); }

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
    const VF z = hn::Min(hn::Neg(x), K(float(height::kMaxExponent)));
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

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace aerial::detail
HWY_AFTER_NAMESPACE();

#endif  // AERIAL_CORE_SIMD_MATH_INL_H_
