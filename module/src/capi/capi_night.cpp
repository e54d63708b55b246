// The C interface (aerial/aerial.h), night part: the moon and the visible stars, over
// aerial/night.hpp. Each entry point runs inside capi::guard, so no exception leaves it.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/aerial.h"
#include "aerial/night.hpp"
#include "capi_internal.hpp"

struct aerial_stars {
    std::vector<aerial::Star> catalogue;  ///< J2000
    std::string last_error;
};

namespace aerial::capi {
namespace {

UtcDateTime utc_to_cpp(const aerial_utc_time& t) {
    return {t.year, t.month, t.day, t.hour, t.minute, t.second};
}

glm::dvec3 unit_or_fail(const double v[3], const char* field) {
    const glm::dvec3 d{v[0], v[1], v[2]};
    const double length = glm::length(d);
    if (!std::isfinite(length) || !(length > 0.0))
        fail(AERIAL_ERROR_INVALID_ARGUMENT, field,
             "expected a finite non-zero vector, got " + detail::vector(d));
    return d / length;
}

/// A light in units of E_sun0: finite, >= 0 per channel, or a failure naming `field`.
glm::dvec3 irradiance_or_fail(const double v[3], const char* field) {
    const glm::dvec3 e{v[0], v[1], v[2]};
    for (int c = 0; c < 3; ++c) {
        if (!(e[c] >= 0.0) || !std::isfinite(e[c]))
            fail(AERIAL_ERROR_INVALID_ARGUMENT, field,
                 "expected finite values >= 0, got " + detail::vector(e));
    }
    return e;
}

}  // namespace
}  // namespace aerial::capi

using namespace aerial;
using capi::fail;
using capi::guard;
using capi::require;

aerial_status aerial_moon_position(const aerial_utc_time* time, double latitude_rad,
                                   double longitude_rad, aerial_moon* moon) {
    return guard("aerial_moon_position", nullptr, [&] {
        require(time, "time");
        require(moon, "moon");
        const MoonPosition m =
            capi::value_or_fail(moon_position(capi::utc_to_cpp(*time), latitude_rad, longitude_rad),
                                AERIAL_ERROR_INVALID_ARGUMENT);
        moon->elevation_rad = m.elevation_rad;
        moon->azimuth_rad = m.azimuth_rad;
        const glm::dvec3 d = moon_direction_enu(m);
        for (int i = 0; i < 3; ++i) moon->direction_enu[i] = d[i];
        moon->distance_km = m.distance_km;
        moon->phase_angle_rad = m.phase_angle_rad;
        moon->illuminated_fraction = m.illuminated_fraction;
        moon->light_fraction = moonlight_fraction(m);
    });
}

aerial_status aerial_moon_bright_limb_angle(const double moon_dir[3], const double sun_dir[3],
                                            const double up[3], double* angle_rad) {
    return guard("aerial_moon_bright_limb_angle", nullptr, [&] {
        require(moon_dir, "moon_dir");
        require(sun_dir, "sun_dir");
        require(up, "up");
        require(angle_rad, "angle_rad");
        *angle_rad = moon_bright_limb_angle_rad(capi::unit_or_fail(moon_dir, "moon_dir"),
                                                capi::unit_or_fail(sun_dir, "sun_dir"),
                                                capi::unit_or_fail(up, "up"));
    });
}

aerial_status aerial_night_exposure(const aerial_context* context, const double card_irradiance[3],
                                    const double sky_irradiance[3],
                                    const aerial_exposure_options* options, float* exposure) {
    return guard("aerial_night_exposure", capi::last_error_of(context), [&] {
        require(context, "context");
        require(card_irradiance, "card_irradiance");
        require(exposure, "exposure");
        const ExposureOptions e = capi::exposure_options(options);
        const glm::dvec3 card = capi::irradiance_or_fail(card_irradiance, "card_irradiance");
        *exposure = float(
            sky_irradiance
                ? night_exposure(context->atmosphere, card,
                                 capi::irradiance_or_fail(sky_irradiance, "sky_irradiance"), e)
                : night_exposure(context->atmosphere, card, e));
    });
}

