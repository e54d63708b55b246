// The sky cubemap and the sun sprite on the fixed pipeline (aerial/sky_gl.hpp).
#include "aerial/sky_gl.hpp"

#include <cmath>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/gl_api.hpp"
#include "state_saver.hpp"
#include "texture_owner.hpp"

namespace aerial::gl {
namespace {

/// Unpack state at its defaults (RGBA8 rows need nothing else) and client memory as the source,
/// all restored by the saver.
void default_unpack(StateSaver& s) {
    s.unbind_pixel_unpack_buffer();
    s.pixel_store(GL_UNPACK_ALIGNMENT, 4);
    s.pixel_store(GL_UNPACK_ROW_LENGTH, 0);
    s.pixel_store(GL_UNPACK_SKIP_ROWS, 0);
    s.pixel_store(GL_UNPACK_SKIP_PIXELS, 0);
    s.pixel_store(GL_UNPACK_SWAP_BYTES, GL_FALSE);
    s.pixel_store(GL_UNPACK_LSB_FIRST, GL_FALSE);
}

/// Binds texture `id` to `target` on unit 0 for an upload from client memory, with linear
/// filtering; `s` restores the unit and the unpack state.
void begin_upload(StateSaver& s, const Api& api, GLenum target, unsigned id) {
    default_unpack(s);
    s.bind_texture(0, target, id);
    api.TexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    api.TexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
}

GLint edge_clamp(const Caps& caps) {
    return caps.at_least(1, 2) || caps.has_extension("GL_SGIS_texture_edge_clamp") ||
                   caps.has_extension("GL_EXT_texture_edge_clamp")
               ? GL_CLAMP_TO_EDGE
               : GL_CLAMP;
}

using aerial::detail::invalid;
using aerial::detail::number;

std::optional<Error> check_faces(const char* function, const Api& api,
                                 const std::array<std::vector<std::uint8_t>, 6>& faces, int size) {
    GLint max_size = 0;
    api.GetIntegerv(GL_MAX_CUBE_MAP_TEXTURE_SIZE, &max_size);
    if (size < 1 || size > max_size) {
        return invalid(function, "size",
                       "1 .. " + number(max_size) + " (GL_MAX_CUBE_MAP_TEXTURE_SIZE)",
                       number(size));
    }
    const std::size_t expected = std::size_t(size) * std::size_t(size) * 4;
    for (std::size_t f = 0; f < 6; ++f) {
        if (faces[f].size() != expected) {
            return invalid(function, "faces", number(expected) + " bytes a face (size * size * 4)",
                           number(faces[f].size()) + " in face " + number(f));
        }
    }
    return std::nullopt;
}

Error no_cube_maps(const char* function, const Api& api) {
    return aerial::detail::unsupported(function, "cube_map",
                                       "the sky box needs GL 1.3 or GL_ARB_texture_cube_map; " +
                                           api.caps.version + " (" + api.caps.renderer +
                                           ") has neither");
}

Error not_perspective(const char* function) {
    return invalid(function, "projection", "a perspective projection with far >= 4 * near > 0",
                   "another matrix");
}

/// Perspective projection's near and far planes; false when it is not one.
bool near_far(const std::array<float, 16>& p, double& near_plane, double& far_plane) {
    if (std::abs(p[11] + 1.0f) > 1e-4f || std::abs(p[15]) > 1e-6f || std::abs(p[3]) > 1e-6f ||
        std::abs(p[7]) > 1e-6f) {
        return false;
    }
    near_plane = double(p[14]) / (double(p[10]) - 1.0);
    far_plane = double(p[14]) / (double(p[10]) + 1.0);
    return std::isfinite(near_plane) && std::isfinite(far_plane) && near_plane > 0 &&
           far_plane >= 4.0 * near_plane;
}

/// The far plane of the view a sprite is drawn in, after the checks every sky draw makes: a
/// current context and a perspective projection (errors under `function`'s name).
Result<double> sprite_far_plane(const Api& api, const SkyBoxView& view, const char* function) {
    if (auto e = no_current_context(api)) return aerial::detail::from(function, *e);
    double near_plane = 0, far_plane = 0;
    if (!near_far(view.projection, near_plane, far_plane)) return not_perspective(function);
    return far_plane;
}

/// The state both draws share: matrices, everything that would alter a plain textured quad off,
/// unit 0 textured with `target` and `texture` in GL_REPLACE mode.
void common_state(const Api& api, StateSaver& s, const SkyBoxView& view, GLenum target,
                  GLuint texture) {
    s.load_matrix(GL_PROJECTION, view.projection.data());
    s.load_matrix(GL_MODELVIEW, view.view_rotation.data());
    for (GLenum cap : {GL_DEPTH_TEST, GL_LIGHTING, GL_FOG, GL_BLEND, GL_ALPHA_TEST, GL_CULL_FACE}) {
        s.enable(cap, false);
    }
    s.depth_mask(false);
    if (api.caps.secondary_color) s.enable(GL_COLOR_SUM, false);
    if (api.caps.vertex_program) s.enable(GL_VERTEX_PROGRAM_ARB, false);
    if (api.caps.fragment_program) s.enable(GL_FRAGMENT_PROGRAM_ARB, false);
    s.use_no_glsl_program();
    for (int unit = 1; unit < detail::saved_texture_units(api.caps); ++unit) {
        s.unit_disable_all_targets(unit);
    }
    s.unit_disable_all_targets(0);
    for (GLenum gen : {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q}) {
        s.unit_enable(0, gen, false);
    }
    s.unit_enable(0, target, true);
    s.bind_texture(0, target, texture);
    s.texture_matrix_identity(0);
    s.tex_env(0, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    s.save_current_texcoord(0);
}

}  // namespace

bool cube_maps_supported(const Api& api) {
    return api.caps.at_least(1, 3) || api.caps.has_extension("GL_ARB_texture_cube_map") ||
           api.caps.has_extension("GL_EXT_texture_cube_map");
}

// ---- SkyCubemapTexture -----------------------------------------------------------------------

Result<SkyCubemapTexture> SkyCubemapTexture::create(
    const Api& api, const std::array<std::vector<std::uint8_t>, 6>& faces, int size) {
    constexpr const char* kFunction = "gl::SkyCubemapTexture::create";
    if (auto e = no_current_context(api)) return aerial::detail::from(kFunction, *e);
    if (!cube_maps_supported(api)) return no_cube_maps(kFunction, api);
    if (auto e = check_faces(kFunction, api, faces, size)) return *e;
    GLuint id = 0;
    api.GenTextures(1, &id);
    SkyCubemapTexture texture(api, id);
    if (auto e = texture.update(faces, size)) return aerial::detail::from(kFunction, *e);
    return texture;
}

std::optional<Error> SkyCubemapTexture::update(
    const std::array<std::vector<std::uint8_t>, 6>& faces, int size) {
    constexpr const char* kFunction = "gl::SkyCubemapTexture::update";
    if (auto e = no_current_context(*api_)) return aerial::detail::from(kFunction, *e);
    if (auto e = check_faces(kFunction, *api_, faces, size)) return e;
    StateSaver s(*api_);
    begin_upload(s, *api_, GL_TEXTURE_CUBE_MAP, id_);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) {
        api_->TexParameteri(GL_TEXTURE_CUBE_MAP, wrap, GL_CLAMP_TO_EDGE);
    }
    for (int f = 0; f < 6; ++f) {
        api_->TexImage2D(static_cast<GLenum>(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), 0, GL_RGBA8, size,
                         size, 0, GL_RGBA, GL_UNSIGNED_BYTE, faces[std::size_t(f)].data());
    }
    size_ = size;
    return std::nullopt;
}

SkyCubemapTexture::SkyCubemapTexture(SkyCubemapTexture&& other) noexcept
    : api_(other.api_), id_(std::exchange(other.id_, 0u)), size_(other.size_) {}

SkyCubemapTexture& SkyCubemapTexture::operator=(SkyCubemapTexture&& other) noexcept {
    if (this != &other) {
        detail::take_texture(api_, id_, other.api_, other.id_);
        size_ = other.size_;
    }
    return *this;
}

SkyCubemapTexture::~SkyCubemapTexture() { detail::release_texture(api_, id_); }

// ---- SunSpriteTexture ------------------------------------------------------------------------

Result<SunSpriteTexture> SunSpriteTexture::create(const Api& api, const SunSprite& sprite) {
    constexpr const char* kFunction = "gl::SunSpriteTexture::create";
    if (auto e = no_current_context(api)) return aerial::detail::from(kFunction, *e);
    GLuint id = 0;
    api.GenTextures(1, &id);
    SunSpriteTexture texture(api, id);
    if (auto e = texture.update(sprite)) return aerial::detail::from(kFunction, *e);
    return texture;
}

std::optional<Error> SunSpriteTexture::update(const SunSprite& sprite) {
    constexpr const char* kFunction = "gl::SunSpriteTexture::update";
    if (auto e = no_current_context(*api_)) return aerial::detail::from(kFunction, *e);
    GLint max_size = 0;
    api_->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (sprite.size < 1 || sprite.size > max_size ||
        sprite.rgba.size() != std::size_t(sprite.size) * std::size_t(sprite.size) * 4 ||
        !(sprite.half_width_rad > 0 && sprite.half_width_rad < 0.8)) {
        return invalid(kFunction, "sprite",
                       "size in 1 .. " + number(max_size) +
                           ", size * size * 4 bytes and a half-width in (0, 0.8) rad",
                       "size " + number(sprite.size) + " with " + number(sprite.rgba.size()) +
                           " bytes and a half-width of " + number(sprite.half_width_rad));
    }
    StateSaver s(*api_);
    begin_upload(s, *api_, GL_TEXTURE_2D, id_);
    api_->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, edge_clamp(api_->caps));
    api_->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, edge_clamp(api_->caps));
    api_->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, sprite.size, sprite.size, 0, GL_RGBA,
                     GL_UNSIGNED_BYTE, sprite.rgba.data());
    half_width_rad_ = sprite.half_width_rad;
    return std::nullopt;
}

