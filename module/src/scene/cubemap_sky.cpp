// The CPU sky cubemap and the sun sprite installed as the scene renderer's sky and sun drawers.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "../common/error_text.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/scene_sky.hpp"
#include "aerial/sky_gl.hpp"

namespace aerial::scene {
namespace {

/// Which sky the texture shows.
enum class Shown { none, sun, moon, both };

/// What both drawers share: the caches, the textures and the exposure their texels were made for.
struct CubemapSky {
    CubemapSkyOptions options;
    SkyCubemapCache cache;                            ///< the sun's sky
    SkyCubemapCache moon_cache;                       ///< the moon's (FrameSettings::moon)
    std::array<std::vector<std::uint8_t>, 6> summed;  ///< both skies' texels (Shown::both)
    Shown shown = Shown::none;
    std::optional<gl::SkyCubemapTexture> sky_texture;
    std::optional<gl::SunSpriteTexture> sun_texture;
    bool updated_this_frame = false;  ///< by the sky drawer, for the sun drawer
    int sun_made_from = -1;
    float sun_exposure = -1.0f;
    ToneCurve sun_tone = ToneCurve::clamp;
    std::shared_ptr<CubemapSkyStats> stats = std::make_shared<CubemapSkyStats>();

    explicit CubemapSky(const CubemapSkyOptions& o)
        : options(o), cache(o.cache), moon_cache(o.cache) {}

    static View view_of(const SkyDrawContext& c, const FrameSettings& light) {
        View view;
        view.eye = c.camera->eye;
        view.sun_dir = light.sun_dir;
        view.up = light.up;
        view.meters_per_unit = light.meters_per_unit;
        return view;
    }

