// The batch API: validation, splitting into threads and blocks, gathering strided positions into
// structure-of-arrays blocks for the kernels, and packing their float results into the caller's
// RGBA8 / float arrays.
#include "aerial/batch.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

#include "../common/error_text.hpp"
#include "batch_kernels.hpp"
#include "worker_pool.hpp"

namespace aerial {
namespace {

using detail::kBlockSize;

const float* advance(const float* p, std::size_t bytes) {
    return reinterpret_cast<const float*>(reinterpret_cast<const unsigned char*>(p) + bytes);
}

/// Reads n positions from `first` into x, y, z, through the model matrix when there is one
/// (column-major, affine; computed in double, rounded once).
void load_positions(const Positions& pos, std::size_t first, std::size_t n, float* x, float* y,
                    float* z) {
    const float* m = pos.model_matrix;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t offset = (first + i) * pos.stride_bytes;
        const double px = *advance(pos.x, offset), py = *advance(pos.y, offset),
                     pz = *advance(pos.z, offset);
        if (!m) {
            x[i] = float(px), y[i] = float(py), z[i] = float(pz);
            continue;
        }
        x[i] = float(double(m[0]) * px + double(m[4]) * py + double(m[8]) * pz + double(m[12]));
        y[i] = float(double(m[1]) * px + double(m[5]) * py + double(m[9]) * pz + double(m[13]));
        z[i] = float(double(m[2]) * px + double(m[6]) * py + double(m[10]) * pz + double(m[14]));
    }
}

/// Rewrites the RGBA8 codes of [first, last) of one output in `format`, in place.
void convert_codes(std::uint8_t* base, std::size_t stride, std::size_t first, std::size_t last,
                   ColourFormat format) {
    if (!base || format == ColourFormat::rgba8) return;
    for (std::size_t i = first; i < last; ++i) {
        std::uint8_t* p = base + i * stride;
        store_colour(p, format, p[0], p[1], p[2], p[3]);
    }
}

/// Scratch of one block, in structure-of-arrays form.
struct BlockScratch {
    alignas(64) float x[kBlockSize];
    alignas(64) float y[kBlockSize];
    alignas(64) float z[kBlockSize];
    alignas(64) float extinction[3][kBlockSize];
    alignas(64) float in_scattering[3][kBlockSize];
    alignas(64) float sun_irradiance[3][kBlockSize];
};

struct Plan {
    const Frame<float>& frame;
    const Positions& positions;
    const BatchOutputs& out;
    const BatchSettings& settings;
    /// hoffman-preetham or height on the SIMD kernels with only RGBA8 outputs (clamp curve):
    /// one pass from positions to codes (detail::shade_rgba8).
    bool one_pass_rgba8;
    bool need_extinction;
    bool need_in_scattering;
    bool need_sun;
    std::size_t extinction_rgba8_stride;
    std::size_t lit_rgba8_stride;
    std::size_t in_scattering_rgba8_stride;
    std::size_t extinction_rgb_stride;
    std::size_t in_scattering_rgb_stride;
    std::size_t sun_irradiance_rgb_stride;
    std::size_t normal_stride;
};

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#error "store_rgba8 packs R, G, B, A into little-endian 32-bit words"
#endif

/// Writes RGBA8 codes of value * scale (the 8-bit rule, see batch.hpp) for n vertices.
void store_rgba8(std::uint8_t* base, std::size_t stride, std::size_t first, std::size_t n,
                 const float (&value)[3][kBlockSize], float scale = 1.0f) {
    alignas(64) std::uint32_t packed[kBlockSize];  // R, G, B, A bytes in memory order
    detail::pack_rgba8(value[0], value[1], value[2], n, scale, packed);
    if (stride == 4) {
        std::memcpy(base + first * 4, packed, n * 4);
        return;
    }
    for (std::size_t i = 0; i < n; ++i) std::memcpy(base + (first + i) * stride, &packed[i], 4);
}

void store_rgb(float* base, std::size_t stride_bytes, std::size_t first, std::size_t n,
               const float (&value)[3][kBlockSize]) {
    auto* bytes = reinterpret_cast<unsigned char*>(base);
    for (std::size_t i = 0; i < n; ++i) {
        float* rgb = reinterpret_cast<float*>(bytes + (first + i) * stride_bytes);
        rgb[0] = value[0][i];
        rgb[1] = value[1][i];
        rgb[2] = value[2][i];
    }
}

/// Writes RGBA8 codes of display_value(display, value): the clamp curve is the packer's scale
/// and clamp; the exponential curve is applied first, in place.
void store_display_rgba8(const Display& display, std::uint8_t* base, std::size_t stride,
                         std::size_t first, std::size_t n, float (&value)[3][kBlockSize]) {
    if (display.tone == ToneCurve::clamp) {
        store_rgba8(base, stride, first, n, value, display.exposure);
        return;
    }
    for (int c = 0; c < 3; ++c) {
        for (std::size_t i = 0; i < n; ++i) value[c][i] = display_value(display, value[c][i]);
    }
    store_rgba8(base, stride, first, n, value);
}

/// The one-pass path: positions straight to codes, through a scratch block only for strided
/// positions.
std::size_t shade_range_rgba8(const Plan& plan, std::size_t first, std::size_t last) {
    const Positions& pos = plan.positions;
    const BatchOutputs& out = plan.out;
    const detail::KernelPrecision precision = plan.settings.kernel == Kernel::simd_fast
                                                  ? detail::KernelPrecision::fast
                                                  : detail::KernelPrecision::accurate;
    detail::Rgba8Job job;
    job.exposure = plan.settings.display.exposure;
    job.exponential_tone = plan.settings.display.tone == ToneCurve::exponential;
    job.extinction_stride = plan.extinction_rgba8_stride;
    job.lit_stride = plan.lit_rgba8_stride;
    job.in_scattering_stride = plan.in_scattering_rgba8_stride;
    job.normal_stride = plan.normal_stride;
    const Lighting* light = out.lit_rgba8 ? plan.settings.lighting : nullptr;
    if (light) {
        for (int c = 0; c < 3; ++c) {
            job.ambient[c] = light->ambient[c];
            job.albedo[c] = light->albedo[c];
        }
    }
    auto point_outputs_at = [&](std::size_t begin) {
        job.extinction =
            out.extinction_rgba8 ? out.extinction_rgba8 + begin * job.extinction_stride : nullptr;
        job.lit = light ? out.lit_rgba8 + begin * job.lit_stride : nullptr;
        job.normals = light ? advance(light->normals, begin * job.normal_stride) : nullptr;
        job.in_scattering = out.in_scattering_rgba8
                                ? out.in_scattering_rgba8 + begin * job.in_scattering_stride
                                : nullptr;
    };
    const bool packed_xyz = pos.x != nullptr && pos.stride_bytes == 3 * sizeof(float) &&
                            pos.y == pos.x + 1 && pos.z == pos.x + 2 && !pos.model_matrix;
    if (packed_xyz || (pos.stride_bytes == sizeof(float) && !pos.model_matrix)) {
        job.packed_xyz = packed_xyz;
        job.x = packed_xyz ? pos.x + 3 * first : pos.x + first;
        job.y = packed_xyz ? nullptr : pos.y + first;
        job.z = packed_xyz ? nullptr : pos.z + first;
        job.count = last - first;
        point_outputs_at(first);
        return detail::shade_rgba8(plan.frame, job, precision);
    }
    alignas(64) float x[kBlockSize], y[kBlockSize], z[kBlockSize];
    std::size_t invalid = 0;
    for (std::size_t begin = first; begin < last; begin += kBlockSize) {
        const std::size_t n = std::min(kBlockSize, last - begin);
        load_positions(pos, begin, n, x, y, z);
        job.x = x;
        job.y = y;
        job.z = z;
        job.count = n;
        point_outputs_at(begin);
        invalid += detail::shade_rgba8(plan.frame, job, precision);
    }
    return invalid;
}

/// Shades vertices [first, last) block by block as RGBA8 codes; returns the invalid-vertex
/// count.
std::size_t shade_range_codes(const Plan& plan, std::size_t first, std::size_t last) {
    if (plan.one_pass_rgba8) return shade_range_rgba8(plan, first, last);
    const Positions& pos = plan.positions;
    const BatchOutputs& out = plan.out;
    const bool simd = !is_numerical(plan.frame.model) && plan.settings.kernel != Kernel::scalar;
    const detail::KernelPrecision precision = plan.settings.kernel == Kernel::simd_fast
                                                  ? detail::KernelPrecision::fast
                                                  : detail::KernelPrecision::accurate;
    // Tightly packed x, y, z records (the common AoS layout) are split with SIMD loads.
    const bool packed_xyz = pos.x != nullptr && pos.stride_bytes == 3 * sizeof(float) &&
                            pos.y == pos.x + 1 && pos.z == pos.x + 2 && !pos.model_matrix;
    BlockScratch scratch;
    std::size_t invalid = 0;
    for (std::size_t begin = first; begin < last; begin += kBlockSize) {
        const std::size_t n = std::min(kBlockSize, last - begin);
        if (packed_xyz) {
            detail::deinterleave3(pos.x + 3 * begin, n, scratch.x, scratch.y, scratch.z);
        } else {
            load_positions(pos, begin, n, scratch.x, scratch.y, scratch.z);
        }
        detail::KernelBlock block;
        block.x = scratch.x;
        block.y = scratch.y;
        block.z = scratch.z;
        block.count = n;
        for (int c = 0; c < 3; ++c) {
            if (plan.need_extinction) block.extinction[c] = scratch.extinction[c];
            if (plan.need_in_scattering) block.in_scattering[c] = scratch.in_scattering[c];
            if (plan.need_sun) block.sun_irradiance[c] = scratch.sun_irradiance[c];
        }
        invalid += simd ? detail::shade_block_simd(plan.frame, block, precision)
                        : detail::shade_block_scalar(plan.frame, block);

        if (out.extinction_rgb) {
            store_rgb(out.extinction_rgb, plan.extinction_rgb_stride, begin, n, scratch.extinction);
        }
        if (out.in_scattering_rgb) {
            store_rgb(out.in_scattering_rgb, plan.in_scattering_rgb_stride, begin, n,
                      scratch.in_scattering);
        }
        if (out.sun_irradiance_rgb) {
            store_rgb(out.sun_irradiance_rgb, plan.sun_irradiance_rgb_stride, begin, n,
                      scratch.sun_irradiance);
        }
        if (out.extinction_rgba8) {
            store_rgba8(out.extinction_rgba8, plan.extinction_rgba8_stride, begin, n,
                        scratch.extinction);
        }
        if (out.in_scattering_rgba8) {
            store_display_rgba8(plan.settings.display, out.in_scattering_rgba8,
                                plan.in_scattering_rgba8_stride, begin, n, scratch.in_scattering);
        }
        if (out.lit_rgba8) {
            // F_ex x albedo x (E_sun max(N.L, 0) + ambient), written over the sun scratch.
            const Lighting& light = *plan.settings.lighting;
            const glm::vec3 sun = plan.frame.sun_dir;
            for (std::size_t i = 0; i < n; ++i) {
                const float* normal = advance(light.normals, (begin + i) * plan.normal_stride);
                const float n_dot_l =
                    std::max(normal[0] * sun.x + normal[1] * sun.y + normal[2] * sun.z, 0.0f);
                for (int c = 0; c < 3; ++c) {
                    scratch.sun_irradiance[c][i] =
                        lit_value(scratch.extinction[c][i], light.albedo[c],
                                  scratch.sun_irradiance[c][i], n_dot_l, light.ambient[c]);
                }
            }
            store_display_rgba8(plan.settings.display, out.lit_rgba8, plan.lit_rgba8_stride, begin,
                                n, scratch.sun_irradiance);
        }
    }
    return invalid;
}

/// Shades vertices [first, last) into the outputs in their colour format.
std::size_t shade_range(const Plan& plan, std::size_t first, std::size_t last) {
    const std::size_t invalid = shade_range_codes(plan, first, last);
    const ColourFormat format = plan.out.colour_format;
    convert_codes(plan.out.extinction_rgba8, plan.extinction_rgba8_stride, first, last, format);
    convert_codes(plan.out.lit_rgba8, plan.lit_rgba8_stride, first, last, format);
    convert_codes(plan.out.in_scattering_rgba8, plan.in_scattering_rgba8_stride, first, last,
                  format);
    return invalid;
}

/// Smallest piece of a split batch, in blocks (2048 vertices, a few microseconds of work).
constexpr std::size_t kMinPieceBlocks = 8;

constexpr const char* kShadeInto = "shade_into";

std::optional<Error> check_stride(const char* field, std::size_t stride, std::size_t element) {
    if (stride != 0 && stride < element) {
        return detail::invalid(kShadeInto, field,
                               "0 (packed) or >= " + detail::number(element) + " bytes",
                               detail::number(stride));
    }
    return std::nullopt;
}

}  // namespace

