// aerial/batch.hpp — shading many vertices at once, into caller memory, ready for the fixed
// pipeline.
//
// How to use this:
//   1. Once per frame: `auto frame = aerial::prepare_frame<float>(atmosphere, view, model);`
//   2. Describe the vertices where they already are: `aerial::Positions::aos(ptr, count, stride)`
//      (x, y, z floats at the start of each record, as for glVertexPointer) or `::soa(x, y, z, n)`.
//   3. Point the outputs you want at your arrays (every output is optional):
//        out.extinction_rgba8    F_ex, for glColorPointer (texture MODULATE)
//        out.lit_rgba8           F_ex x (E_sun max(N.L, 0) + ambient), the same with lighting baked
//                                in (needs Lighting::normals; fixed-function lighting ignores the
//                                secondary colour, so a lit engine must bake it here)
//        out.in_scattering_rgba8 L_in, for glSecondaryColorPointerEXT + GL_COLOR_SUM_EXT
//        out.*_rgb               the raw linear floats (3 per vertex), before exposure
//   4. `aerial::shade_into(*frame, positions, out, settings)`; check the Result.
//
// 8-bit rule: a linear value v (after exposure and tone curve for L_in and lit colours, as is for
// F_ex) becomes round-half-up of clamp(v, 0, 1) * 255, i.e. floor(clamp(v, 0, 1) * 255 + 0.5).
// Alpha is 255. Vertices that are not positions (NaN/Inf, farther than kMaxDistanceM) get
// F_ex = 1, L_in = 0, E_sun = 0 and are counted in BatchStats::invalid_vertices.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>

#include <glm/vec3.hpp>

#include "aerial/error.hpp"
#include "aerial/scattering.hpp"

namespace aerial {

/// Vertex positions in caller memory (engine units, like View::eye).
struct Positions {
    const float* x = nullptr;  ///< first x; y and z follow at y_offset / z_offset in `stride` units
    const float* y = nullptr;
    const float* z = nullptr;
    std::size_t count = 0;
    std::size_t stride_bytes = 0;  ///< bytes between consecutive vertices of each array
    /// Model space: 16 floats, column-major (glLoadMatrixf's layout), affine (bottom row 0, 0,
    /// 0, 1), mapping the positions to the world (computed in double per vertex); null: the
    /// positions are world positions.
    const float* model_matrix = nullptr;

