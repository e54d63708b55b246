// The fixed-function paths (aerial/gl.hpp): colour = texture × F_ex + L_in with CPU colours.
#include <array>
#include <climits>
#include <string>
#include <utility>
#include <vector>

#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "pass_state.hpp"
#include "state_saver.hpp"
#include "texture_owner.hpp"

namespace aerial::gl {

constexpr aerial::detail::NameTable<Path, 4> kPathNames{{{Path::automatic, "automatic"},
                                                         {Path::secondary_color, "secondary-color"},
                                                         {Path::combiner, "combiner"},
                                                         {Path::two_pass, "two-pass"}}};

const char* path_name(Path path) { return aerial::detail::name_in(kPathNames, path, "automatic"); }

std::optional<Path> parse_path(std::string_view name) {
    return aerial::detail::find_in(kPathNames, name);
}

namespace {

std::string context_text(const Caps& caps) {
    return "the context has GL " + std::to_string(caps.version_major) + "." +
           std::to_string(caps.version_minor) + " (" + caps.renderer + ")";
}

constexpr const char* kChoosePath = "gl::choose_path";
constexpr const char* kCombinerCreate = "gl::CombinerTexture::create";
constexpr const char* kDraw = "gl::draw_with_colours";

// "<extension>: the <path> path needs <version> or <extension>; the context has ... without it".
Error path_needs(const Caps& caps, const std::string& extension, const char* path,
                 const char* version) {
    return aerial::detail::unsupported(kChoosePath, extension,
                                       "the " + std::string(path) + " path needs " + version +
                                           " or " + extension + "; " + context_text(caps) +
                                           " without it");
}

// Why `path` cannot run on `caps`, or nullopt when it can.
std::optional<Error> missing_for(const Caps& caps, Path path) {
    switch (path) {
        case Path::secondary_color:
            if (!caps.secondary_color) {
                return path_needs(caps, "GL_EXT_secondary_color", "secondary-color", "GL 1.4");
            }
            return std::nullopt;
        case Path::combiner:
            if (!caps.multitexture || caps.max_texture_units < 2) {
                return aerial::detail::unsupported(
                    kChoosePath, "GL_ARB_multitexture",
                    "the combiner path needs GL 1.3 or GL_ARB_multitexture with 2 texture "
                    "units; " +
                        context_text(caps) + " with " +
                        aerial::detail::number(caps.max_texture_units) + " unit(s)");
            }
            if (!caps.texture_env_combine) {
                return path_needs(caps, "GL_ARB_texture_env_combine", "combiner", "GL 1.3");
            }
            if (!caps.texture_3d) return path_needs(caps, "GL_EXT_texture3D", "combiner", "GL 1.2");
            return std::nullopt;
        case Path::two_pass:
        case Path::automatic:
            return std::nullopt;
    }
    return std::nullopt;
}

}  // namespace

Result<Path> choose_path(const Caps& caps, Path requested, bool fixed_function_lighting) {
    if (requested == Path::automatic) {
        for (Path p : {Path::secondary_color, Path::combiner}) {
            if (p == Path::secondary_color && fixed_function_lighting) continue;
            if (!missing_for(caps, p)) return p;
        }
        return Path::two_pass;
    }
    if (requested == Path::secondary_color && fixed_function_lighting) {
        return aerial::detail::error(
            kChoosePath, "fixed_function_lighting",
            "the secondary-color path cannot add L_in while GL lighting is on "
            "(lighting replaces the secondary colour); use the combiner or "
            "two-pass path, or bake lighting with aerial::shade_into's "
            "lit_rgba8");
    }
    if (auto missing = missing_for(caps, requested)) return *missing;
    return requested;
}

// ---- CombinerTexture ---------------------------------------------------------------------------

Result<CombinerTexture> CombinerTexture::create(const Api& api, int size) {
    if (auto e = no_current_context(api)) return aerial::detail::from(kCombinerCreate, *e);
    if (!api.caps.texture_3d || api.TexImage3D == nullptr) {
        return aerial::detail::unsupported(
            kCombinerCreate, "combiner",
            "the identity texture needs GL 1.2 or GL_EXT_texture3D; " + context_text(api.caps) +
                " without it");
    }
    if (size < 2 || size > 18 || 255 % (size - 1) != 0) {
        return aerial::detail::invalid(kCombinerCreate, "size",
                                       "2, 4, 6, 16 or 18 texels a side (255 / (size - 1) whole)",
                                       aerial::detail::number(size));
    }
    // Texel (i, j, k) = (i, j, k) × 255 / (size - 1), exact; RGBA rows of 4 size bytes, so any
    // UNPACK_ALIGNMENT up to 8 reads them right; the other unpack state is set to its defaults
    // and restored.
    const auto n = static_cast<std::size_t>(size);
    const int step = 255 / (size - 1);
    std::vector<GLubyte> texels(n * n * n * 4);
    for (std::size_t k = 0; k < n; ++k) {
        for (std::size_t j = 0; j < n; ++j) {
            for (std::size_t i = 0; i < n; ++i) {
                GLubyte* t = &texels[((k * n + j) * n + i) * 4];
                t[0] = static_cast<GLubyte>(step * static_cast<int>(i));
                t[1] = static_cast<GLubyte>(step * static_cast<int>(j));
                t[2] = static_cast<GLubyte>(step * static_cast<int>(k));
                t[3] = 255;
            }
        }
    }
    static constexpr std::array<GLenum, 7> kUnpack{
        GL_UNPACK_ALIGNMENT,    GL_UNPACK_ROW_LENGTH,  GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_PIXELS,
        GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_IMAGES, GL_UNPACK_SWAP_BYTES};
    static constexpr std::array<GLint, 7> kDefaults{4, 0, 0, 0, 0, 0, GL_FALSE};
    std::array<GLint, 7> unpack{};
    for (std::size_t i = 0; i < kUnpack.size(); ++i) {
        api.GetIntegerv(kUnpack[i], &unpack[i]);
        api.PixelStorei(kUnpack[i], kDefaults[i]);
    }
    GLint unpack_buffer = 0;
    if (api.caps.pixel_buffer_object) {
        api.GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack_buffer);
        api.BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    }
    GLint bound = 0;
    api.GetIntegerv(GL_TEXTURE_BINDING_3D, &bound);
    GLuint id = 0;
    api.GenTextures(1, &id);
    api.BindTexture(GL_TEXTURE_3D, id);
    api.TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    api.TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    api.TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    api.TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    api.TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    api.TexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
    api.TexImage3D(GL_TEXTURE_3D, 0, GL_RGBA8, size, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                   texels.data());
    api.BindTexture(GL_TEXTURE_3D, static_cast<GLuint>(bound));
    if (api.caps.pixel_buffer_object) {
        api.BindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpack_buffer));
    }
    for (std::size_t i = 0; i < kUnpack.size(); ++i) api.PixelStorei(kUnpack[i], unpack[i]);
    return CombinerTexture(&api, id, size);
}