    /// Brings the texels of one light's cache up to date (the sun's: c.settings); nullopt (and
    /// stats->error set) on failure, else whether they changed.
    std::optional<bool> update_cache(const SkyDrawContext& c, SkyCubemapCache& which,
                                     const FrameSettings& light) {
        auto changed = which.update(light.atmosphere, view_of(c, light), light.display);
        if (!changed) {
            stats->error = "sky cubemap: " + changed.error().message;
            return std::nullopt;
        }
        return *changed;
    }
    std::optional<bool> update_cache(const SkyDrawContext& c) {
        return update_cache(c, cache, *c.settings);
    }
};

/// The lights of a frame (SkyDrawContext::lights; the settings' sun when none is given).
std::vector<const FrameSettings*> lights_of(const SkyDrawContext& c) {
    return c.lights.empty() ? std::vector<const FrameSettings*>{c.settings} : c.lights;
}

/// Both skies' texels: the sum of the caches' radiance after the display.
void sum_skies(CubemapSky& sky, const Display& display) {
    SkyCubemap sum = sky.cache.cubemap();
    const SkyCubemap& moon = sky.moon_cache.cubemap();
    for (std::size_t f = 0; f < sum.faces.size(); ++f) {
        for (std::size_t t = 0; t < sum.faces[f].size() && t < moon.faces[f].size(); ++t) {
            sum.faces[f][t] += moon.faces[f][t];
        }
    }
    sky.summed = cubemap_to_rgba8(sum, display.exposure, display.tone);
}

/// Updates the caches of the frame's lights; nullopt on failure, else whether the texels to show
/// changed (sky.shown says which they are).
std::optional<bool> update_skies(CubemapSky& sky, const SkyDrawContext& c) {
    bool changed = false, sun = false, moon = false;
    for (const FrameSettings* light : lights_of(c)) {
        const bool is_sun = light == c.settings;
        const auto updated = sky.update_cache(c, is_sun ? sky.cache : sky.moon_cache, *light);
        if (!updated) return std::nullopt;
        changed = changed || *updated;
        (is_sun ? sun : moon) = true;
    }
    const Shown shown = sun && moon ? Shown::both : (moon ? Shown::moon : Shown::sun);
    changed = changed || shown != sky.shown;
    sky.shown = shown;
    if (changed && shown == Shown::both) sum_skies(sky, c.settings->display);
    sky.updated_this_frame = sun;
    return changed;
}

/// Fades the sprite to black towards its edge (from kFadeStart of its half-width to the inscribed
/// circle): at a low sun the exposure is high and the halo still shows at the sprite's edge,
/// which would draw the square.
constexpr double kFadeStart = 0.5;

void fade_edges(SunSprite& sprite) {
    const double half = 0.5 * sprite.size;
    for (int y = 0; y < sprite.size; ++y) {
        for (int x = 0; x < sprite.size; ++x) {
            const double r = std::hypot(x + 0.5 - half, y + 0.5 - half) / half;
            const double t = std::clamp((r - kFadeStart) / (1.0 - kFadeStart), 0.0, 1.0);
            const double w = 1.0 - t * t * (3.0 - 2.0 * t);
            std::uint8_t* texel = &sprite.rgba[(std::size_t(y) * sprite.size + x) * 4];
            for (int c = 0; c < 3; ++c) texel[c] = std::uint8_t(std::lround(texel[c] * w));
        }
    }
}

void draw_sky(CubemapSky& sky, const SkyDrawContext& c) {
    const auto start = std::chrono::steady_clock::now();
    CubemapSkyStats& stats = *sky.stats;
    const int before = sky.cache.recomputes() + sky.moon_cache.recomputes();
    const auto changed = update_skies(sky, c);
    if (!changed) return;
    const SkyCubemapCache& shown = sky.shown == Shown::moon ? sky.moon_cache : sky.cache;
    const SkyCubemapCache::Stats& cache = shown.stats();
    stats.recomputes = sky.cache.recomputes() + sky.moon_cache.recomputes();
    stats.recomputed_last_frame = stats.recomputes != before;
    stats.directions_last_frame = cache.directions_last_update;
    stats.bound_steps = cache.bound_steps;
    stats.last_switch_steps = cache.last_switch_steps;
    if (sky.shown == Shown::both) {
        stats.directions_last_frame += sky.moon_cache.stats().directions_last_update;
        stats.bound_steps += sky.moon_cache.stats().bound_steps;
    }
    if (!sky.sky_texture || *changed) {
        const auto& faces = sky.shown == Shown::both ? sky.summed : shown.rgba8();
        const int size = shown.cubemap().size;
        if (sky.sky_texture) {
            if (auto e = sky.sky_texture->update(faces, size)) {
                stats.error = "sky cubemap: " + e->message;
                return;
            }
        } else {
            auto texture = gl::SkyCubemapTexture::create(*c.api, faces, size);
            if (!texture) {
                stats.error = "sky cubemap: " + texture.error().message;
                return;
            }
            sky.sky_texture.emplace(std::move(texture.value()));
        }
        ++stats.uploads;
    }
    stats.last_refresh_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats.total_refresh_ms += stats.last_refresh_ms;
    if (auto e = gl::draw_sky_box(*c.api, *sky.sky_texture,
                                  gl::sky_box_view_from_current_matrices(*c.api))) {
        stats.error = "sky box: " + e->message;
    }
}

/// At most how many 8-bit steps a texel made at exposure `made` moves at display.exposure: the
/// code 255 t(e x) changes by 255 x e t'(e x) per unit of ln e, at most 255 / e for the
/// exponential curve (x e^-x peaks at 1 / e) and 255 for the clamp.
double exposure_steps(float made, const Display& display) {
    if (!(made > 0.0f)) return 1e300;
    const double slope = display.tone == ToneCurve::exponential ? 255.0 / std::exp(1.0) : 255.0;
    return slope * std::abs(std::log(double(display.exposure) / double(made)));
}

void draw_sun(CubemapSky& sky, const SkyDrawContext& c) {
    CubemapSkyStats& stats = *sky.stats;
    // Not a light of this frame (night): no sun to draw.
    const auto lights = lights_of(c);
    if (std::find(lights.begin(), lights.end(), c.settings) == lights.end()) return;
    // The sky drawer, called first each frame, brings the cache up to date; without a sky
    // node in the scene the sun does.
    if (!sky.updated_this_frame && !sky.update_cache(c)) return;
    sky.updated_this_frame = false;
    const Display& display = c.settings->display;
    if (!sky.sun_texture || sky.sun_made_from != sky.cache.recomputes() ||
        exposure_steps(sky.sun_exposure, display) >= sky.options.cache.max_change_steps ||
        sky.sun_tone != display.tone) {
        // The sprite needs the sky at the eye (E_sun there, the Mie optical depth to the sun).
        auto context = prepare_sky(c.settings->atmosphere, CubemapSky::view_of(c, *c.settings),
                                   SkyMethod::dome_height);
        if (!context) {
            stats.error = "sun sprite: " + context.error().message;
            return;
        }
        auto sprite = make_sun_sprite(*context, display.exposure, display.tone, sky.options.sprite);
        if (!sprite) {
            stats.error = "sun sprite: " + sprite.error().message;
            return;
        }
        fade_edges(sprite.value());
        if (sky.sun_texture) {
            if (auto e = sky.sun_texture->update(sprite.value())) {
                stats.error = "sun sprite: " + e->message;
                return;
            }
        } else {
            auto texture = gl::SunSpriteTexture::create(*c.api, sprite.value());
            if (!texture) {
                stats.error = "sun sprite: " + texture.error().message;
                return;
            }
            sky.sun_texture.emplace(std::move(texture.value()));
        }
        sky.sun_made_from = sky.cache.recomputes();
        sky.sun_exposure = display.exposure;
        sky.sun_tone = display.tone;
        ++stats.sprite_updates;
    }
    if (auto e = gl::draw_sun_sprite(*c.api, *sky.sun_texture,
                                     gl::sky_box_view_from_current_matrices(*c.api),
                                     c.settings->sun_dir)) {
        stats.error = "sun sprite: " + e->message;
    }
}

}  // namespace

Result<std::shared_ptr<const CubemapSkyStats>> install_cubemap_sky(
    SceneRenderer& renderer, const gl::Api& api, const CubemapSkyOptions& options) {
    constexpr const char* kFunction = "scene::install_cubemap_sky";
    if (!gl::cube_maps_supported(api)) {
        return aerial::detail::unsupported(
            kFunction, "cube_map",
            "the context has no cube map textures (GL 1.3, ARB_texture_cube_map or "
            "EXT_texture_cube_map); keep the per-vertex dome");
    }
    if (options.cache.size < 1) {
        return aerial::detail::invalid(kFunction, "cache.size", ">= 1 texels",
                                       aerial::detail::number(options.cache.size));
    }
    if (options.sprite.size < 8) {
        return aerial::detail::invalid(kFunction, "sprite.size", ">= 8 texels",
                                       aerial::detail::number(options.sprite.size));
    }
    auto sky = std::make_shared<CubemapSky>(options);
    renderer.set_sky_drawer([sky](const SkyDrawContext& c) { draw_sky(*sky, c); });
    if (options.draw_sun) {
        renderer.set_sun_drawer([sky](const SkyDrawContext& c) { draw_sun(*sky, c); });
    }
    return std::shared_ptr<const CubemapSkyStats>(sky->stats);
}

}  // namespace aerial::scene