std::optional<Error> validate_model_matrix(const float* m) {
    constexpr const char* kFunction = "validate_model_matrix";
    if (!m) return std::nullopt;
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(m[i])) {
            return detail::invalid(kFunction, "model_matrix", "16 finite numbers",
                                   "element " + detail::number(i) + " = " + detail::number(m[i]));
        }
    }
    if (m[3] != 0.0f || m[7] != 0.0f || m[11] != 0.0f || m[15] != 1.0f) {
        return detail::invalid(kFunction, "model_matrix",
                               "an affine matrix (bottom row 0, 0, 0, 1; column-major m[3], m[7], "
                               "m[11], m[15])",
                               detail::vector(std::array<float, 4>{m[3], m[7], m[11], m[15]}));
    }
    return std::nullopt;
}

const char* colour_format_name(ColourFormat format) {
    switch (format) {
        case ColourFormat::rgba8:
            return "rgba8";
        case ColourFormat::bgra8:
            return "bgra8";
        case ColourFormat::argb32:
            return "argb32";
    }
    return "unknown";
}

Result<BatchStats> shade_into(const Frame<float>& frame, const Positions& positions,
                              const BatchOutputs& out, const BatchSettings& settings) {
    if (positions.count > 0 && (!positions.x || !positions.y || !positions.z)) {
        return detail::error(kShadeInto, "positions",
                             "a null array for " + detail::number(positions.count) + " vertices");
    }
    if (positions.count > 0 && positions.stride_bytes < sizeof(float)) {
        return detail::invalid(kShadeInto, "positions.stride_bytes", ">= 4",
                               detail::number(positions.stride_bytes));
    }
    if (!out.extinction_rgba8 && !out.lit_rgba8 && !out.in_scattering_rgba8 &&
        !out.extinction_rgb && !out.in_scattering_rgb && !out.sun_irradiance_rgb) {
        return detail::error(kShadeInto, "outputs", "no output array is set");
    }
    const struct {
        const char* field;
        std::size_t stride;
        std::size_t element;
    } strides[] = {{"extinction_rgba8_stride", out.extinction_rgba8_stride, 4},
                   {"lit_rgba8_stride", out.lit_rgba8_stride, 4},
                   {"in_scattering_rgba8_stride", out.in_scattering_rgba8_stride, 4},
                   {"extinction_rgb_stride", out.extinction_rgb_stride, 12},
                   {"in_scattering_rgb_stride", out.in_scattering_rgb_stride, 12},
                   {"sun_irradiance_rgb_stride", out.sun_irradiance_rgb_stride, 12}};
    for (const auto& s : strides) {
        if (auto e = check_stride(s.field, s.stride, s.element)) return *e;
    }
    if (out.lit_rgba8 && (!settings.lighting || !settings.lighting->normals)) {
        return detail::invalid(kShadeInto, "lighting", "normals for lit_rgba8", "none");
    }
    if (settings.lighting) {
        if (auto e = check_stride("lighting.normal_stride_bytes",
                                  settings.lighting->normal_stride_bytes, 12)) {
            return *e;
        }
    }
    if (auto e = validate_model_matrix(positions.model_matrix)) {
        return detail::from(kShadeInto, *e, "positions.");
    }
    if (out.colour_format != ColourFormat::rgba8 && out.colour_format != ColourFormat::bgra8 &&
        out.colour_format != ColourFormat::argb32) {
        return detail::invalid(kShadeInto, "outputs.colour_format", "rgba8, bgra8 or argb32",
                               detail::number(int(out.colour_format)));
    }
    if (!std::isfinite(settings.display.exposure) || settings.display.exposure <= 0.0f) {
        return detail::invalid(kShadeInto, "display.exposure", "a finite value > 0",
                               detail::number(settings.display.exposure));
    }

    auto packed = [](std::size_t stride, std::size_t element) { return stride ? stride : element; };
    const bool one_pass_rgba8 =
        (frame.model == Model::hoffman_preetham || frame.model == Model::height) &&
        settings.kernel != Kernel::scalar && !out.extinction_rgb && !out.in_scattering_rgb &&
        !out.sun_irradiance_rgb;
    const Plan plan{frame,
                    positions,
                    out,
                    settings,
                    one_pass_rgba8,
                    out.extinction_rgba8 || out.lit_rgba8 || out.extinction_rgb,
                    out.in_scattering_rgba8 || out.in_scattering_rgb,
                    out.lit_rgba8 || out.sun_irradiance_rgb,
                    packed(out.extinction_rgba8_stride, 4),
                    packed(out.lit_rgba8_stride, 4),
                    packed(out.in_scattering_rgba8_stride, 4),
                    packed(out.extinction_rgb_stride, 12),
                    packed(out.in_scattering_rgb_stride, 12),
                    packed(out.sun_irradiance_rgb_stride, 12),
                    settings.lighting ? packed(settings.lighting->normal_stride_bytes, 12) : 12};

    BatchStats stats;
    stats.vertices = positions.count;
    // Asked once: glibc reads /sys on every call (about 10 us, as long as shading 3000 vertices).
    static const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    const unsigned wanted = settings.threads ? settings.threads : hardware;
    const std::size_t per_thread = std::max<std::size_t>(settings.min_vertices_per_thread, 1);
    const unsigned threads = static_cast<unsigned>(
        std::max<std::size_t>(1, std::min<std::size_t>(wanted, positions.count / per_thread)));
    stats.threads_used = threads;
    if (threads == 1) {
        stats.invalid_vertices = shade_range(plan, 0, positions.count);
        return stats;
    }
    // Whole blocks in guided pieces (WorkerPool::run), taken by whichever thread is free: a
    // thread that starts late or is slowed down by other work on the machine takes fewer.
    const std::size_t blocks = (positions.count + kBlockSize - 1) / kBlockSize;
    const std::size_t min_piece =
        std::clamp<std::size_t>(blocks / (std::size_t(threads) * 16), 1, kMinPieceBlocks);
    std::atomic<std::size_t> invalid{0};
    stats.threads_used = detail::WorkerPool::instance().run(
        threads, blocks, min_piece, [&](std::size_t first_block, std::size_t last_block) {
            const std::size_t first = std::min(positions.count, first_block * kBlockSize);
            const std::size_t last = std::min(positions.count, last_block * kBlockSize);
            invalid.fetch_add(shade_range(plan, first, last), std::memory_order_relaxed);
        });
    stats.invalid_vertices = invalid.load();
    return stats;
}

const char* simd_target() { return detail::simd_target_name(); }

}  // namespace aerial
