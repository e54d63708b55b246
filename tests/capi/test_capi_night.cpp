// The night through the C interface (aerial/aerial.h): the moon for an engine's own sprite and
// light, the visible stars for its own points; the answers equal the C++ API's.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/aerial.h"
#include "aerial/atmosphere.hpp"
#include "aerial/night.hpp"

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

TEST(CApiNight, MoonEqualsTheCppApi) {
    const aerial_utc_time t = {2026, 12, 6, 20, 0, 0.0};
    aerial_moon moon;
    ASSERT_EQ(aerial_moon_position(&t, 48.0 * kDegree, 11.0 * kDegree, &moon), AERIAL_OK);
    const auto cpp =
        aerial::moon_position({2026, 12, 6, 20, 0, 0.0}, 48.0 * kDegree, 11.0 * kDegree);
    ASSERT_TRUE(cpp.ok());
    EXPECT_EQ(moon.elevation_rad, cpp->elevation_rad);
    EXPECT_EQ(moon.azimuth_rad, cpp->azimuth_rad);
    EXPECT_EQ(moon.illuminated_fraction, cpp->illuminated_fraction);
    EXPECT_EQ(moon.light_fraction, aerial::moonlight_fraction(*cpp));
    EXPECT_NEAR(moon.direction_enu[2], std::sin(moon.elevation_rad), 1e-12);
    const aerial_utc_time bad = {2026, 13, 6, 20, 0, 0.0};
    EXPECT_EQ(aerial_moon_position(&bad, 0.0, 0.0, &moon), AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "month");
    EXPECT_EQ(aerial_moon_position(&t, 0.0, 0.0, nullptr), AERIAL_ERROR_NULL_ARGUMENT);
}

TEST(CApiNight, MoonSpriteEqualsTheCppApi) {
    std::vector<unsigned char> rgba(32 * 32 * 4);
    ASSERT_EQ(aerial_moon_sprite(1.0, 0.3, 32, rgba.data(), rgba.size()), AERIAL_OK);
    EXPECT_EQ(rgba, aerial::make_moon_sprite(1.0, 0.3, 32).value().rgba);
    EXPECT_EQ(aerial_moon_sprite(1.0, 0.3, 32, rgba.data(), 100), AERIAL_ERROR_BUFFER_TOO_SMALL);
    const double moon[3] = {1, 0, 1}, sun[3] = {1, 1, 1}, up[3] = {0, 0, 1};
    double angle = 0.0;
    ASSERT_EQ(aerial_moon_bright_limb_angle(moon, sun, up, &angle), AERIAL_OK);
    EXPECT_GT(angle, 0.0) << "north of an eastern moon: its left";
}

TEST(CApiNight, NightExposureEqualsTheCppApi) {
    aerial_context* context = nullptr;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &context), AERIAL_OK);
    const aerial::Atmosphere earth = aerial::atmosphere_preset("earth").value();
    // A twilight card: lit by the sky alone.
    const double card[3] = {2e-5, 3e-5, 5e-5};
    float exposure = 0.0f;
    ASSERT_EQ(aerial_night_exposure(context, card, card, nullptr, &exposure), AERIAL_OK)
        << aerial_last_error_message();
    const glm::dvec3 e{card[0], card[1], card[2]};
    EXPECT_EQ(exposure, float(aerial::night_exposure(earth, e, e)));
    ASSERT_EQ(aerial_night_exposure(context, card, nullptr, nullptr, &exposure), AERIAL_OK);
    EXPECT_EQ(exposure, float(aerial::night_exposure(earth, e)));
    aerial_exposure_options options = {};
    options.key = 0.8;
    ASSERT_EQ(aerial_night_exposure(context, card, nullptr, &options, &exposure), AERIAL_OK);
    aerial::ExposureOptions cpp;
    cpp.key = 0.8;
    EXPECT_EQ(exposure, float(aerial::night_exposure(earth, e, cpp)));
    const double bad[3] = {1e-5, -1.0, 0.0};
    EXPECT_EQ(aerial_night_exposure(context, bad, nullptr, nullptr, &exposure),
              AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "card_irradiance");
    EXPECT_EQ(aerial_night_exposure(context, card, bad, nullptr, &exposure),
              AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "sky_irradiance");
    EXPECT_EQ(aerial_night_exposure(context, nullptr, nullptr, nullptr, &exposure),
              AERIAL_ERROR_NULL_ARGUMENT);
    aerial_context_destroy(context);
}

TEST(CApiNight, VisibleStarsForTheEnginesPoints) {
    aerial_stars* stars = nullptr;
    ASSERT_EQ(aerial_stars_load(nullptr, &stars), AERIAL_OK) << aerial_last_error_message();
    EXPECT_GT(aerial_stars_count(stars), 9000u);
    aerial_context* context = nullptr;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &context), AERIAL_OK);
    aerial_star_query query = {};
    query.time = {2026, 12, 6, 23, 0, 0.0};
    query.latitude_rad = 45.0 * kDegree;
    query.altitude_m = 100.0;
    query.sun_enu[1] = std::cos(18.0 * kDegree);
    query.sun_enu[2] = -std::sin(18.0 * kDegree);
    size_t count = 0;
    // Asking for the count first: BUFFER_TOO_SMALL with the number needed.
    EXPECT_EQ(aerial_visible_stars(stars, context, &query, nullptr, 0, &count),
              AERIAL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_GT(count, 2000u);
    EXPECT_LT(count, 3500u);
    std::vector<aerial_visible_star> seen(count);
    ASSERT_EQ(aerial_visible_stars(stars, context, &query, seen.data(), seen.size(), &count),
              AERIAL_OK)
        << aerial_last_error_message();
    for (const auto& s : seen) {
        EXPECT_GT(s.direction_enu[2], 0.0f);
        EXPECT_LT(s.apparent_magnitude, s.limiting_magnitude);
    }
    // Daylight: none.
    query.sun_enu[2] = std::sin(30.0 * kDegree);
    ASSERT_EQ(aerial_visible_stars(stars, context, &query, seen.data(), seen.size(), &count),
              AERIAL_OK);
    EXPECT_EQ(count, 0u);
    query.sun_enu[0] = query.sun_enu[1] = query.sun_enu[2] = 0.0;
    EXPECT_EQ(aerial_visible_stars(stars, context, &query, seen.data(), seen.size(), &count),
              AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "sun_enu");
    aerial_stars* missing = nullptr;
    EXPECT_EQ(aerial_stars_load("/nonexistent/stars", &missing), AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(missing, nullptr);
    aerial_context_destroy(context);
    aerial_stars_destroy(stars);
}

}  // namespace
