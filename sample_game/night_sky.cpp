#include "night_sky.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

namespace sample {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// The stars' places of date are made again after this long (the catalogue precesses 0.00004 deg
/// a day), minutes.
constexpr double kStarsOfDateMinutes = 720.0;

bool moved(const glm::dvec3& a, const glm::dvec3& b) {
    return glm::dot(a, b) < std::cos(kStarRecomputeRad);
}

/// The catalogue, read at the first night; a missing or bad file leaves it empty (one line on
/// stderr).
void read_catalogue(StarCache& cache) {
    if (cache.catalogue_read) return;
    cache.catalogue_read = true;
    auto stars = aerial::read_star_catalogue(aerial::kBrightStarCataloguePath);
    if (stars) {
        cache.catalogue = std::move(stars).value();
    } else {
        std::fprintf(stderr, "aerial-sample: no stars: %s\n", stars.error().message.c_str());
    }
}

/// The visible stars for the frame's sun, moon and atmosphere: the cached set while they stay
/// close to what it was found for.
std::optional<aerial::Error> refresh_visible(StarCache& cache, const SunSchedule& schedule,
                                             const FrameLight& light, double sidereal_rad) {
    const glm::dvec3 moon_enu = light.moon ? light.moon->dir : glm::dvec3(0.0, 0.0, 1.0);
    const double moon_fraction = light.moon ? light.moon->fraction : 0.0;
    if (cache.visible && !moved(light.sun_dir, cache.sun_enu) && !moved(moon_enu, cache.moon_enu) &&
        moon_fraction == cache.moon_fraction && light.atmosphere == cache.atmosphere) {
        return std::nullopt;
    }
    aerial::StarVisibilityOptions options;
    options.moon_enu = moon_enu;
    options.moon_fraction = moon_fraction;
    auto visible =
        aerial::visible_stars(cache.of_date, light.atmosphere, kLightingAltitudeM, light.sun_dir,
                              schedule.latitude_rad, sidereal_rad, options);
    if (!visible) return visible.error();
    cache.visible = std::move(visible).value();
    cache.sun_enu = light.sun_dir;
    cache.moon_enu = moon_enu;
    cache.moon_fraction = moon_fraction;
    cache.atmosphere = light.atmosphere;
    ++cache.recomputes;
    return std::nullopt;
}

std::optional<aerial::Error> update_stars(StarCache& cache,
                                          std::vector<aerial::StarAppearance>& out,
                                          const FlightState& state, const SunSchedule& schedule,
                                          const FrameLight& light, double pixel_rad) {
    out.clear();
    if (state.sun_elevation_rad > kStarsBelowSunRad) return std::nullopt;
    read_catalogue(cache);
    if (cache.catalogue.empty()) return std::nullopt;
    const aerial::UtcDateTime time = utc_at(schedule, state.utc_min);
    if (!(std::abs(state.utc_min - cache.of_date_utc_min) <= kStarsOfDateMinutes)) {
        cache.of_date = aerial::stars_of_date(cache.catalogue, time);
        cache.of_date_utc_min = state.utc_min;
    }
    const double sidereal = aerial::local_sidereal_time_rad(time, schedule.longitude_rad);
    if (auto e = refresh_visible(cache, schedule, light, sidereal)) return e;
    // The set found a little earlier, each star where it stands now.
    for (aerial::VisibleStar star : *cache.visible) {
        star.direction =
            aerial::star_direction_enu(cache.of_date[star.index], schedule.latitude_rad, sidereal);
        if (star.direction.z > 0.0) out.push_back(aerial::star_appearance(star, pixel_rad));
    }
    return std::nullopt;
}

/// The moon sprite's colour (see update_night_sky).
glm::vec3 moon_colour(const FrameLight& light, const aerial::Display& display,
                      double half_width_rad) {
    const double disc_sr = kPi * half_width_rad * half_width_rad;
    const glm::dvec3 shown =
        aerial::tone_map(light.moon_direct * light.tint / disc_sr, display.exposure, display.tone);
    const double brightest = std::max({shown.x, shown.y, shown.z});
    const double held = std::clamp(brightest, double(kMoonColourMin), 1.0);
    if (brightest > 0.0) return glm::vec3(shown * (held / brightest));
    // In the planet's shadow (just below the horizon): the faintest disc, in the light's tint.
    return glm::vec3(light.tint * (held / std::max({light.tint.x, light.tint.y, light.tint.z})));
}

void update_moon(aerial::scene::NightSky& sky, const FlightState& state, const FrameLight& light,
                 const aerial::Display& display) {
    sky.draw_moon = state.moon && light.moon && state.moon->elevation_rad > kMoonDrawnAboveRad;
    if (!sky.draw_moon) return;
    sky.moon_dir = light.moon->dir;
    sky.moon_phase_angle_rad = state.moon->phase_angle_rad;
    sky.moon_bright_limb_angle_rad =
        aerial::moon_bright_limb_angle_rad(sky.moon_dir, light.sun_dir, {0.0, 0.0, 1.0});
    sky.moon_colour = moon_colour(light, display, sky.moon_half_width_rad);
}

}  // namespace

std::shared_ptr<NightSkyState> install_night_sky(aerial::scene::SceneRenderer& renderer) {
    auto night = std::make_shared<NightSkyState>();
    night->sky->moon_half_width_rad = kMoonShownHalfWidthRad;
    renderer.set_sun_drawer(
        aerial::scene::night_sky_drawer(renderer.sun_drawer(), night->sky, night->stats));
    return night;
}

std::optional<aerial::Error> update_night_sky(NightSkyState& night, const FlightState& state,
                                              const SunSchedule& schedule, const FrameLight& light,
                                              const aerial::Display& display, double pixel_rad) {
    update_moon(*night.sky, state, light, display);
    return update_stars(night.stars, night.sky->stars, state, schedule, light, pixel_rad);
}

}  // namespace sample