SunSpriteTexture::SunSpriteTexture(SunSpriteTexture&& other) noexcept
    : api_(other.api_), id_(std::exchange(other.id_, 0u)), half_width_rad_(other.half_width_rad_) {}

SunSpriteTexture& SunSpriteTexture::operator=(SunSpriteTexture&& other) noexcept {
    if (this != &other) {
        detail::take_texture(api_, id_, other.api_, other.id_);
        half_width_rad_ = other.half_width_rad_;
    }
    return *this;
}

SunSpriteTexture::~SunSpriteTexture() { detail::release_texture(api_, id_); }

// ---- Drawing ---------------------------------------------------------------------------------

SkyBoxView sky_box_view_from_current_matrices(const Api& api) {
    SkyBoxView view;
    api.GetFloatv(GL_PROJECTION_MATRIX, view.projection.data());
    api.GetFloatv(GL_MODELVIEW_MATRIX, view.view_rotation.data());
    view.view_rotation[12] = view.view_rotation[13] = view.view_rotation[14] = 0.0f;
    return view;
}

std::optional<Error> draw_sky_box(const Api& api, const SkyCubemapTexture& texture,
                                  const SkyBoxView& view) {
    constexpr const char* kFunction = "gl::draw_sky_box";
    if (auto e = no_current_context(api)) return aerial::detail::from(kFunction, *e);
    if (!cube_maps_supported(api)) return no_cube_maps(kFunction, api);
    double near_plane = 0, far_plane = 0;
    if (!near_far(view.projection, near_plane, far_plane)) return not_perspective(kFunction);
    // The cube's corners must stay inside the far plane; its faces in front of the near plane
    // for any view direction within 64 deg of the axis (far >= 4 near).
    const auto h = static_cast<GLfloat>(0.99 * far_plane / std::sqrt(3.0));
    StateSaver s(api);
    common_state(api, s, view, GL_TEXTURE_CUBE_MAP, texture.id());
    // Each face as a quad; texture coordinates are the (unnormalised) world directions.
    static constexpr float kFaces[6][4][3] = {
        {{1, -1, -1}, {1, 1, -1}, {1, 1, 1}, {1, -1, 1}},
        {{-1, -1, 1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, -1}},
        {{-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}},
        {{-1, -1, 1}, {-1, -1, -1}, {1, -1, -1}, {1, -1, 1}},
        {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}},
        {{1, -1, -1}, {-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}},
    };
    api.Begin(GL_QUADS);
    for (const auto& face : kFaces) {
        for (const auto& v : face) {
            api.TexCoord3f(v[0], v[1], v[2]);
            api.Vertex3f(v[0] * h, v[1] * h, v[2] * h);
        }
    }
    api.End();
    return std::nullopt;
}

