// The sun (aerial/sun.hpp): position against Meeus' worked examples and published sunrise and
// sunset times, the events against the position they are derived from, sunlight by altitude
// (mountain tops lit at dawn while valleys are dark), skylight, exposure, and bad input.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"

namespace {

constexpr double kDeg = aerial::kPi / 180.0;

aerial::Atmosphere earth() { return *aerial::atmosphere_preset("earth"); }

/// UTC minutes after midnight as a date-time of the same day.
aerial::UtcDateTime at_minutes(int y, int m, int d, double minutes) {
    aerial::UtcDateTime t{y, m, d, 0, 0, 0.0};
    t.hour = int(minutes / 60.0);
    t.minute = int(minutes - t.hour * 60.0);
    t.second = (minutes - t.hour * 60.0 - t.minute) * 60.0;
    return t;
}

TEST(SunPosition, DeclinationMatchesMeeusExample25a) {
    // Meeus, Astronomical Algorithms, example 25.a: 1992 October 13.0, apparent declination
    // -7 deg 47' 06" = -7.78507 deg (low-precision method).
    auto sun = aerial::sun_position({1992, 10, 13, 0, 0, 0.0}, 0.0, 0.0);
    ASSERT_TRUE(sun.ok()) << sun.error().message;
    EXPECT_NEAR(sun->declination_rad / kDeg, -7.78507, 0.005);
}

TEST(SunPosition, EquationOfTimeMatchesMeeusExample28a) {
    // Meeus example 28.a: 1992 October 13.0, E = +13 min 42.6 s.
    auto sun = aerial::sun_position({1992, 10, 13, 0, 0, 0.0}, 0.0, 0.0);
    ASSERT_TRUE(sun.ok());
    EXPECT_NEAR(sun->equation_of_time_min, 13.0 + 42.6 / 60.0, 0.05);
}

TEST(SunPosition, StandsOverheadAtTheSubsolarPointAtSolarNoon) {
    // At the June solstice the sun is overhead near the Tropic of Cancer at solar noon.
    auto events = aerial::solar_events(2026, 6, 21, 23.44 * kDeg, 0.0);
    ASSERT_TRUE(events.ok());
    auto sun = aerial::sun_position(at_minutes(2026, 6, 21, events->solar_noon_utc_min),
                                    23.44 * kDeg, 0.0);
    ASSERT_TRUE(sun.ok());
    EXPECT_GT(sun->elevation_rad / kDeg, 89.9);
}

TEST(SunPosition, DirectionPointsSouthAtNoonInTheNorth) {
    auto events = aerial::solar_events(2026, 3, 1, 48.0 * kDeg, 11.0 * kDeg);
    ASSERT_TRUE(events.ok());
    auto sun = aerial::sun_position(at_minutes(2026, 3, 1, events->solar_noon_utc_min), 48.0 * kDeg,
                                    11.0 * kDeg);
    ASSERT_TRUE(sun.ok());
    EXPECT_NEAR(sun->azimuth_rad / kDeg, 180.0, 0.05);
    const glm::dvec3 d = aerial::sun_direction_enu(*sun);
    EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
    EXPECT_LT(d.y, 0.0) << "north component of a southern sun";
    EXPECT_NEAR(d.z, std::sin(sun->elevation_rad), 1e-12);
    // Refraction lifts the image, most near the horizon.
    EXPECT_GT(sun->apparent_elevation_rad, sun->elevation_rad);
}

TEST(SolarEvents, SunriseAndSunsetAreWhereTheCentreIsStandardlyDepressed) {
    // The events are iterated at their own time: the position there must agree to seconds.
    for (double lat : {-33.9, 0.0, 40.7, 59.9}) {
        for (int month : {1, 4, 7, 10}) {
            auto ev = aerial::solar_events(2025, month, 15, lat * kDeg, -74.0 * kDeg);
            ASSERT_TRUE(ev.ok());
            ASSERT_TRUE(ev->sunrise_utc_min && ev->sunset_utc_min) << lat << " " << month;
            for (double when : {*ev->sunrise_utc_min, *ev->sunset_utc_min}) {
                // The events of a date can fall on the next UTC day far west of Greenwich.
                const int day_shift = int(std::floor(when / 1440.0));
                auto sun = aerial::sun_position(
                    at_minutes(2025, month, 15 + day_shift, when - 1440.0 * day_shift), lat * kDeg,
                    -74.0 * kDeg);
                ASSERT_TRUE(sun.ok());
                EXPECT_NEAR(sun->elevation_rad / kDeg, -0.833, 0.003)
                    << "lat " << lat << " month " << month << " at " << when << " min";
            }
        }
    }
}

TEST(SolarEvents, CivilTwilightEndsWhereTheCentreIsSixDegreesDown) {
    for (double lat : {-33.9, 0.0, 46.5}) {
        for (int month : {1, 6}) {
            auto ev = aerial::solar_events(2025, month, 15, lat * kDeg, 8.0 * kDeg);
            ASSERT_TRUE(ev.ok());
            ASSERT_TRUE(ev->civil_dawn_utc_min && ev->civil_dusk_utc_min) << lat << " " << month;
            EXPECT_LT(*ev->civil_dawn_utc_min, *ev->sunrise_utc_min);
            EXPECT_GT(*ev->civil_dusk_utc_min, *ev->sunset_utc_min);
            for (double when : {*ev->civil_dawn_utc_min, *ev->civil_dusk_utc_min}) {
                auto sun =
                    aerial::sun_position(at_minutes(2025, month, 15, when), lat * kDeg, 8.0 * kDeg);
                ASSERT_TRUE(sun.ok());
                EXPECT_NEAR(sun->elevation_rad / kDeg, -6.0, 0.003)
                    << "lat " << lat << " month " << month << " at " << when << " min";
            }
        }
    }
    // White nights: at 62 N at midsummer the sun sets but never sinks 6 degrees (4.6 at most).
    auto white = aerial::solar_events(2026, 6, 21, 62.0 * kDeg, 25.0 * kDeg);
    ASSERT_TRUE(white.ok());
    EXPECT_TRUE(white->sunset_utc_min.has_value());
    EXPECT_FALSE(white->civil_dusk_utc_min.has_value());
}

TEST(SolarEvents, MatchPublishedTimesForLondon) {
    // Published sunrise and sunset for London (51.5074 N, 0.1278 W), rounded to the minute:
    // 2024-06-20 04:43 and 21:21 BST (03:43 and 20:21 UTC); 2024-12-21 08:04 and 15:53 GMT.
    struct Case {
        int month, day;
        double sunrise_min, sunset_min;
    } cases[] = {{6, 20, 3 * 60 + 43, 20 * 60 + 21}, {12, 21, 8 * 60 + 4, 15 * 60 + 53}};
    for (const Case& c : cases) {
        auto ev = aerial::solar_events(2024, c.month, c.day, 51.5074 * kDeg, -0.1278 * kDeg);
        ASSERT_TRUE(ev.ok());
        ASSERT_TRUE(ev->sunrise_utc_min && ev->sunset_utc_min);
        // The published value is rounded, so a true time within [t - 0.5, t + 0.5] min; allow
        // one more minute for the algorithm.
        EXPECT_NEAR(*ev->sunrise_utc_min, c.sunrise_min, 1.5) << "month " << c.month;
        EXPECT_NEAR(*ev->sunset_utc_min, c.sunset_min, 1.5) << "month " << c.month;
    }
}

TEST(SolarEvents, EquatorialDayIsTwelveHoursAndSevenMinutesAtTheEquinox) {
    // Refraction and the sun's radius lengthen the equinox day at the equator by about 7 min.
    auto ev = aerial::solar_events(2026, 3, 20, 0.0, 0.0);
    ASSERT_TRUE(ev.ok());
    ASSERT_TRUE(ev->sunrise_utc_min && ev->sunset_utc_min);
    EXPECT_NEAR(*ev->sunset_utc_min - *ev->sunrise_utc_min, 12 * 60 + 7, 1.0);
    EXPECT_NEAR(ev->solar_noon_utc_min, 12 * 60 + 7.5, 0.5) << "equation of time about -7.5 min";
}

TEST(SolarEvents, PolarDayAndPolarNight) {
    auto summer = aerial::solar_events(2026, 6, 21, 80.0 * kDeg, 15.0 * kDeg);
    ASSERT_TRUE(summer.ok());
    EXPECT_TRUE(summer->polar_day);
    EXPECT_FALSE(summer->sunrise_utc_min.has_value());
    auto winter = aerial::solar_events(2026, 12, 21, 80.0 * kDeg, 15.0 * kDeg);
    ASSERT_TRUE(winter.ok());
    EXPECT_TRUE(winter->polar_night);
    EXPECT_FALSE(winter->sunset_utc_min.has_value());
}

TEST(SunPosition, RejectsBadInputNamingTheField) {
    struct Case {
        aerial::UtcDateTime t;
        double lat, lon;
        const char* field;
    } cases[] = {
        {{2023, 2, 29, 12, 0, 0.0}, 0.0, 0.0, "day"},
        {{2024, 13, 1, 12, 0, 0.0}, 0.0, 0.0, "month"},
        {{1800, 1, 1, 12, 0, 0.0}, 0.0, 0.0, "year"},
        {{2024, 1, 1, 24, 0, 0.0}, 0.0, 0.0, "hour"},
        {{2024, 1, 1, 12, 60, 0.0}, 0.0, 0.0, "minute"},
        {{2024, 1, 1, 12, 0, NAN}, 0.0, 0.0, "second"},
        {{2024, 1, 1, 12, 0, 0.0}, 2.0, 0.0, "latitude"},
        {{2024, 1, 1, 12, 0, 0.0}, 0.0, 4.0, "longitude"},
    };
    for (const Case& c : cases) {
        auto sun = aerial::sun_position(c.t, c.lat, c.lon);
        ASSERT_FALSE(sun.ok()) << c.field;
        EXPECT_EQ(sun.error().field, c.field);
        EXPECT_EQ(
            sun.error().message.rfind(std::string("aerial::sun_position(): ") + c.field + ": ", 0),
            0u)
            << sun.error().message;
    }
    EXPECT_EQ(aerial::solar_events(2024, 2, 30, 0.0, 0.0).error().message,
              "aerial::solar_events(): day: expected 1 .. 29 for 2024-2, got 30");
}

TEST(SunIrradiance, MountainTopsAreLitAtDawnWhileValleysAreDark) {
    // Sun 1 deg below the sea-level horizon: the planet shadows the valley floor; from 3000 m
    // the horizon dips by 1.76 deg, so the summit still sees the sun, reddened.
    const auto a = earth();
    const glm::dvec3 valley = aerial::sun_irradiance_at_altitude(a, 0.0, -1.0 * kDeg);
    const glm::dvec3 summit = aerial::sun_irradiance_at_altitude(a, 3000.0, -1.0 * kDeg);
    EXPECT_EQ(valley, glm::dvec3(0.0));
    EXPECT_GT(summit.x, 0.0);
    EXPECT_GT(summit.x, 5.0 * summit.z) << "dawn light on the summit is red";
    // Higher is brighter at a low sun, and noon is whiter than dawn.
    const glm::dvec3 low = aerial::sun_irradiance_at_altitude(a, 0.0, 3.0 * kDeg);
    const glm::dvec3 high = aerial::sun_irradiance_at_altitude(a, 2000.0, 3.0 * kDeg);
    EXPECT_GT(high.z, low.z);
    const glm::dvec3 noon = aerial::sun_irradiance_at_altitude(a, 0.0, 60.0 * kDeg);
    EXPECT_GT(noon.z / noon.x, 2.0 * low.z / low.x);
}

TEST(SunIrradianceProfile, MatchesTheDirectComputationBetweenSamples) {
    const auto a = earth();
    for (double elevation_deg : {-1.0, 0.5, 4.0, 30.0}) {
        auto p = aerial::SunIrradianceProfile::build(a, elevation_deg * kDeg, 0.0, 4000.0);
        ASSERT_TRUE(p.ok());
        for (double h = 17.0; h < 4000.0; h += 211.0) {
            const glm::dvec3 direct =
                aerial::sun_irradiance_at_altitude(a, h, elevation_deg * kDeg);
            const glm::dvec3 table = p->at(h);
            for (int c = 0; c < 3; ++c) {
                // 0.5 % relative, or 1e-4 of E_sun0 (a fortieth of an 8-bit step at exposure 1)
                // where the shadow edge crosses the table.
                EXPECT_NEAR(table[c], direct[c], std::max(0.005 * direct[c], 1e-4))
                    << "elevation " << elevation_deg << " altitude " << h << " channel " << c;
            }
        }
    }
    EXPECT_EQ(aerial::SunIrradianceProfile().at(100.0), glm::dvec3(0.0)) << "not built";
    EXPECT_EQ(aerial::SunIrradianceProfile::build(a, 0.1, 100.0, 100.0).error().field,
              "max_altitude_m");
    EXPECT_EQ(aerial::SunIrradianceProfile::build(a, 0.1, 0.0, 100.0, 1).error().field, "samples");
}

TEST(SkyAmbient, IsBlueAtNoonFallsAtDuskAndAgreesWithTheReferenceSky) {
    const auto a = earth();
    auto noon = aerial::sky_ambient(a, 0.0, 60.0 * kDeg);
    auto low = aerial::sky_ambient(a, 0.0, 5.0 * kDeg);
    auto night = aerial::sky_ambient(a, 0.0, -12.0 * kDeg);
    ASSERT_TRUE(noon.ok() && low.ok() && night.ok());
    EXPECT_GT(noon->z, 1.5 * noon->x) << "skylight is blue";
    EXPECT_GT(noon->y, low->y);
    EXPECT_LT(night->y, 1e-3 * noon->y) << "single scattering: no skylight once the air is dark";
    aerial::SkyAmbientOptions reference;
    reference.use_reference = true;
    reference.elevation_steps = 4;
    reference.azimuth_steps = 8;
    aerial::SkyAmbientOptions coarse = reference;
    coarse.use_reference = false;
    auto exact = aerial::sky_ambient(a, 0.0, 30.0 * kDeg, reference);
    auto fast = aerial::sky_ambient(a, 0.0, 30.0 * kDeg, coarse);
    ASSERT_TRUE(exact.ok() && fast.ok());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR((*fast)[c], (*exact)[c], 0.01 * (*exact)[c]);
    // A finer quadrature changes the default result by little (convergence).
    aerial::SkyAmbientOptions fine;
    fine.elevation_steps = 32;
    fine.azimuth_steps = 64;
    auto converged = aerial::sky_ambient(a, 0.0, 30.0 * kDeg, fine);
    auto standard = aerial::sky_ambient(a, 0.0, 30.0 * kDeg);
    ASSERT_TRUE(converged.ok() && standard.ok());
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR((*standard)[c], (*converged)[c], 0.03 * (*converged)[c]);
    aerial::SkyAmbientOptions bad;
    bad.azimuth_steps = 2;
    EXPECT_EQ(aerial::sky_ambient(a, 0.0, 0.5, bad).error().field, "azimuth_steps");
}

TEST(Exposure, NoonAndDawnBothReadWell) {
    const auto a = earth();
    auto grey_card = [&](double elevation_deg, double exposure) {
        const double e = elevation_deg * kDeg;
        const glm::dvec3 sun = aerial::sun_irradiance_at_altitude(a, 0.0, e);
        const glm::dvec3 sky = *aerial::sky_ambient(a, 0.0, e);
        const glm::dvec3 radiance = 0.18 / aerial::kPi * (sun * std::max(std::sin(e), 0.0) + sky);
        return aerial::luminance(
            aerial::tone_map(radiance, exposure, aerial::ToneCurve::exponential));
    };
    auto exposure_at = [&](double elevation_deg) {
        const double e = elevation_deg * kDeg;
        return aerial::auto_exposure(aerial::sun_irradiance_at_altitude(a, 0.0, e), e,
                                     *aerial::sky_ambient(a, 0.0, e), a.sun_irradiance);
    };
    const double noon_exposure = exposure_at(60.0), dawn_exposure = exposure_at(3.0);
    const double target = 1.0 - std::exp(-0.5);  // the default key through the curve
    EXPECT_NEAR(grey_card(60.0, noon_exposure), target, 0.03);
    EXPECT_NEAR(grey_card(3.0, dawn_exposure), target, 0.03);
    EXPECT_LT(grey_card(3.0, noon_exposure), 0.5 * target) << "a fixed noon exposure loses dawn";
    // Night is held at the gain limit instead of being lifted to grey.
    aerial::ExposureOptions o;
    const double limit =
        o.max_gain * o.key / (o.albedo / aerial::kPi * aerial::luminance(a.sun_irradiance));
    EXPECT_NEAR(exposure_at(-15.0), limit, 1e-9 * limit);
    EXPECT_LT(dawn_exposure, limit);
}

TEST(ToneCurve, NamesRoundTripAndCurvesStayInRange) {
    for (aerial::ToneCurve c : {aerial::ToneCurve::clamp, aerial::ToneCurve::exponential}) {
        auto parsed = aerial::parse_tone_curve(aerial::tone_curve_name(c));
        ASSERT_TRUE(parsed.ok());
        EXPECT_EQ(*parsed, c);
        double last = -1;
        for (double x : {0.0, 0.1, 0.5, 1.0, 4.0, 1e6}) {
            const double v = aerial::tone_map(glm::dvec3(x), 1.0, c).x;
            EXPECT_GE(v, last);
            EXPECT_LE(v, 1.0);
            last = v;
        }
        EXPECT_EQ(aerial::tone_map(glm::dvec3(NAN, -1.0, 0.0), 2.0, c), glm::dvec3(0.0));
    }
    EXPECT_EQ(aerial::parse_tone_curve("filmic").error().field, "tone_curve");
}

}  // namespace
