// aerial/scene_sky.hpp — the CPU sky cubemap and the sun sprite as the scene renderer's sky, and
// the night's stars and moon after it (night_sky_drawer).
//
// How to use this:
//   1. Once, after SceneRenderer::create and with the context current:
//      `auto sky = aerial::scene::install_cubemap_sky(renderer, api);` — an error "cube_map"
//      when the context has no cube maps (GL 1.1): the renderer then keeps its per-vertex dome.
//   2. Render as before. Each frame the sky drawer updates an aerial::SkyCubemapCache
//      (height-chained, 32² by default), which recomputes the sky only when a texel could have
//      moved by half a step and spreads the work over a few frames; the drawer uploads the
//      texels when they changed and draws them with aerial::gl::draw_sky_box. The sun drawer
//      draws aerial::make_sun_sprite (disc and Mie halo) with draw_sun_sprite.
//   3. `sky->recomputes`, `sky->last_refresh_ms` say what it cost (shared with the drawers).
//
// The GL textures belong to the drawers: replace the drawers (set_sky_drawer / set_sun_drawer)
// or destroy the renderer while the context is still current.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>

#include "aerial/error.hpp"
#include "aerial/night.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/sky.hpp"

namespace aerial::scene {

struct CubemapSkyOptions {
    /// Texels a face side (>= 1), the sky model of the cubemap, and the cache's bound.
    SkyCubemapCache::Options cache = {32, SkyMethod::height_chained};
    SunSpriteOptions sprite = {64, 0.087, 0.00465, 0.95, 4};
    bool draw_sun = true;  ///< false: leave the sun drawer as it is
};

/// What the cubemap sky did so far. Updated by the drawers during SceneRenderer::render.
struct CubemapSkyStats {
    int recomputes = 0;      ///< skies completed (SkyCubemapCache::Stats::recomputes)
    int uploads = 0;         ///< texel uploads (new skies, the sun or the exposure moved)
    int sprite_updates = 0;  ///< sun sprites made
    bool recomputed_last_frame = false;  ///< a new sky was shown in the last frame
    int directions_last_frame = 0;       ///< sky directions evaluated in the last frame
    double last_refresh_ms = 0.0;        ///< CPU time of the last frame's cache update and upload
    double total_refresh_ms = 0.0;       ///< the same over every frame
    double bound_steps = 0.0;            ///< how far the last frame's texels could be off (steps)
    double last_switch_steps = 0.0;      ///< largest texel change when the last sky was shown
    /// The last error of a drawer (a drawer cannot fail render()); empty when none.
    std::string error;
};

/// Installs the cubemap sky and (with options.draw_sun) the sun sprite on the renderer.
/// Errors: "cube_map" when the context has no cube maps, "cache.size" below 1,
/// "sprite.size" below 8; the renderer is unchanged then.
Result<std::shared_ptr<const CubemapSkyStats>> install_cubemap_sky(
    SceneRenderer& renderer, const gl::Api& api, const CubemapSkyOptions& options = {});

/// The night's lights the renderer draws after the sky (aerial/night.hpp): the application fills
/// it (visible_stars and star_appearance, moon_position) and changes it between frames.
struct NightSky {
    std::vector<StarAppearance> stars;  ///< directions east-north-up
    glm::dmat3 enu_to_world{1.0};       ///< columns: east, north, up in world coordinates
    bool draw_moon = false;
    glm::dvec3 moon_dir{0.0, 0.0, 1.0};  ///< world, unit
    double moon_phase_angle_rad = 0.0;
    double moon_bright_limb_angle_rad = 0.0;  ///< moon_bright_limb_angle_rad of the world up
    double moon_half_width_rad = 0.0045;      ///< its angular radius
    glm::vec3 moon_colour{1.0f};              ///< display values the sprite is modulated by
};

/// What the night drawer did. `error` keeps its last drawing error (a drawer cannot fail
/// render()); empty when none.
struct NightSkyStats {
    std::size_t stars_drawn = 0;
    int moon_sprites = 0;  ///< moon images made (a new one when the phase or limb moved 0.5 deg)
    std::string error;
};

/// A sun drawer that calls `sun` (the renderer's current one, SceneRenderer::sun_drawer(); null:
/// none), then draws the stars and the moon of `*night` as it is at that frame with
/// aerial::gl::draw_stars and draw_moon_sprite. Its textures are made on its first frame (the
/// context current); `stats` (may be null) is updated each frame.
SkyDrawer night_sky_drawer(SkyDrawer sun, std::shared_ptr<const NightSky> night,
                           std::shared_ptr<NightSkyStats> stats = nullptr);

}  // namespace aerial::scene
