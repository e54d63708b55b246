// Internal, per SIMD target (Highway's -inl.h convention): how the kernels walk the caller's
// arrays. Positions in (three arrays, or packed x y z deinterleaved), results out to float
// arrays (VectorOut) or registers (RegisterOut), the partial last vector through padded copies
// so that nothing reads or writes past the caller's count.
#if defined(AERIAL_CORE_SIMD_BLOCKS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef AERIAL_CORE_SIMD_BLOCKS_INL_H_
#undef AERIAL_CORE_SIMD_BLOCKS_INL_H_
#else
#define AERIAL_CORE_SIMD_BLOCKS_INL_H_
#endif

#include <algorithm>
#include <cstring>
#include <type_traits>

#include <hwy/highway.h>

#include "batch_kernels.hpp"
#include "simd_math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace aerial::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

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

/// A vector sink (like VectorOut) that keeps the results in registers.
struct RegisterOut {
    VF* extinction;
    VF* in_scattering;
    VF* sun_irradiance;
    HWY_INLINE void Extinction(int c, VF v) const { extinction[c] = v; }
    HWY_INLINE void InScattering(int c, VF v) const { in_scattering[c] = v; }
    HWY_INLINE void SunIrradiance(int c, VF v) const { sun_irradiance[c] = v; }
};

/// Calls f(std::integral_constant<int, c>()) for the channels c = 0, 1, 2 (so that c can be a
/// template argument, such as the shift of the channel's byte).
template <class F>
HWY_INLINE void ForEachChannel(const F& f) {
    f(std::integral_constant<int, 0>());
    f(std::integral_constant<int, 1>());
    f(std::integral_constant<int, 2>());
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

#endif  // AERIAL_CORE_SIMD_BLOCKS_INL_H_
