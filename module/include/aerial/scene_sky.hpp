// aerial/scene_sky.hpp — the CPU sky cubemap and the sun sprite as the scene renderer's sky.
//
// How to use this:
//   1. Once, after SceneRenderer::create and with the context current:
//      `auto sky = aerial::scene::install_cubemap_sky(renderer, api);` — an error "cube_map"
//      when the context has no cube maps (GL 1.1): the renderer then keeps its per-vertex dome.
//   2. Render as before. Each frame the sky drawer asks an aerial::SkyCubemapCache whether the
//      sun, the eye's altitude or the atmosphere moved beyond its bound and recomputes the
//      faces only then (height-chained, 32² by default); it re-encodes the texels when the
//      exposure or tone curve changed, and draws them with aerial::gl::draw_sky_box. The sun
//      drawer draws aerial::make_sun_sprite (disc and Mie halo) with draw_sun_sprite.
//   3. `sky->recomputes`, `sky->last_recompute_ms` say what it cost (shared with the drawers).
//
// The GL textures belong to the drawers: replace the drawers (set_sky_drawer / set_sun_drawer)
// or destroy the renderer while the context is still current.
#pragma once

#include <memory>

#include "aerial/error.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/sky.hpp"

namespace aerial::scene {

struct CubemapSkyOptions {
    /// Texels a face side (>= 1) and the sky model of the cubemap, and the cache's bounds.
    SkyCubemapCache::Options cache = {32, SkyMethod::height_chained,
                                      0.05 * 3.14159265358979323846 / 180.0, 10.0};
    SunSpriteOptions sprite = {64, 0.087, 0.00465, 0.95, 4};
    bool draw_sun = true;  ///< false: leave the sun drawer as it is
};

/// What the cubemap sky did so far. Updated by the drawers during SceneRenderer::render.
struct CubemapSkyStats {
    int recomputes = 0;              ///< cubemaps computed (SkyCubemapCache recomputes)
    int uploads = 0;                 ///< texel uploads (recomputes and exposure changes)
    int sprite_updates = 0;          ///< sun sprites made
    double last_recompute_ms = 0.0;  ///< CPU time of the last recompute and its upload
    double total_recompute_ms = 0.0;
    bool recomputed_last_frame = false;
    /// The last error of a drawer (a drawer cannot fail render()); empty when none.
    std::string error;
};

/// Installs the cubemap sky and (with options.draw_sun) the sun sprite on the renderer.
/// Errors: "cube_map" when the context has no cube maps, "cache.size" below 1,
/// "sprite.size" below 8; the renderer is unchanged then.
Result<std::shared_ptr<const CubemapSkyStats>> install_cubemap_sky(
    SceneRenderer& renderer, const gl::Api& api, const CubemapSkyOptions& options = {});

}  // namespace aerial::scene
