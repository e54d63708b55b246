// The night sky's sources (aerial/night.hpp): the moon against Meeus's worked examples, the star
// catalogue, and star visibility as properties of the model's own sky.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <libnova/julian_day.h>
#include <libnova/solar.h>

#include "aerial/night.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

glm::dvec3 sun_at(double elevation_deg) {
    return {0.0, std::cos(elevation_deg * kDegree), std::sin(elevation_deg * kDegree)};
}

// Meeus, Astronomical Algorithms (2nd ed.), example 47.a: 1992 April 12, 0h TD: apparent right
// ascension 134.688470 deg, declination 13.768368 deg, distance 368 409.7 km; example 48.a: the
// phase angle 69.0756 deg, the illuminated fraction 0.6786.
TEST(Moon, MatchesMeeussWorkedExamples) {
    const auto moon = aerial::moon_position({1992, 4, 12, 0, 0, 0.0}, 0.0, 0.0);
    ASSERT_TRUE(moon.ok()) << moon.error().message;
    const double dec = 13.768368 * kDegree;
    EXPECT_NEAR((moon->right_ascension_rad - 134.688470 * kDegree) * std::cos(dec), 0.0,
                0.05 * kDegree);
    EXPECT_NEAR(moon->declination_rad, dec, 0.05 * kDegree);
    EXPECT_NEAR(moon->distance_km, 368409.7, 50.0);
    EXPECT_NEAR(moon->phase_angle_rad, 69.0756 * kDegree, 0.01 * 69.0756 * kDegree);
    EXPECT_NEAR(moon->illuminated_fraction, 0.6786, 0.01 * 0.6786);
    std::printf("moon 1992-04-12 0h: ra %.6f dec %.6f deg, %.1f km, phase angle %.4f deg, "
                "fraction %.4f\n",
                moon->right_ascension_rad / kDegree, moon->declination_rad / kDegree,
                moon->distance_km, moon->phase_angle_rad / kDegree, moon->illuminated_fraction);
}

// The horizontal position is the equatorial one seen from the place: at the moon's transit its
// azimuth is south (northern observer) and its elevation 90 deg - latitude + declination, less the
// parallax (up to a degree).
TEST(Moon, HorizontalPositionFollowsTheEquatorialOne) {
    const auto moon = aerial::moon_position({2026, 12, 6, 20, 0, 0.0}, 48.0 * kDegree,
                                            11.0 * kDegree);
    ASSERT_TRUE(moon.ok());
    const glm::dvec3 d = aerial::moon_direction_enu(*moon);
    EXPECT_NEAR(glm::length(d), 1.0, 1e-12);
    EXPECT_NEAR(d.z, std::sin(moon->elevation_rad), 1e-12);
    EXPECT_GE(moon->azimuth_rad, 0.0);
    EXPECT_LT(moon->azimuth_rad, 2.0 * kPi);
    // Altitude from the geocentric position and the local sidereal time, within the parallax.
    const double lst = aerial::local_sidereal_time_rad({2026, 12, 6, 20, 0, 0.0}, 11.0 * kDegree);
    const aerial::Star as_star{moon->right_ascension_rad, moon->declination_rad, 0.0};
    const glm::dvec3 geocentric = aerial::star_direction_enu(as_star, 48.0 * kDegree, lst);
    EXPECT_NEAR(std::asin(geocentric.z), moon->elevation_rad, 1.05 * kDegree);
    EXPECT_LE(moon->elevation_rad, std::asin(geocentric.z) + 1e-6) << "parallax lowers the moon";
    EXPECT_EQ(aerial::moon_position({2026, 12, 6, 20, 0, 0.0}, 2.0, 0.0).error().message,
              "aerial::moon_position(): latitude_rad: expected a value in [-pi/2, pi/2], got 2");
}

// Krisciunas & Schaefer: the full moon about 0.3 lux, a quarter moon about a tenth of it.
TEST(Moon, IlluminanceFollowsThePhaseLaw) {
    const double full = aerial::moon_illuminance_lux(0.0, 384400.0);
    const double quarter = aerial::moon_illuminance_lux(90.0 * kDegree, 384400.0);
    EXPECT_NEAR(full, 0.31, 0.02);
    EXPECT_NEAR(quarter / full, 0.088, 0.01);
    EXPECT_NEAR(aerial::moon_illuminance_lux(0.0, 356500.0) / full,
                std::pow(384400.0 / 356500.0, 2.0), 1e-12);
}

