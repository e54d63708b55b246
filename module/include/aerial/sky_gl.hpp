// aerial/sky_gl.hpp — the sky cubemap, the sun sprite, the moon and the stars on the fixed
// pipeline.
//
// How to use this:
//   1. Once, with the engine's context current: `if (aerial::gl::cube_maps_supported(api))`
//      create `auto sky = aerial::gl::SkyCubemapTexture::create(api, faces, size);` from
//      aerial::cubemap_to_rgba8 (aerial/sky.hpp); `sky->update(faces, size)` when the
//      SkyCubemapCache recomputed. Likewise `SunSpriteTexture::create(api, sprite)`.
//   2. Each frame, first thing after clearing: `aerial::gl::draw_sky_box(api, *sky, view)` with
//      the engine's projection and the rotation part of its view matrix, then
//      `aerial::gl::draw_sun_sprite(api, *sun, view, sun_dir)`; then draw the scene.
//   3. Both draw with depth test and depth writes off (the sky is behind everything), and put
//      back every piece of GL state they change (aerial/gl_state.hpp lists what is checked).
//
// The cube is drawn around the eye with its vertices as texture coordinates, so each pixel
// looks up the world direction through it (fixed-function cube mapping, GL 1.3 or
// ARB_texture_cube_map); matrices are column-major float[16], as glLoadMatrixf takes them.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "aerial/error.hpp"
#include "aerial/night.hpp"
#include "aerial/sky.hpp"

namespace aerial::gl {

struct Api;  // aerial/gl_api.hpp

/// Whether the context offers cube map textures (GL 1.3, ARB_ or EXT_texture_cube_map).
bool cube_maps_supported(const Api& api);

/// An RGBA8 cube map texture, linear filtering, clamped to each face's edge. Move-only; the
/// destructor deletes the texture (the context must be current then).
class SkyCubemapTexture {
  public:
    /// Errors: "cube_map" when the context has no cube maps; "faces" when a face does not hold
    /// size * size * 4 bytes; "size" outside 1 .. GL_MAX_CUBE_MAP_TEXTURE_SIZE. The engine's
    /// unpack state and texture bindings are restored.
    static Result<SkyCubemapTexture> create(const Api& api,
                                            const std::array<std::vector<std::uint8_t>, 6>& faces,
                                            int size);
    /// Replaces the texels (any size the create() rules accept).
    std::optional<Error> update(const std::array<std::vector<std::uint8_t>, 6>& faces, int size);

    SkyCubemapTexture(SkyCubemapTexture&& other) noexcept;
    SkyCubemapTexture& operator=(SkyCubemapTexture&& other) noexcept;
    SkyCubemapTexture(const SkyCubemapTexture&) = delete;
    SkyCubemapTexture& operator=(const SkyCubemapTexture&) = delete;
    ~SkyCubemapTexture();

    unsigned id() const { return id_; }
    int size() const { return size_; }

  private:
    SkyCubemapTexture(const Api& api, unsigned id) : api_(&api), id_(id) {}
    const Api* api_ = nullptr;
    unsigned id_ = 0;
    int size_ = 0;
};

/// The sun sprite (aerial::make_sun_sprite) as an RGBA8 2D texture. Move-only.
class SunSpriteTexture {
  public:
    /// Errors: "sprite" when its pixels do not match its size or its half-width is not in
    /// (0, 0.8) rad.
    static Result<SunSpriteTexture> create(const Api& api, const SunSprite& sprite);
    std::optional<Error> update(const SunSprite& sprite);

    SunSpriteTexture(SunSpriteTexture&& other) noexcept;
    SunSpriteTexture& operator=(SunSpriteTexture&& other) noexcept;
    SunSpriteTexture(const SunSpriteTexture&) = delete;
    SunSpriteTexture& operator=(const SunSpriteTexture&) = delete;
    ~SunSpriteTexture();

    unsigned id() const { return id_; }
    double half_width_rad() const { return half_width_rad_; }

  private:
    SunSpriteTexture(const Api& api, unsigned id) : api_(&api), id_(id) {}
    const Api* api_ = nullptr;
    unsigned id_ = 0;
    double half_width_rad_ = 0;
};

/// The camera the sky is drawn with.
struct SkyBoxView {
    /// The engine's perspective projection, column-major.
    /// Default: 90 deg field of view, square, near 0.1, far 100.
    std::array<float, 16> projection{1, 0, 0,          0,  0, 1, 0,           0,
                                     0, 0, -1.002002f, -1, 0, 0, -0.2002002f, 0};
    /// World to eye rotation (the view matrix without its translation), column-major.
    std::array<float, 16> view_rotation{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

/// The view of the matrices currently loaded in GL (GL_PROJECTION, and GL_MODELVIEW with its
/// translation removed): for engines that set their camera before drawing the sky.
SkyBoxView sky_box_view_from_current_matrices(const Api& api);

/// Draws the cube map around the eye on texture unit 0 (the other units' targets disabled) with
/// GL_REPLACE, depth test and depth writes, lighting, fog, blending, alpha test, face culling,
/// texture-coordinate generation and programs off. Errors: "cube_map" without cube maps;
/// "projection" when it is not a perspective projection or its far plane is not at least four
/// times its near plane (the cube is drawn between them).
std::optional<Error> draw_sky_box(const Api& api, const SkyCubemapTexture& texture,
                                  const SkyBoxView& view);

/// Draws the sun sprite additively (GL_ONE, GL_ONE) as a square facing the eye, centred on the
/// unit world direction towards the sun, spanning the sprite's angular half-width. Same state
/// rules and errors as draw_sky_box; "sun_dir" when it is not a unit vector.
std::optional<Error> draw_sun_sprite(const Api& api, const SunSpriteTexture& texture,
                                     const SkyBoxView& view, const glm::dvec3& sun_dir);

/// Draws the moon's disc (aerial::make_moon_sprite, aerial/night.hpp, uploaded as a
/// SunSpriteTexture whose half-width is the moon's angular radius, about 0.0045 rad) additively,
/// facing the eye, centred on the unit world direction `moon_dir`, the image's top row along
/// `up` (world, unit) as it crosses the line of sight, its left column on the observer's left,
/// modulated by `colour` (display values, 0 .. 1). Same state rules and errors as
/// draw_sun_sprite ("moon_dir", "up" when not unit, or parallel to each other).
std::optional<Error> draw_moon_sprite(const Api& api, const SunSpriteTexture& texture,
                                      const SkyBoxView& view, const glm::dvec3& moon_dir,
                                      const glm::dvec3& up, const glm::vec3& colour);

/// Draws stars (aerial::star_appearance) additively as small quads of the `glow` texture
/// (aerial::make_star_glow) facing the eye: each centred on its direction mapped to the world by
/// `enu_to_world` (columns: east, north, up in world coordinates), as wide as its half-width,
/// as bright as its brightness (a grey). Same state rules and errors as draw_sun_sprite.
std::optional<Error> draw_stars(const Api& api, const SunSpriteTexture& glow,
                                const SkyBoxView& view, const std::vector<StarAppearance>& stars,
                                const glm::dmat3& enu_to_world = glm::dmat3(1.0));

}  // namespace aerial::gl