    /// Interleaved records: x, y, z floats at the start of each, `stride_bytes` apart (0 means
    /// tightly packed, 12).
    static Positions aos(const float* xyz, std::size_t count, std::size_t stride_bytes = 0) {
        const std::size_t stride = stride_bytes ? stride_bytes : 3 * sizeof(float);
        return Positions{xyz, xyz ? xyz + 1 : nullptr, xyz ? xyz + 2 : nullptr, count, stride};
    }
    /// Three separate arrays of floats.
    static Positions soa(const float* x, const float* y, const float* z, std::size_t count) {
        return Positions{x, y, z, count, sizeof(float)};
    }
};

/// How linear radiance becomes a displayable value in [0, 1] (docs/conventions.md, Physics:
/// Display).
enum class ToneCurve {
    clamp,        ///< min(exposure * x, 1): linear, for scenes whose brightest L_in is known
    exponential,  ///< 1 - exp(-exposure * x): never clips, keeps noon and dawn readable
};

struct Display {
    float exposure = 1.0f;  ///< multiplies L_in and lit colours (not F_ex, a transmittance), > 0
    ToneCurve tone = ToneCurve::clamp;
};

/// The display value of a linear radiance (L_in or a lit colour).
inline float display_value(const Display& display, float linear) {
    const float x = display.exposure * linear;
    if (display.tone == ToneCurve::exponential) return x > 0.0f ? 1.0f - std::exp(-x) : 0.0f;
    return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
}

/// The lit colour of one channel before the display: F_ex x albedo x (E_sun cos + ambient), with
/// cos = max(N.L, 0) (or the cosine the caller stands for, e.g. level ground). The one rule of
/// lit_rgba8 (the SIMD kernels compute the same product in the same order) and of the scene
/// renderer's lit nodes, skipped nodes and arb lighting factor.
inline float lit_value(float extinction, float albedo, float sun_irradiance, float cos_incidence,
                       float ambient) {
    return extinction * albedo * (sun_irradiance * cos_incidence + ambient);
}

/// The 8-bit code of a value in [0, 1]: floor(clamp(v, 0, 1) * 255 + 0.5); NaN gives 0.
inline std::uint8_t to_unorm8(float v) {
    const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  // NaN -> 0
    return static_cast<std::uint8_t>(c * 255.0f + 0.5f);
}

/// Per-vertex lighting for the lit variant.
struct Lighting {
    const float* normals = nullptr;  ///< unit normals, x, y, z floats at the start of each record
    std::size_t normal_stride_bytes = 0;  ///< 0 means tightly packed (12)
    glm::vec3 ambient{0.0f};              ///< sky irradiance added to the sun term (linear RGB)
    glm::vec3 albedo{1.0f};               ///< multiplies the lit colour (1 when the texture has it)
};

/// A model matrix as Positions::model_matrix takes it: 16 finite floats, column-major, affine
/// (m[3], m[7], m[11] = 0, m[15] = 1). The error's field is "model_matrix". Null is valid (none).
std::optional<Error> validate_model_matrix(const float* column_major);

/// The memory layout of the 8-bit colour outputs.
enum class ColourFormat {
    rgba8,   ///< bytes R, G, B, A (glColorPointer(4, GL_UNSIGNED_BYTE, ...))
    bgra8,   ///< bytes B, G, R, A (GL_BGRA)
    argb32,  ///< a native 32-bit word A << 24 | R << 16 | G << 8 | B (D3DCOLOR, Irrlicht SColor)
};

/// "rgba8", "bgra8" or "argb32".
const char* colour_format_name(ColourFormat format);

/// Writes an RGBA code into 4 bytes of `format` (the one rule of every colour output).
inline void store_colour(std::uint8_t* out, ColourFormat format, std::uint8_t r, std::uint8_t g,
                         std::uint8_t b, std::uint8_t a) {
    if (format == ColourFormat::argb32) {
        const std::uint32_t word = std::uint32_t(a) << 24 | std::uint32_t(r) << 16 |
                                   std::uint32_t(g) << 8 | std::uint32_t(b);
        std::memcpy(out, &word, 4);
        return;
    }
    const bool bgra = format == ColourFormat::bgra8;
    out[0] = bgra ? b : r;
    out[1] = g;
    out[2] = bgra ? r : b;
    out[3] = a;
}

/// Where results go. Null pointers are skipped; strides of 0 mean tightly packed (4 bytes for
/// RGBA8, 12 for float RGB).
struct BatchOutputs {
    std::uint8_t* extinction_rgba8 = nullptr;
    std::size_t extinction_rgba8_stride = 0;
    std::uint8_t* lit_rgba8 = nullptr;
    std::size_t lit_rgba8_stride = 0;
    std::uint8_t* in_scattering_rgba8 = nullptr;
    std::size_t in_scattering_rgba8_stride = 0;
    float* extinction_rgb = nullptr;
    std::size_t extinction_rgb_stride = 0;
    float* in_scattering_rgb = nullptr;
    std::size_t in_scattering_rgb_stride = 0;
    float* sun_irradiance_rgb = nullptr;
    std::size_t sun_irradiance_rgb_stride = 0;
    /// The layout of the three *_rgba8 outputs (the names keep "rgba8" for every format). With
    /// a stride they go straight into the colour field of interleaved engine vertices.
    ColourFormat colour_format = ColourFormat::rgba8;
};

/// Which implementation computes the model.
enum class Kernel {
    simd,       ///< Highway SIMD (hoffman-preetham, height), accurate exp/log: within 0.5 LSB
    simd_fast,  ///< Highway SIMD with lower-degree polynomials: faster, error measured (< 1 LSB)
    scalar,     ///< plain loop over scatter<float> with std::exp; the only one for `reference`
};

struct BatchSettings {
    Display display;
    Kernel kernel = Kernel::simd;
    /// Worker threads, including the caller's: 0 = all hardware threads, 1 = the caller only.
    /// The workers are created on first need and kept (joined at exit); a split batch is cut
    /// into contiguous pieces, each the part left over twice the threads (large first, small
    /// last), taken by whichever thread is free. One batch at a time uses them: a call made
    /// while another application thread's batch has them runs alone.
    unsigned threads = 0;
    /// Batches smaller than this many vertices per thread are not split (no thread overhead).
    std::size_t min_vertices_per_thread = 32768;
    const Lighting* lighting = nullptr;  ///< required by lit_rgba8
};

struct BatchStats {
    std::size_t vertices = 0;          ///< shaded
    std::size_t invalid_vertices = 0;  ///< not positions (see the 8-bit rule above)
    unsigned threads_used = 1;
};

/// Shades every vertex of `positions` into `outputs`. With the hoffman-preetham or height model,
/// a SIMD kernel, and only RGBA8 outputs (extinction, lit, in-scattering; clamp curve for the
/// last two), the vertices go from positions to codes in one pass, with no float arrays in
/// between (the fastest case). The codes are the 8-bit rule applied to the model's values: those
/// the float path's values give, except that for F_ex and L_in alone with the 2002 model (255
/// and the exposure folded into the kernel's constants) a code may differ from that by one step
/// where the value lies within float rounding (1e-6 relative) of a rounding boundary.
/// Errors (nothing is written): a null array
/// with count > 0, a stride smaller than its element, lit_rgba8 without lighting normals,
/// exposure <= 0 or not finite, no output at all, a model matrix that is not finite and affine.
/// `reference` runs on the scalar kernel whatever
/// `settings.kernel` says.
Result<BatchStats> shade_into(const Frame<float>& frame, const Positions& positions,
                              const BatchOutputs& outputs, const BatchSettings& settings = {});

/// The Highway target the SIMD kernels run on here ("AVX2", "AVX3", "SSE4", ...).
const char* simd_target();

}  // namespace aerial
