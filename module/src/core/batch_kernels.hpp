// Internal: the per-block shading kernels behind the batch API (batch.cpp). A block is at most
// kBlockSize vertices in structure-of-arrays form; outputs are raw linear floats, SoA, each
// optional. Two implementations with one contract:
//   shade_block_scalar  a plain loop over scatter<float> (std::exp): the reference for the SIMD
//                       kernels and the `scalar` figure of aerial-bench;
//   shade_block_simd    Google Highway, dynamic dispatch (SSE4 / AVX2 / AVX-512 as the CPU
//                       allows), for the hoffman-preetham and height models.
#pragma once

#include <cstddef>
#include <cstdint>

#include "aerial/scattering.hpp"

namespace aerial::detail {

/// Vertices per block: small enough for the SoA scratch to stay in L1, large enough to amortise
/// the per-block work.
inline constexpr std::size_t kBlockSize = 256;

/// How the kernels compute exp/log.
enum class KernelPrecision {
    /// Highway's Exp/Log/Expm1/Log1p (about 1 ulp); hoffman-preetham: exp and expm1 from one
    /// range reduction, a table of 2^(j/8) and a degree-4 polynomial (relative error 2e-7)
    accurate,
    /// low-degree polynomial exp2/log2; hoffman-preetham: the same exp/expm1 with degree 3
    /// (relative error 4e-6); errors measured by the tests, well below 1 LSB
    fast,
};

/// One block of work. Positions are in engine units, like View::eye. Any output pointer may be
/// null: that quantity is then not written (and not computed when nothing needs it).
struct KernelBlock {
    const float* x = nullptr;
    const float* y = nullptr;
    const float* z = nullptr;
    std::size_t count = 0;                                   ///< <= kBlockSize
    float* extinction[3] = {nullptr, nullptr, nullptr};      ///< F_ex per channel
    float* in_scattering[3] = {nullptr, nullptr, nullptr};   ///< L_in per channel
    float* sun_irradiance[3] = {nullptr, nullptr, nullptr};  ///< E_sun at the vertex per channel
};

/// Contract shared by both kernels: for each vertex i < count, the same quantities as
/// scatter(frame, {x[i], y[i], z[i]}) (within float rounding for `accurate`); vertices that are
/// not positions (NaN, Inf, farther than kMaxDistanceM) get F_ex = 1, L_in = 0, E_sun = 0 and
/// are counted in the return value. frame.model must be hoffman_preetham or height for the SIMD
/// kernel; the scalar kernel takes any model.
std::size_t shade_block_scalar(const Frame<float>& frame, const KernelBlock& block);
std::size_t shade_block_simd(const Frame<float>& frame, const KernelBlock& block,
                             KernelPrecision precision);

/// Either SIMD model straight from positions to RGBA8 codes, one pass, no float arrays (the
/// batch API's fast path for F_ex, the lit colour and L_in with ToneCurve::clamp). Pointers start
/// at the first vertex.
struct Rgba8Job {
    const float* x = nullptr;  ///< packed_xyz: x, y, z floats back to back from here
    const float* y = nullptr;  ///< else three tightly packed arrays
    const float* z = nullptr;
    bool packed_xyz = false;
    std::size_t count = 0;
    std::uint8_t* extinction = nullptr;     ///< F_ex codes, or null
    std::size_t extinction_stride = 4;      ///< bytes
    std::uint8_t* lit = nullptr;            ///< codes of the lit colour * exposure, or null
    std::size_t lit_stride = 4;             ///< bytes
    const float* normals = nullptr;         ///< for lit: x, y, z floats at the start of each record
    std::size_t normal_stride = 12;         ///< bytes
    float ambient[3] = {0.0f, 0.0f, 0.0f};  ///< Lighting::ambient
    float albedo[3] = {1.0f, 1.0f, 1.0f};   ///< Lighting::albedo
    std::uint8_t* in_scattering = nullptr;  ///< codes of L_in * exposure, or null
    std::size_t in_scattering_stride = 4;
    float exposure = 1.0f;
    bool exponential_tone = false;  ///< ToneCurve::exponential for L_in and lit, else clamp
};

/// Shades job.count vertices of the hoffman-preetham or height frame `frame` into the job's
/// arrays: the codes are, bit for bit, the 8-bit rule applied to what shade_block_simd gives in
/// float with the same precision (and, for lit, to batch.cpp's lit colour of those floats).
/// Returns the number of invalid vertices.
std::size_t shade_rgba8(const Frame<float>& frame, const Rgba8Job& job, KernelPrecision precision);

/// RGBA8 words (R in the lowest byte, A = 255) of n vertices: each channel times `scale`, then
/// floor(clamp(v, 0, 1) * 255 + 0.5), bit-identical to to_unorm8(v * scale) for finite v.
void pack_rgba8(const float* r, const float* g, const float* b, std::size_t n, float scale,
                std::uint32_t* out);

/// Splits n tightly packed x, y, z float triples into three arrays.
void deinterleave3(const float* xyz, std::size_t n, float* x, float* y, float* z);

/// Name of the SIMD target the dispatcher picked on this CPU ("AVX2", "AVX3", "SSE4", ...).
const char* simd_target_name();

}  // namespace aerial::detail