CombinerTexture::CombinerTexture(CombinerTexture&& other) noexcept
    : api_(other.api_),
      id_(std::exchange(other.id_, 0u)),
      size_(other.size_),
      texcoords_(std::move(other.texcoords_)) {}

CombinerTexture& CombinerTexture::operator=(CombinerTexture&& other) noexcept {
    if (this != &other) {
        detail::take_texture(api_, id_, other.api_, other.id_);
        size_ = other.size_;
        texcoords_ = std::move(other.texcoords_);
    }
    return *this;
}

CombinerTexture::~CombinerTexture() { detail::release_texture(api_, id_); }

const float* CombinerTexture::texcoords_for(const VertexColours& colours) {
    const std::size_t n = colours.vertex_count;
    texcoords_.resize(3 * n);
    const std::size_t stride = colours.secondary_stride_bytes ? colours.secondary_stride_bytes : 4;
    // Texel centres are at (i + 0.5) / size: (0.5 + (size - 1) c / 255) / size puts c / 255
    // of the way from the first to the last, where the linear filter returns c.
    const float offset = 0.5f / static_cast<float>(size_);
    const float scale = static_cast<float>(size_ - 1) / (255.0f * static_cast<float>(size_));
    for (std::size_t v = 0; v < n; ++v) {
        const std::uint8_t* c = colours.secondary + v * stride;
        float* t = &texcoords_[3 * v];
        t[0] = offset + scale * static_cast<float>(c[0]);
        t[1] = offset + scale * static_cast<float>(c[1]);
        t[2] = offset + scale * static_cast<float>(c[2]);
    }
    return texcoords_.data();
}

