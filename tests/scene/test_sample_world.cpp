// The sample game's day and night without GL: the schedule into the night, the script's clock,
// the moon as second light, the exposure and tint, and the night sky the renderer is handed
// (sample_game/world.hpp, sample_game/night_sky.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "night_sky.hpp"
#include "world.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kMinuteTolerance = 0.01;  ///< of a schedule's times, minutes
constexpr int kFrames = 24;                ///< the README's flythrough

double sun_elevation_deg(const sample::SunSchedule& schedule, double utc_min) {
    return aerial::sun_position(sample::utc_at(schedule, utc_min), schedule.latitude_rad,
                                schedule.longitude_rad)
               .value()
               .elevation_rad /
           kDeg;
}

sample::SunSchedule schedule_at(double latitude_deg) {
    return sample::make_sun_schedule(2026, 6, 21, latitude_deg * kDeg, 8.0 * kDeg).value();
}

/// The card's displayed value: exposure times the radiance of an 18 % card.
double shown_card(const sample::FrameLight& light) {
    return light.exposure * 0.18 / kPi * aerial::luminance(light.card);
}

const sample::World& world() {
    static const sample::World w = sample::build_world({});
    return w;
}

TEST(SampleSchedule, DefaultEndsWithTheSunFifteenDegreesDown) {
    const sample::SunSchedule s = sample::default_sun_schedule();
    EXPECT_NEAR(sun_elevation_deg(s, s.end_utc_min), -15.0, 0.01);
    EXPECT_NEAR(sun_elevation_deg(s, s.night_utc_min), -12.0, 0.01);
    EXPECT_LT(s.noon_utc_min, s.sunset_utc_min);
    EXPECT_LT(s.sunset_utc_min, s.night_utc_min);
    EXPECT_LT(s.night_utc_min, s.end_utc_min);
    EXPECT_LT(s.end_utc_min, s.noon_utc_min + 720.0) << "the default night reaches -20 deg";
}

TEST(SampleSchedule, WhiteNightsEndAtSolarMidnight) {
    const sample::SunSchedule s = schedule_at(60.0);  // lowest about -6.6 deg
    EXPECT_NEAR(s.end_utc_min, s.noon_utc_min + 720.0, kMinuteTolerance);
    EXPECT_NEAR(s.night_utc_min, s.end_utc_min, kMinuteTolerance)
        << "no night: twilight to the end";
    const double lowest = sun_elevation_deg(s, s.end_utc_min);
    EXPECT_GT(lowest, -15.0);
    EXPECT_LE(lowest, sun_elevation_deg(s, s.end_utc_min - 10.0));
    EXPECT_LE(lowest, sun_elevation_deg(s, s.end_utc_min + 10.0));
}

TEST(SampleSchedule, PolarDayEndsTenHoursAfterNoon) {
    const sample::SunSchedule s = schedule_at(75.0);
    EXPECT_NEAR(s.end_utc_min, s.noon_utc_min + sample::kPolarDayScriptMinutes, kMinuteTolerance);
    EXPECT_EQ(s.sunset_utc_min, s.end_utc_min);
    EXPECT_EQ(s.night_utc_min, s.end_utc_min);
    EXPECT_EQ(sample::script_utc_min(s, 1.0), s.end_utc_min);
}

TEST(SampleFlight, TwentyFourFramesHaveAfternoonTwilightAndNight) {
    const sample::SunSchedule s = sample::default_sun_schedule();
    int afternoon = 0, twilight = 0, night = 0;
    double previous = 91.0;
    for (int i = 0; i < kFrames; ++i) {
        const sample::FlightState state = sample::flight_at(world(), double(i) / (kFrames - 1), s);
        const double sun = state.sun_elevation_rad / kDeg;
        EXPECT_LE(sun, previous) << "frame " << i << ": the sun rose";
        previous = sun;
        if (state.utc_min > s.noon_utc_min && sun > 0.0) ++afternoon;
        if (sun <= 0.0 && sun >= -12.0) ++twilight;
        if (sun < -12.0) ++night;
    }
    EXPECT_GE(afternoon, 8);
    EXPECT_GE(twilight, 4);
    EXPECT_GE(night, 4);
    EXPECT_NEAR(previous, -15.0, 0.01) << "the last frame ends the schedule";
}