TEST(Stars, TheCatalogueReadsAndBadLinesAreNamed) {
    const auto stars = aerial::read_star_catalogue(aerial::kBrightStarCataloguePath);
    ASSERT_TRUE(stars.ok()) << stars.error().message << " (Debian package xplanet)";
    EXPECT_GT(stars->size(), 9000u);
    EXPECT_NEAR(stars->front().magnitude, -1.46, 1e-9) << "Sirius first";
    const std::string path = testing::TempDir() + "bad_stars.txt";
    std::ofstream(path) << "# comment\n-16.7161  6.7525 -1.46\n12.0 25.0 3.0\n";
    const auto bad = aerial::read_star_catalogue(path);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().message,
              "aerial::read_star_catalogue(): " + path +
                  ":3: expected declination (degrees, -90 .. 90), right ascension (hours, 0 .. "
                  "24) and magnitude");
}

TEST(Stars, LimitingMagnitudeFallsAsTheSkyBrightens) {
    const double dark = aerial::limiting_magnitude(aerial::kNaturalNightSkyCdM2);
    EXPECT_GT(dark, 6.0);
    EXPECT_LT(dark, 7.0);
    double last = dark;
    for (double b : {1e-3, 1e-2, 0.1, 1.0, 10.0, 1e3}) {
        const double m = aerial::limiting_magnitude(b);
        EXPECT_LT(m, last) << b;
        last = m;
    }
    EXPECT_LT(aerial::limiting_magnitude(5000.0), -3.0) << "a daylight sky hides every star";
}

// Visibility follows the model's sky: none in daylight, more as the sun sinks through nautical
// into astronomical twilight, and at -18 deg (no moon) the count a dark site shows.
TEST(Stars, VisibleCountFollowsTheSky) {
    const auto stars = aerial::read_star_catalogue(aerial::kBrightStarCataloguePath);
    ASSERT_TRUE(stars.ok()) << stars.error().message;
    const aerial::Atmosphere earth = aerial::atmosphere_preset("earth").value();
    const double latitude = 45.0 * kDegree, sidereal = 1.0;
    const auto count = [&](double sun_elevation_deg) {
        auto seen = aerial::visible_stars(*stars, earth, 100.0, sun_at(sun_elevation_deg),
                                          latitude, sidereal);
        EXPECT_TRUE(seen.ok()) << seen.error().message;
        return seen.ok() ? seen->size() : 0;
    };
    EXPECT_EQ(count(30.0), 0u);
    EXPECT_EQ(count(0.0), 0u);
    std::size_t last = 0;
    for (double sun = -6.0; sun >= -18.0; sun -= 2.0) {
        const std::size_t n = count(sun);
        std::printf("sun %5.1f deg: %zu stars visible\n", sun, n);
        EXPECT_GE(n, last) << sun;
        last = n;
    }
    EXPECT_GE(last, 2000u);
    EXPECT_LE(last, 3500u);
    EXPECT_LT(count(-8.0), count(-18.0));
}

}  // namespace

namespace {

// Precession moves the catalogue's J2000 places by about 50" a year: Polaris (J2000 RA 2h 31m
// 49s, Dec +89 15' 51") is at RA 3h 5m, Dec +89 22' in 2026 (its apparent place).
TEST(Stars, PlacesOfTheDateArePrecessed) {
    const aerial::Star polaris{(2.0 + 31.0 / 60.0 + 49.09 / 3600.0) * 15.0 * kDegree,
                               (89.0 + 15.0 / 60.0 + 50.8 / 3600.0) * kDegree, 2.0};
    const auto dated = aerial::stars_of_date({polaris}, {2026, 12, 6, 0, 0, 0.0});
    EXPECT_NEAR(dated[0].declination_rad / kDegree, 89.0 + 22.0 / 60.0, 0.02);
    EXPECT_NEAR(dated[0].right_ascension_rad / kDegree / 15.0, 3.0 + 5.0 / 60.0, 0.1);
}

// The sun of libnova (VSOP87) and of the NOAA calculator that sun_position uses agree within
// 0.02 deg over a year (both are far better than a pixel of a sky; sun_position stays the
// source for the sun: it needs no library and gives the equation of time and the events).
TEST(Sun, TheNoaaCalculatorAgreesWithLibnova) {
    double worst = 0.0;
    for (int month = 1; month <= 12; ++month) {
        const aerial::UtcDateTime t{2026, month, 15, 10, 0, 0.0};
        const auto noaa = aerial::sun_position(t, 48.0 * kDegree, 11.0 * kDegree);
        ASSERT_TRUE(noaa.ok());
        ln_date date{t.year, t.month, t.day, t.hour, t.minute, t.second};
        ln_equ_posn sun{};
        ln_get_solar_equ_coords(ln_get_julian_day(&date), &sun);
        // libnova's places are J2000's: to the date's apparent place as for the stars.
        const auto dated = aerial::stars_of_date({{sun.ra * kDegree, sun.dec * kDegree, 0.0}}, t);
        worst = std::max(worst, std::abs(dated[0].declination_rad - noaa->declination_rad) / kDegree);
    }
    std::printf("sun: NOAA against libnova, declination within %.4f deg over 2026\n", worst);
    EXPECT_LT(worst, 0.02);
}

}  // namespace
