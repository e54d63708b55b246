// sample_game/night_sky.hpp — the sample's stars and moon: the aerial::scene::NightSky that the
// renderer's night drawer (aerial::scene::night_sky_drawer) shows after the sun, kept up to date
// frame by frame.
//
// How to use this:
//   1. Once, after the sky is installed: `auto night = install_night_sky(renderer);` (install_sky
//      does it).
//   2. Per frame, before SceneRenderer::render: `update_night_sky(*night, state, schedule, light,
//      settings.display, pixel_rad)` with frame_light's light and settings_for's display.
//   3. After the frame: `night->stats->stars_drawn`, `night->stats->error` (empty: none).
//
// The stars cost: the catalogue is read once (missing: no stars, one warning on stderr), moved
// to the date's places once a night, and aerial::visible_stars (about 0.5 s) runs again only when
// the sun or the moon moved by more than kStarRecomputeRad, the moon's light or the atmosphere
// changed; between, the visible stars turn with the sky (their directions every frame).
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "aerial/night.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/scene_sky.hpp"
#include "world.hpp"

namespace sample {

/// No star is shown while the sun is higher than this (none is visible in daylight), radians.
inline constexpr double kStarsBelowSunRad = -3.0 * 3.14159265358979323846 / 180.0;
/// The visible stars are found again when the sun or the moon moved by more than this, radians.
inline constexpr double kStarRecomputeRad = 0.5 * 3.14159265358979323846 / 180.0;
/// The moon is drawn while its centre is higher than this (the terrain hides it below), radians.
inline constexpr double kMoonDrawnAboveRad = -1.0 * 3.14159265358979323846 / 180.0;
/// The moon's drawn angular radius: three times its mean 0.26 degrees, as the renderer's
/// built-in sun disc is, to be seen at the sample's resolution (a true moon is 3 pixels wide at
/// 480 x 270).
inline constexpr double kMoonShownHalfWidthRad = 3.0 * 0.0045;
/// The moon sprite's colour: its largest channel is held in [kMoonColourMin, 1] (see
/// update_night_sky).
inline constexpr float kMoonColourMin = 0.15f;

/// The stars' catalogue and the last visible set, kept between frames.
struct StarCache {
    bool catalogue_read = false;          ///< read attempted (a failure warned once)
    std::vector<aerial::Star> catalogue;  ///< J2000 (kBrightStarCataloguePath); empty: none
    std::vector<aerial::Star> of_date;    ///< stars_of_date of the catalogue
    double of_date_utc_min = std::numeric_limits<double>::quiet_NaN();  ///< (schedule's minutes)
    /// The last aerial::visible_stars (indices into of_date) and what it was found for.
    std::optional<std::vector<aerial::VisibleStar>> visible;
    glm::dvec3 sun_enu{0.0}, moon_enu{0.0};
    double moon_fraction = 0.0;
    aerial::Atmosphere atmosphere;
    int recomputes = 0;  ///< visible_stars calls so far
};

/// The night the renderer draws and what it costs to keep it.
struct NightSkyState {
    std::shared_ptr<aerial::scene::NightSky> sky = std::make_shared<aerial::scene::NightSky>();
    std::shared_ptr<aerial::scene::NightSkyStats> stats =
        std::make_shared<aerial::scene::NightSkyStats>();
    StarCache stars;
};

/// Installs aerial::scene::night_sky_drawer after the renderer's current sun drawer.
std::shared_ptr<NightSkyState> install_night_sky(aerial::scene::SceneRenderer& renderer);

/// Fills night.sky for a frame (the world is east-north-up: enu_to_world stays the identity):
///   - the moon where it is higher than kMoonDrawnAboveRad: its direction, phase and bright limb
///     (towards the sun, with the world's up), and its colour: the display value of its disc's
///     radiance (its light through the atmosphere over the disc's solid angle, in the light's
///     tint) at the frame's exposure and tone curve, scaled so that its largest channel is in
///     [kMoonColourMin, 1]: white at night, a faint disc by day, reddened near the horizon;
///   - the stars of aerial::visible_stars (sun and moon from `light`, observer at
///     kLightingAltitudeM), each drawn by aerial::star_appearance with `pixel_rad` (the
///     camera's vertical field of view over the image's height); none while the sun is higher
///     than kStarsBelowSunRad. Errors: visible_stars' (a bad atmosphere).
std::optional<aerial::Error> update_night_sky(NightSkyState& night, const FlightState& state,
                                              const SunSchedule& schedule, const FrameLight& light,
                                              const aerial::Display& display, double pixel_rad);

}  // namespace sample