// ---- draw_with_colours -------------------------------------------------------------------------

namespace {

std::optional<Error> check_stride(const char* field, std::size_t stride) {
    if (stride != 0 && (stride < 4 || stride > static_cast<std::size_t>(INT_MAX))) {
        return aerial::detail::invalid(
            kDraw, field, "0 (packed) or 4 .. " + aerial::detail::number(INT_MAX) + " bytes",
            aerial::detail::number(stride));
    }
    return std::nullopt;
}

}  // namespace

namespace detail {

// State every path sets the same way: no vertex, fragment or GLSL program (they would bypass
// the fixed pipeline), no fixed-function lighting unless the options keep it (it replaces the
// primary colour; bake lighting with aerial::shade_into's lit_rgba8 instead), and the engine's
// texture modulated on `unit` (or texturing off there when the engine draws untextured).
void common_state(const Api& api, StateSaver& s, const ApplyOptions& options) {
    if (api.caps.vertex_program) s.enable(GL_VERTEX_PROGRAM_ARB, false);
    if (api.caps.fragment_program) s.enable(GL_FRAGMENT_PROGRAM_ARB, false);
    s.use_no_glsl_program();
    if (!options.fixed_function_lighting) s.enable(GL_LIGHTING, false);
    if (options.textured) {
        s.tex_env(options.texture_unit, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    } else {
        s.unit_disable_all_targets(options.texture_unit);
    }
}

}  // namespace detail

Result<ApplyStats> draw_with_colours(const Api& api, const ApplyOptions& options,
                                     const VertexColours& colours,
                                     const std::function<void()>& draw) {
    if (auto e = no_current_context(api)) return aerial::detail::from(kDraw, *e);
    if (colours.primary == nullptr) {
        return aerial::detail::error(kDraw, "colours.primary", "the F_ex array is null");
    }
    if (colours.secondary == nullptr) {
        return aerial::detail::error(kDraw, "colours.secondary", "the L_in array is null");
    }
    if (colours.vertex_count == 0) {
        return aerial::detail::invalid(kDraw, "colours.vertex_count", "> 0", "0");
    }
    if (auto e = check_stride("colours.primary_stride_bytes", colours.primary_stride_bytes)) {
        return *e;
    }
    if (auto e = check_stride("colours.secondary_stride_bytes", colours.secondary_stride_bytes)) {
        return *e;
    }
    if (!draw) return aerial::detail::error(kDraw, "draw", "the draw callback is empty");
    auto chosen = choose_path(api.caps, options.path, options.fixed_function_lighting);
    if (!chosen) return aerial::detail::from(kDraw, chosen.error());
    const Path path = *chosen;
    const int units_needed = path == Path::combiner ? 2 : 1;
    if (options.texture_unit < 0 ||
        options.texture_unit + units_needed > api.caps.max_texture_units) {
        return aerial::detail::invalid(
            kDraw, "texture_unit",
            "0 .. " + aerial::detail::number(api.caps.max_texture_units - units_needed) + " (the " +
                path_name(path) + " path uses " + aerial::detail::number(units_needed) +
                " unit(s) of the context's " + aerial::detail::number(api.caps.max_texture_units) +
                ")",
            aerial::detail::number(options.texture_unit));
    }
    std::optional<CombinerTexture> temporary;
    CombinerTexture* combiner = options.combiner;
    if (path == Path::combiner && combiner != nullptr && combiner->id() == 0) {
        return aerial::detail::error(kDraw, "combiner",
                                     "the CombinerTexture was moved from (texture name 0)");
    }
    if (path == Path::combiner && combiner == nullptr) {
        auto created = CombinerTexture::create(api);
        if (!created) return created.error();
        temporary.emplace(std::move(created).value());
        combiner = &*temporary;
    }

    // Stride 0 would mean 3 bytes to glSecondaryColorPointer (3 components): always explicit.
    const auto primary_stride =
        static_cast<GLsizei>(colours.primary_stride_bytes ? colours.primary_stride_bytes : 4);
    const auto secondary_stride =
        static_cast<GLsizei>(colours.secondary_stride_bytes ? colours.secondary_stride_bytes : 4);
    const int unit = options.texture_unit;
    ApplyStats stats;
    stats.path = path;
    StateSaver s(api);
    detail::common_state(api, s, options);
    std::optional<Error> error;  // what the engine's draw changed (detail::check_*)
    switch (path) {
        case Path::secondary_color:
            s.color_array(4, GL_UNSIGNED_BYTE, primary_stride, colours.primary);
            s.secondary_color_array(3, GL_UNSIGNED_BYTE, secondary_stride, colours.secondary);
            s.enable(GL_COLOR_SUM, true);
            s.rebind_engine_array_buffer();
            draw();
            error = detail::check_colour_array(api, kDraw, colours.primary, false);
            if (!error) error = detail::check_colour_array(api, kDraw, colours.secondary, true);
            stats.passes = 1;
            break;
        case Path::combiner: {
            // Unit u: texture × F_ex (MODULATE, as in the other paths). Unit u + 1: previous +
            // the identity texture sampled where its linear filter returns L_in, interpolated per
            // pixel like a colour (see CombinerTexture). Alpha passes through.
            const int next = unit + 1;
            s.color_array(4, GL_UNSIGNED_BYTE, primary_stride, colours.primary);
            if (options.fixed_function_lighting) s.color_material();
            if (api.caps.secondary_color) s.enable(GL_COLOR_SUM, false);
            s.unit_disable_all_targets(next);
            for (GLenum gen : {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R}) {
                s.unit_enable(next, gen, false);
            }
            s.unit_enable(next, GL_TEXTURE_3D, true);
            s.bind_texture(next, GL_TEXTURE_3D, combiner->id());
            s.texture_matrix_identity(next);
            s.tex_env(next, GL_TEXTURE_ENV_MODE, GL_COMBINE);
            s.tex_env(next, GL_COMBINE_RGB, GL_ADD);
            s.tex_env(next, GL_SOURCE0_RGB, GL_PREVIOUS);
            s.tex_env(next, GL_OPERAND0_RGB, GL_SRC_COLOR);
            s.tex_env(next, GL_SOURCE1_RGB, GL_TEXTURE);
            s.tex_env(next, GL_OPERAND1_RGB, GL_SRC_COLOR);
            s.tex_env(next, GL_RGB_SCALE, 1);
            s.tex_env(next, GL_COMBINE_ALPHA, GL_REPLACE);
            s.tex_env(next, GL_SOURCE0_ALPHA, GL_PREVIOUS);
            s.tex_env(next, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
            s.tex_env(next, GL_ALPHA_SCALE, 1);
            s.texcoord_array(next, 3, GL_FLOAT, 0, combiner->texcoords_for(colours));
            s.rebind_engine_array_buffer();
            draw();
            error = detail::check_colour_array(api, kDraw, colours.primary, false);
            stats.passes = 1;
            break;
        }
        case Path::two_pass: {
            // Pass 1: texture × F_ex with the engine's own depth, blend and fog state.
            s.color_array(4, GL_UNSIGNED_BYTE, primary_stride, colours.primary);
            if (options.fixed_function_lighting) s.color_material();
            if (api.caps.secondary_color) s.enable(GL_COLOR_SUM, false);
            s.rebind_engine_array_buffer();
            draw();
            error = detail::check_colour_array(api, kDraw, colours.primary, false);
            stats.passes = 1;
            if (error) break;
            detail::in_scattering_pass_state(api, s, options);
            s.color_array(4, GL_UNSIGNED_BYTE, secondary_stride, colours.secondary);
            s.rebind_engine_array_buffer();
            draw();
            error = detail::check_colour_array(api, kDraw, colours.secondary, false);
            if (!error) error = detail::check_in_scattering_state(api, kDraw);
            stats.passes = 2;
            break;
        }
        case Path::automatic:
            break;
    }
    s.restore();
    if (error) return *error;
    return stats;
}

}  // namespace aerial::gl