TEST(SampleLight, DayIsExposedAsBeforeTheNight) {
    const sample::SunSchedule s = sample::default_sun_schedule();
    aerial::ExposureOptions options;
    options.key = sample::kExposureKey;
    options.max_gain = sample::kExposureMaxGain;
    aerial::SkyAmbientOptions ambient;
    ambient.elevation_steps = 8;
    ambient.azimuth_steps = 16;
    const auto skylight = [&](const aerial::Atmosphere& atmosphere, double elevation_rad) {
        return aerial::sky_ambient(atmosphere, sample::kLightingAltitudeM, elevation_rad, ambient)
            .value();
    };
    // Noon, the afternoon, sunset and twilight while the card is photopic.
    const double sunset_min = s.sunset_utc_min - s.noon_utc_min;
    for (double minutes : {0.0, 240.0, 360.0, 420.0, sunset_min, sunset_min + 10.0}) {
        sample::FlightState state;
        sample::place_sky(state, s, s.noon_utc_min + minutes);
        const sample::FrameLight light = sample::frame_light(state, "earth").value();
        ASSERT_GE(light.card_cd_m2, aerial::NightOptions{}.photopic_cd_m2) << minutes;
        // The rule of the sample before the night: the sun and its skylight at 300 m; after
        // sunset raised as the skylight fades, the sky's mean radiance held at max_sky_value.
        const double sun_rad = state.sun_elevation_rad;
        const glm::dvec3 sun = aerial::sun_irradiance_at_altitude(
            light.atmosphere, sample::kLightingAltitudeM, sun_rad);
        const glm::dvec3 sky = skylight(light.atmosphere, sun_rad);
        double before =
            aerial::auto_exposure(sun, sun_rad, sky, light.atmosphere.sun_irradiance, options);
        if (sun_rad < 0.0) {
            before = std::max(before,
                              aerial::NightOptions{}.max_sky_value * kPi / aerial::luminance(sky));
        }
        // The moon's light on the card adds about 1e-6 of the sun's by day.
        EXPECT_NEAR(light.exposure / before, 1.0, 1e-5) << minutes << " min after noon";
        EXPECT_EQ(light.tint, glm::dvec3(1.0)) << minutes << " min after noon";
    }
}

TEST(SampleLight, NightHasTheFirstQuarterMoonAsSecondLight) {
    const sample::FlightState state =
        sample::flight_at(world(), 1.0, sample::default_sun_schedule());
    ASSERT_TRUE(state.moon.has_value());
    EXPECT_NEAR(state.moon->phase_angle_rad / kDeg, 90.0, 5.0) << "first quarter on 2026-06-21";
    EXPECT_GT(state.moon->elevation_rad, 0.0);
    const aerial::scene::FrameSettings settings =
        sample::settings_for(state, "earth", aerial::Model::height, aerial::ToneCurve::exponential)
            .value();
    ASSERT_TRUE(settings.moon.has_value());
    EXPECT_GT(settings.moon->fraction, 0.0);
    EXPECT_NEAR(settings.moon->fraction / aerial::moonlight_fraction(*state.moon), 1.0,
                sample::kMoonFractionStep / 2 + 1e-9);
    EXPECT_NEAR(glm::length(settings.moon->dir), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(settings.moon->dir, aerial::moon_direction_enu(*state.moon)), 1.0, 1e-12);
}

