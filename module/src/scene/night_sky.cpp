// The scene renderer's night drawer: the stars and the moon after the sky. See
// aerial/scene_sky.hpp.
#include <cmath>
#include <optional>
#include <utility>

#include "aerial/gl_api.hpp"
#include "aerial/scene_sky.hpp"
#include "aerial/sky_gl.hpp"

namespace aerial::scene {
namespace {

/// The drawer's GL textures and what its moon image was made for.
struct NightTextures {
    std::optional<gl::SunSpriteTexture> glow, moon;
    double moon_phase = -1.0, moon_limb = 0.0, moon_half_width = 0.0;
};

/// The moon image is made again when its phase or limb moved by half a degree.
constexpr double kMoonRemakeRad = 0.5 * 3.14159265358979323846 / 180.0;
constexpr int kMoonSpriteSize = 64;

std::optional<Error> draw_night(const SkyDrawContext& c, const NightSky& night, NightTextures& t,
                                NightSkyStats& stats) {
    const gl::SkyBoxView view = gl::sky_box_view_from_current_matrices(*c.api);
    if (!t.glow) {
        auto glow = make_star_glow();
        if (!glow) return glow.error();
        auto texture = gl::SunSpriteTexture::create(*c.api, *glow);
        if (!texture) return texture.error();
        t.glow.emplace(std::move(texture).value());
    }
    if (!night.stars.empty()) {
        if (auto e = gl::draw_stars(*c.api, *t.glow, view, night.stars, night.enu_to_world))
            return e;
    }
    stats.stars_drawn = night.stars.size();
    if (!night.draw_moon) return std::nullopt;
    if (!t.moon || std::abs(night.moon_phase_angle_rad - t.moon_phase) > kMoonRemakeRad ||
        std::abs(night.moon_bright_limb_angle_rad - t.moon_limb) > kMoonRemakeRad ||
        night.moon_half_width_rad != t.moon_half_width) {
        auto image = make_moon_sprite(night.moon_phase_angle_rad, night.moon_bright_limb_angle_rad,
                                      kMoonSpriteSize);
        if (!image) return image.error();
        const SunSprite sprite{image->size, night.moon_half_width_rad, image->rgba};
        if (t.moon) {
            if (auto e = t.moon->update(sprite)) return e;
        } else {
            auto texture = gl::SunSpriteTexture::create(*c.api, sprite);
            if (!texture) return texture.error();
            t.moon.emplace(std::move(texture).value());
        }
        t.moon_phase = night.moon_phase_angle_rad;
        t.moon_limb = night.moon_bright_limb_angle_rad;
        t.moon_half_width = night.moon_half_width_rad;
        ++stats.moon_sprites;
    }
    return gl::draw_moon_sprite(*c.api, *t.moon, view, night.moon_dir,
                                c.settings ? c.settings->up : glm::dvec3(0, 0, 1),
                                night.moon_colour);
}

}  // namespace

SkyDrawer night_sky_drawer(SkyDrawer sun, std::shared_ptr<const NightSky> night,
                           std::shared_ptr<NightSkyStats> stats) {
    auto textures = std::make_shared<NightTextures>();
    if (!stats) stats = std::make_shared<NightSkyStats>();
    return
        [sun = std::move(sun), night = std::move(night), stats, textures](const SkyDrawContext& c) {
            if (sun) sun(c);
            if (!night || !c.api) return;
            if (auto e = draw_night(c, *night, *textures, *stats))
                stats->error = e->message;
            else
                stats->error.clear();
        };
}

}  // namespace aerial::scene