namespace {

/// `v` normalised when its length is finite and within 1e-3 of 1.
std::optional<glm::dvec3> unit(const glm::dvec3& v) {
    const double length = glm::length(v);
    if (!std::isfinite(length) || std::abs(length - 1.0) > 1e-3) return std::nullopt;
    return v / length;
}

}  // namespace

std::optional<Error> draw_sun_sprite(const Api& api, const SunSpriteTexture& texture,
                                     const SkyBoxView& view, const glm::dvec3& sun_dir) {
    constexpr const char* kFunction = "gl::draw_sun_sprite";
    const auto far = sprite_far_plane(api, view, kFunction);
    if (!far) return far.error();
    const double far_plane = *far;
    const auto unit_sun = unit(sun_dir);
    if (!unit_sun)
        return invalid(kFunction, "sun_dir", "a unit vector", aerial::detail::vector(sun_dir));
    const glm::dvec3 sun = *unit_sun;
    const glm::dvec3 helper = std::abs(sun.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(helper, sun));
    const glm::dvec3 v = glm::cross(sun, u);
    const double h = 0.99 * far_plane / std::sqrt(3.0);
    const double t = std::tan(texture.half_width_rad());
    StateSaver s(api);
    common_state(api, s, view, GL_TEXTURE_2D, texture.id());
    s.enable(GL_BLEND, true);
    s.blend_func(GL_ONE, GL_ONE);
    api.Begin(GL_QUADS);
    static constexpr float kCorners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& c : kCorners) {
        const glm::dvec3 p = h * (sun + (2.0 * c[0] - 1.0) * t * u + (2.0 * c[1] - 1.0) * t * v);
        api.TexCoord2f(c[0], c[1]);
        api.Vertex3f(static_cast<GLfloat>(p.x), static_cast<GLfloat>(p.y),
                     static_cast<GLfloat>(p.z));
    }
    api.End();
    return std::nullopt;
}