aerial_status aerial_moon_sprite(double phase_angle_rad, double bright_limb_angle_rad, int size,
                                 unsigned char* rgba, size_t capacity) {
    return guard("aerial_moon_sprite", nullptr, [&] {
        require(rgba, "rgba");
        const MoonSprite sprite =
            capi::value_or_fail(make_moon_sprite(phase_angle_rad, bright_limb_angle_rad, size),
                                AERIAL_ERROR_INVALID_ARGUMENT);
        if (capacity < sprite.rgba.size())
            fail(AERIAL_ERROR_BUFFER_TOO_SMALL, "capacity",
                 "expected at least " + std::to_string(sprite.rgba.size()) + " bytes, got " +
                     std::to_string(capacity));
        std::copy(sprite.rgba.begin(), sprite.rgba.end(), rgba);
    });
}

aerial_status aerial_stars_load(const char* path, aerial_stars** out) {
    return guard("aerial_stars_load", nullptr, [&] {
        require(out, "out");
        *out = nullptr;
        auto stars = std::make_unique<aerial_stars>();
        stars->catalogue =
            capi::value_or_fail(read_star_catalogue(path ? path : kBrightStarCataloguePath),
                                AERIAL_ERROR_INVALID_ARGUMENT);
        *out = stars.release();
    });
}

void aerial_stars_destroy(aerial_stars* stars) { delete stars; }

const char* aerial_stars_last_error(const aerial_stars* stars) {
    return stars ? stars->last_error.c_str() : "";
}

size_t aerial_stars_count(const aerial_stars* stars) { return stars ? stars->catalogue.size() : 0; }

aerial_status aerial_visible_stars(aerial_stars* stars, const aerial_context* context,
                                   const aerial_star_query* query, aerial_visible_star* out,
                                   size_t capacity, size_t* count) {
    return guard("aerial_visible_stars", capi::last_error_of(stars), [&] {
        require(stars, "stars");
        require(context, "context");
        require(query, "query");
        require(count, "count");
        *count = 0;
        if (capacity > 0) require(out, "out");
        if (!(query->altitude_m >= 0.0) || !std::isfinite(query->altitude_m))
            fail(AERIAL_ERROR_INVALID_ARGUMENT, "altitude_m",
                 "expected a finite altitude >= 0, got " + detail::number(query->altitude_m));
        const glm::dvec3 sun = capi::unit_or_fail(query->sun_enu, "sun_enu");
        StarVisibilityOptions options;
        if (query->natural_background_cd_m2 != 0.0)
            options.natural_background_cd_m2 = query->natural_background_cd_m2;
        if (query->moon) {
            options.moon_enu = capi::unit_or_fail(query->moon->direction_enu, "moon.direction_enu");
            options.moon_fraction = query->moon->light_fraction;
        }
        const auto dated = stars_of_date(stars->catalogue, capi::utc_to_cpp(query->time));
        const double sidereal =
            local_sidereal_time_rad(capi::utc_to_cpp(query->time), query->longitude_rad);
        const auto seen =
            capi::value_or_fail(visible_stars(dated, context->atmosphere, query->altitude_m, sun,
                                              query->latitude_rad, sidereal, options),
                                AERIAL_ERROR_INVALID_ARGUMENT);
        *count = seen.size();
        for (std::size_t i = 0; i < std::min(seen.size(), capacity); ++i) {
            for (int k = 0; k < 3; ++k) out[i].direction_enu[k] = float(seen[i].direction[k]);
            out[i].apparent_magnitude = float(seen[i].apparent_magnitude);
            out[i].limiting_magnitude = float(seen[i].limiting_magnitude);
        }
        if (seen.size() > capacity)
            fail(AERIAL_ERROR_BUFFER_TOO_SMALL, "capacity",
                 "expected room for " + std::to_string(seen.size()) + " stars, got " +
                     std::to_string(capacity));
    });
}
