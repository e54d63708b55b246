// Internal, per SIMD target (Highway's -inl.h convention): RGBA8 outputs. The batch API's 8-bit
// rule on vectors (Unorm8), words and their stores, the generic one-pass driver from positions
// to codes (ShadeRgba8, for either model's Shader) and the float-to-RGBA8 packer.
#if defined(AERIAL_CORE_SIMD_OUTPUTS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AERIAL_CORE_SIMD_OUTPUTS_INL_H_
#undef AERIAL_CORE_SIMD_OUTPUTS_INL_H_
#else
#define AERIAL_CORE_SIMD_OUTPUTS_INL_H_
#endif

#include <algorithm>
#include <cstdint>
#include <cstring>

#include <hwy/highway.h>

#include "batch_kernels.hpp"
#include "simd_blocks-inl.h"
#include "simd_frame_constants.hpp"
#include "simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aerial::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using simd::FrameConstants;

// ---- 8-bit codes and RGBA8 words ---------------------------------------------------------------

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

/// From positions to the caller's RGBA8 arrays in one pass: positions loaded (deinterleaved
/// when job.packed_xyz, else three arrays), F_ex, the lit colour (kLit) and L_in (kInScattering)
/// computed in registers by the Shader and stored as codes, no float arrays in between; the last,
/// partial step goes through zero-padded copies. `exposure` multiplies L_in and the lit colour
/// before the tone curve. With ToneCurve::clamp the codes are those of the float path (the block
/// kernels, then batch.cpp's lit colour and the 8-bit rule), bit for bit: the same operations in
/// the same order, no fused multiply-adds where batch.cpp has none; the exponential curve is
/// Highway's expm1 where the float path calls std::exp, which moves a code by one now and then.
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
    // The tone curve of an exposed value: clamp (the 8-bit rule clamps) or 1 - exp(-v) for
    // v > 0 and 0 otherwise (NaN included), as display_value.
    auto tone = [&](VF v) {
        if (!job.exponential_tone) return v;
        const VF positive = hn::Max(v, zero);  // Max first: 0 for NaN
        return hn::Neg(M::Expm1Far(hn::Neg(positive)));
    };
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
                // aerial::lit_value, in the same order.
                const VF lit = hn::Mul(hn::Mul(extinction[c], K(job.albedo[c])),
                                       hn::Add(hn::Mul(sun[c], n_dot_l), K(job.ambient[c])));
                code[c] = Unorm8(tone(hn::Mul(lit, exposure)));
            }
            StoreWords(PackWords(code[0], code[1], code[2]), job.lit + first * job.lit_stride,
                       job.lit_stride, n);
        }
        if constexpr (kInScattering) {
            constexpr bool kPositive = Shader::kInScatteringNonNegative;
            StoreWords(PackWords(Unorm8<kPositive>(tone(hn::Mul(in_scattering[0], exposure))),
                                 Unorm8<kPositive>(tone(hn::Mul(in_scattering[1], exposure))),
                                 Unorm8<kPositive>(tone(hn::Mul(in_scattering[2], exposure)))),
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

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace HWY_NAMESPACE
}  // namespace aerial::detail
HWY_AFTER_NAMESPACE();

#endif  // AERIAL_CORE_SIMD_OUTPUTS_INL_H_