namespace {

/// A textured square facing the eye around `centre` (unit), its texture's first row along `top`
/// and first column along -right, half-width `t` as a tangent, at distance h; the caller has set
/// the state.
void facing_quad(const Api& api, const glm::dvec3& centre, const glm::dvec3& right,
                 const glm::dvec3& top, double t, double h) {
    static constexpr float kCorners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& c : kCorners) {
        const glm::dvec3 p =
            h * (centre + (2.0 * c[0] - 1.0) * t * right + (1.0 - 2.0 * c[1]) * t * top);
        api.TexCoord2f(c[0], c[1]);
        api.Vertex3f(static_cast<GLfloat>(p.x), static_cast<GLfloat>(p.y),
                     static_cast<GLfloat>(p.z));
    }
}

/// The common set-up of the additive, colour-modulated sprites.
void additive_modulated(const Api& api, StateSaver& s, const SkyBoxView& view, GLuint texture) {
    common_state(api, s, view, GL_TEXTURE_2D, texture);
    s.tex_env(0, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    s.enable(GL_BLEND, true);
    s.blend_func(GL_ONE, GL_ONE);
    s.save_current_color();
}

}  // namespace

std::optional<Error> draw_moon_sprite(const Api& api, const SunSpriteTexture& texture,
                                      const SkyBoxView& view, const glm::dvec3& moon_dir,
                                      const glm::dvec3& up, const glm::vec3& colour) {
    constexpr const char* kFunction = "gl::draw_moon_sprite";
    const auto far = sprite_far_plane(api, view, kFunction);
    if (!far) return far.error();
    const double far_plane = *far;
    const auto moon = unit(moon_dir);
    if (!moon)
        return invalid(kFunction, "moon_dir", "a unit vector", aerial::detail::vector(moon_dir));
    const auto sky_up = unit(up);
    const glm::dvec3 across = sky_up ? *sky_up - glm::dot(*sky_up, *moon) * *moon : glm::dvec3(0);
    if (!sky_up || glm::length(across) < 1e-6)
        return invalid(kFunction, "up", "a unit vector not along moon_dir",
                       aerial::detail::vector(up));
    const glm::dvec3 top = glm::normalize(across);
    const glm::dvec3 right = glm::cross(*moon, top);
    StateSaver s(api);
    additive_modulated(api, s, view, texture.id());
    api.Color4f(colour.x, colour.y, colour.z, 1.0f);
    api.Begin(GL_QUADS);
    facing_quad(api, *moon, right, top, std::tan(texture.half_width_rad()),
                0.99 * far_plane / std::sqrt(3.0));
    api.End();
    return std::nullopt;
}

std::optional<Error> draw_stars(const Api& api, const SunSpriteTexture& glow,
                                const SkyBoxView& view, const std::vector<StarAppearance>& stars,
                                const glm::dmat3& enu_to_world) {
    constexpr const char* kFunction = "gl::draw_stars";
    const auto far = sprite_far_plane(api, view, kFunction);
    if (!far) return far.error();
    const double far_plane = *far;
    const double h = 0.99 * far_plane / std::sqrt(3.0);
    StateSaver s(api);
    additive_modulated(api, s, view, glow.id());
    api.Begin(GL_QUADS);
    for (const StarAppearance& star : stars) {
        const glm::dvec3 d = enu_to_world * star.direction;
        const double length = glm::length(d);
        if (!(length > 0.0) || !std::isfinite(length)) continue;
        const glm::dvec3 centre = d / length;
        const glm::dvec3 helper =
            std::abs(centre.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
        const glm::dvec3 right = glm::normalize(glm::cross(centre, helper));
        const glm::dvec3 top = glm::cross(right, centre);
        api.Color4f(star.brightness, star.brightness, star.brightness, 1.0f);
        facing_quad(api, centre, right, top, std::tan(double(star.half_width_rad)), h);
    }
    api.End();
    return std::nullopt;
}

}  // namespace aerial::gl