TEST(SampleLight, NightIsExposedByNightExposureAndShownDark) {
    const sample::SunSchedule s = sample::default_sun_schedule();
    const sample::FlightState night = sample::flight_at(world(), 1.0, s);
    sample::FlightState dusk = night;  // the end of civil twilight
    sample::place_sky(dusk, s, s.sunset_utc_min + 40.0);
    ASSERT_LT(dusk.sun_elevation_rad, -5.0 * kDeg);
    const sample::FrameLight at_night = sample::frame_light(night, "earth").value();
    const sample::FrameLight at_dusk = sample::frame_light(dusk, "earth").value();
    ASSERT_TRUE(std::isfinite(at_night.exposure));
    EXPECT_GT(at_night.exposure, at_dusk.exposure);
    // The card below the scotopic level: night_exposure's rule alone (with the skylight's
    // hold), the card shown at most at key (L / 5)^0.25.
    ASSERT_LT(at_night.card_cd_m2, aerial::NightOptions{}.scotopic_cd_m2);
    aerial::ExposureOptions options;
    options.key = sample::kExposureKey;
    EXPECT_NEAR(at_night.exposure / aerial::night_exposure(at_night.atmosphere, at_night.card,
                                                           at_night.skylight, options),
                1.0, 1e-12);
    const double unheld =
        sample::kExposureKey *
        std::pow(at_night.card_cd_m2 / aerial::NightOptions{}.photopic_cd_m2, 0.25);
    EXPECT_LE(shown_card(at_night), unheld * (1.0 + 1e-9));
    EXPECT_GT(shown_card(at_night), 0.5 * unheld) << "the moon lights the card, not the sky";
    EXPECT_LT(shown_card(at_night), 0.2 * sample::kExposureKey) << "the night is shown dark";
    // Rod vision: the light's tint is the scotopic blue, its luminance kept.
    EXPECT_GT(at_night.tint.z, at_night.tint.x);
    EXPECT_GT(at_night.tint.x, at_night.tint.y);
    EXPECT_NEAR(aerial::luminance(at_night.tint), 1.0, 1e-12);
}

TEST(SampleNightSky, StarsAtNightNoneByDayAndTheMoonDrawn) {
    if (!std::ifstream(aerial::kBrightStarCataloguePath)) {
        GTEST_SKIP() << "no star catalogue at " << aerial::kBrightStarCataloguePath
                     << " (Debian's xplanet)";
    }
    const sample::SunSchedule s = sample::default_sun_schedule();
    const double pixel_rad = 50.0 * kDeg / 270.0;
    sample::NightSkyState night;
    const auto update = [&](const sample::FlightState& state) {
        const sample::FrameLight light = sample::frame_light(state, "earth").value();
        aerial::Display display;
        display.exposure = float(light.exposure);
        display.tone = aerial::ToneCurve::exponential;
        ASSERT_FALSE(sample::update_night_sky(night, state, s, light, display, pixel_rad));
    };
    const sample::FlightState noon = sample::flight_at(world(), 0.0, s);
    update(noon);
    EXPECT_TRUE(night.sky->stars.empty());
    EXPECT_EQ(night.stars.recomputes, 0) << "no star search by day";
    EXPECT_TRUE(night.sky->draw_moon) << "the first quarter moon rises before noon";
    EXPECT_NEAR(
        std::max({night.sky->moon_colour.x, night.sky->moon_colour.y, night.sky->moon_colour.z}),
        sample::kMoonColourMin, 1e-6)
        << "a faint moon by day";

    sample::FlightState state = sample::flight_at(world(), 1.0, s);
    update(state);
    EXPECT_GT(night.sky->stars.size(), 100u);
    EXPECT_EQ(night.stars.recomputes, 1);
    EXPECT_TRUE(night.sky->draw_moon);
    EXPECT_NEAR(night.sky->moon_phase_angle_rad, state.moon->phase_angle_rad, 1e-12);
    EXPECT_NEAR(
        std::max({night.sky->moon_colour.x, night.sky->moon_colour.y, night.sky->moon_colour.z}),
        1.0, 1e-6)
        << "the moon at night is the brightest thing";
    // A minute on the sun moves about 0.2 deg: the same stars, turned with the sky.
    const glm::dvec3 before = night.sky->stars.front().direction;
    sample::place_sky(state, s, state.utc_min + 1.0);
    update(state);
    EXPECT_EQ(night.stars.recomputes, 1);
    EXPECT_GT(glm::length(night.sky->stars.front().direction - before), 0.1 * kDeg);
    // Five minutes: found again.
    sample::place_sky(state, s, state.utc_min + 4.0);
    update(state);
    EXPECT_EQ(night.stars.recomputes, 2);
}

}  // namespace
