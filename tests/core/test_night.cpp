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
    std::printf(
        "moon 1992-04-12 0h: ra %.6f dec %.6f deg, %.1f km, phase angle %.4f deg, "
        "fraction %.4f\n",
        moon->right_ascension_rad / kDegree, moon->declination_rad / kDegree, moon->distance_km,
        moon->phase_angle_rad / kDegree, moon->illuminated_fraction);
}

// The horizontal position is the equatorial one seen from the place: at the moon's transit its
// azimuth is south (northern observer) and its elevation 90 deg - latitude + declination, less the
// parallax (up to a degree).
TEST(Moon, HorizontalPositionFollowsTheEquatorialOne) {
    const auto moon =
        aerial::moon_position({2026, 12, 6, 20, 0, 0.0}, 48.0 * kDegree, 11.0 * kDegree);
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
              "aerial::moon_position(): latitude: expected a value in [-pi/2, pi/2] rad, got 2");
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
        auto seen = aerial::visible_stars(*stars, earth, 100.0, sun_at(sun_elevation_deg), latitude,
                                          sidereal);
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
        worst =
            std::max(worst, std::abs(dated[0].declination_rad - noaa->declination_rad) / kDegree);
    }
    std::printf("sun: NOAA against libnova, declination within %.4f deg over 2026\n", worst);
    EXPECT_LT(worst, 0.02);
}

}  // namespace

namespace {

// Krisciunas & Schaefer (1991), eq. 15-21: the sky brightness the moon adds, V band, nL, for a
// moon of phase angle alpha (deg) at zenith distance zm, a sky point at zenith distance z and
// rho degrees from the moon, with an extinction of k magnitudes an airmass.
double krisciunas_schaefer_cd_m2(double alpha, double zm, double z, double rho, double k) {
    const auto airmass = [](double zenith_deg) {
        return 1.0 / std::sqrt(1.0 - 0.96 * std::pow(std::sin(zenith_deg * kDegree), 2.0));
    };
    const double f = std::pow(10.0, 5.36) * (1.06 + std::pow(std::cos(rho * kDegree), 2.0)) +
                     std::pow(10.0, 6.15 - rho / 40.0);
    const double illuminance =
        std::pow(10.0, -0.4 * (3.84 + 0.026 * alpha + 4e-9 * std::pow(alpha, 4.0)));
    const double nl = f * illuminance * std::pow(10.0, -0.4 * k * airmass(zm)) *
                      (1.0 - std::pow(10.0, -0.4 * k * airmass(z)));
    return nl * 1e-5 / kPi;  // 1 nL = 1e-5 / pi cd/m2
}

// The moonlit sky of the model (the height model's chained sky lit from the moon's direction by
// moonlight_fraction of the sun's light) against Krisciunas & Schaefer's empirical model with
// the same extinction (the earth preset's vertical G optical depth): within 30 % from 60 deg
// from the moon outwards; nearer the moon the model's aureole is fainter than their fit (ratio
// 0.46-0.88 within 45 deg), which the test reports and bounds loosely.
TEST(Moon, MoonlitSkyAgainstKrisciunasSchaefer) {
    const aerial::Atmosphere earth = aerial::atmosphere_preset("earth").value();
    const double k = -2.5 * std::log10(aerial::sun_transmittance(earth, 0.0, 1.0).y);
    double far_worst = 1.0, near_lowest = 1.0;
    for (double moon_el : {30.0, 60.0}) {
        for (double alpha : {0.0, 60.0}) {
            aerial::MoonPosition moon;
            moon.elevation_rad = moon_el * kDegree;
            moon.phase_angle_rad = alpha * kDegree;
            moon.distance_km = 384400.0;
            aerial::View view;
            view.up = {0, 0, 1};
            view.sun_dir = aerial::moon_direction_enu(moon);
            for (double el : {90.0, 60.0, 30.0, 15.0}) {
                for (double az : {0.0, 90.0, 180.0}) {
                    const glm::dvec3 d{std::cos(el * kDegree) * std::sin(az * kDegree),
                                       std::cos(el * kDegree) * std::cos(az * kDegree),
                                       std::sin(el * kDegree)};
                    const auto model = aerial::sky_luminance_cd_m2(
                        earth, view, d, aerial::moonlight_fraction(moon));
                    ASSERT_TRUE(model.ok()) << model.error().message;
                    const double rho = std::acos(glm::dot(d, view.sun_dir)) / kDegree;
                    const double ratio = *model / krisciunas_schaefer_cd_m2(alpha, 90.0 - moon_el,
                                                                            90.0 - el, rho, k);
                    if (rho >= 60.0)
                        far_worst = std::max(far_worst, std::max(ratio, 1.0 / ratio));
                    else
                        near_lowest = std::min(near_lowest, ratio);
                }
            }
        }
    }
    std::printf(
        "moonlit sky / Krisciunas-Schaefer: within a factor %.2f from 60 deg off the "
        "moon, lowest ratio %.2f nearer (k = %.3f mag an airmass)\n",
        far_worst, near_lowest, k);
    EXPECT_LE(far_worst, 1.3);
    EXPECT_GT(near_lowest, 0.4);
}

// A full moon brightens the sky around it: fewer stars there than on a moonless night.
TEST(Stars, FewerNearTheMoon) {
    const auto catalogue = aerial::read_star_catalogue(aerial::kBrightStarCataloguePath);
    ASSERT_TRUE(catalogue.ok());
    const aerial::Atmosphere earth = aerial::atmosphere_preset("earth").value();
    aerial::MoonPosition moon;
    moon.elevation_rad = 45.0 * kDegree;
    moon.azimuth_rad = kPi;
    moon.distance_km = 384400.0;
    aerial::StarVisibilityOptions with_moon;
    with_moon.moon_enu = aerial::moon_direction_enu(moon);
    with_moon.moon_fraction = aerial::moonlight_fraction(moon);
    const auto dark =
        aerial::visible_stars(*catalogue, earth, 100.0, sun_at(-30.0), 45.0 * kDegree, 1.0);
    const auto lit = aerial::visible_stars(*catalogue, earth, 100.0, sun_at(-30.0), 45.0 * kDegree,
                                           1.0, with_moon);
    ASSERT_TRUE(dark.ok() && lit.ok());
    const auto near = [&](const std::vector<aerial::VisibleStar>& seen) {
        std::size_t n = 0;
        for (const auto& s : seen) n += glm::dot(s.direction, with_moon.moon_enu) > std::cos(0.35);
        return n;
    };
    std::printf(
        "stars within 20 deg of a full moon 45 deg up: %zu (moonless: %zu); in all %zu "
        "(%zu)\n",
        near(*lit), near(*dark), lit->size(), dark->size());
    EXPECT_LT(near(*lit) * 4, near(*dark));
    EXPECT_LT(lit->size(), dark->size());
}

// Each star's dimming is the G transmittance to space along its direction (a table by elevation
// stands in for one integral a star): within 0.002 magnitudes above 1 degree.
TEST(Stars, DimmedByTheTransmittanceAlongTheirDirection) {
    const auto catalogue = aerial::read_star_catalogue(aerial::kBrightStarCataloguePath);
    ASSERT_TRUE(catalogue.ok());
    const aerial::Atmosphere hazy = aerial::atmosphere_preset("hazy").value();
    const auto seen =
        aerial::visible_stars(*catalogue, hazy, 100.0, sun_at(-30.0), 45.0 * kDegree, 2.0);
    ASSERT_TRUE(seen.ok());
    ASSERT_GT(seen->size(), 100u);
    double worst = 0.0;
    std::size_t compared = 0;
    for (const aerial::VisibleStar& v : *seen) {
        if (v.direction.z < std::sin(kDegree)) continue;
        const double t = aerial::sun_transmittance(hazy, 100.0, v.direction.z).y;
        const double expected = (*catalogue)[v.index].magnitude - 2.5 * std::log10(t);
        worst = std::max(worst, std::abs(v.apparent_magnitude - expected));
        ++compared;
    }
    std::printf("dimming of %zu stars within %.5f magnitudes of the transmittance's\n", compared,
                worst);
    EXPECT_LT(worst, 0.002);
}

}  // namespace

namespace {

// The sprite's lit share of the disc is the illuminated fraction (1 + cos i) / 2, and its lit
// side faces the bright limb's angle; the angle follows the sun across the line of sight.
TEST(Moon, SpriteShowsThePhaseOnTheSunsSide) {
    for (double i_deg : {0.0, 45.0, 90.0, 135.0, 170.0}) {
        const auto sprite = aerial::make_moon_sprite(i_deg * kDegree, 0.0, 128);
        ASSERT_TRUE(sprite.ok()) << sprite.error().message;
        EXPECT_NEAR(sprite->lit_fraction, 0.5 * (1.0 + std::cos(i_deg * kDegree)), 0.02) << i_deg;
    }
    // Half moon, limb to the left (pi / 2): the lit texels lie left of the centre.
    const auto half = aerial::make_moon_sprite(90.0 * kDegree, 0.5 * kPi, 64).value();
    double x_sum = 0.0, weight = 0.0;
    for (int row = 0; row < 64; ++row)
        for (int col = 0; col < 64; ++col) {
            const double v = half.rgba[4 * (std::size_t(row) * 64 + std::size_t(col))];
            x_sum += v * (col + 0.5 - 32.0);
            weight += v;
        }
    EXPECT_LT(x_sum / weight, -10.0);
    EXPECT_EQ(half.rgba[3], 0) << "outside the disc: transparent";
    EXPECT_EQ(half.rgba[4 * (32 * 64 + 32) + 3], 255);
    // The moon in the east 30 deg up, the sun north of it on the sky: looking east, north is on
    // the left.
    const glm::dvec3 moon{std::cos(30.0 * kDegree), 0.0, std::sin(30.0 * kDegree)};
    const glm::dvec3 sun = glm::normalize(moon + glm::dvec3(0.0, 0.5, 0.0));
    EXPECT_NEAR(aerial::moon_bright_limb_angle_rad(moon, sun, {0, 0, 1}), 0.5 * kPi, 1e-9);
    const glm::dvec3 below = glm::normalize(moon - glm::dvec3(0.0, 0.0, 0.5));
    EXPECT_NEAR(std::abs(aerial::moon_bright_limb_angle_rad(moon, below, {0, 0, 1})), kPi, 0.05);
    EXPECT_EQ(aerial::make_moon_sprite(4.0, 0.0, 64).error().field, "phase_angle_rad");
    EXPECT_EQ(aerial::make_moon_sprite(1.0, 0.0, 4).error().field, "size");
}

}  // namespace

namespace {

// The day rule by day; below the photopic luminance the card is shown darker as the light
// falls, never clamped to black; a full moon leaves it readable.
TEST(NightExposure, DayAsBeforeMoonlightDarkButReadable) {
    const aerial::Atmosphere earth = aerial::atmosphere_preset("earth").value();
    const aerial::ExposureOptions day;
    const double noon_elevation = 60.0 * kDegree;
    const glm::dvec3 sun = aerial::sun_irradiance_at_altitude(earth, 0.0, noon_elevation);
    const glm::dvec3 sky = aerial::sky_ambient(earth, 0.0, noon_elevation).value();
    const glm::dvec3 noon = sun * std::sin(noon_elevation) + sky;
    EXPECT_NEAR(aerial::night_exposure(earth, noon),
                aerial::auto_exposure(sun, noon_elevation, sky, earth.sun_irradiance), 1e-9);

    aerial::MoonPosition full;
    full.elevation_rad = 45.0 * kDegree;
    full.distance_km = 384400.0;
    const aerial::Atmosphere lit = aerial::moonlit(earth, full);
    const glm::dvec3 moon = aerial::sun_irradiance_at_altitude(lit, 0.0, full.elevation_rad) *
                                std::sin(full.elevation_rad) +
                            aerial::sky_ambient(lit, 0.0, full.elevation_rad).value();
    const double card = aerial::card_luminance_cd_m2(earth, moon);
    const double shown =
        aerial::night_exposure(earth, moon) * day.albedo / kPi * aerial::luminance(moon);
    std::printf("full moon 45 deg up: card %.4f cd/m2, shown at %.3f (day %.2f)\n", card, shown,
                day.key);
    EXPECT_GT(card, 0.005);
    EXPECT_LT(card, 0.05);
    EXPECT_GT(shown, 0.05);
    EXPECT_LT(shown, 0.2);
    // Darker light is shown darker, all the way down.
    double last = 1e9;
    for (double f = 1.0; f > 1e-9; f *= 0.1) {
        const glm::dvec3 e = noon * f;
        const double value =
            aerial::night_exposure(earth, e) * day.albedo / kPi * aerial::luminance(e);
        EXPECT_LE(value, last + 1e-12) << f;
        last = value;
    }
    EXPECT_GT(last, 0.0);
}

// In twilight the card is lit by the sky alone: with the sky's irradiance the exposure holds
// the sky's mean radiance at max_sky_value there, by the sky's share of the card (little by
// day), and leaves a moonlit night, whose sky is dark, as it was.
TEST(NightExposure, TwilightHoldsTheSkyMoonlightIsLeftAlone) {
    const aerial::Atmosphere earth = aerial::atmosphere_preset("earth").value();
    const aerial::NightOptions night;
    const auto sky_value = [&](const glm::dvec3& card, const glm::dvec3& sky) {
        return aerial::night_exposure(earth, card, sky) * aerial::luminance(sky) / kPi;
    };
    double last_sky = 0.0;
    for (double sun_deg : {10.0, -2.0, -6.0, -9.0, -12.0}) {
        const glm::dvec3 sky = aerial::sky_ambient(earth, 0.0, sun_deg * kDegree).value();
        const glm::dvec3 direct =
            aerial::sun_irradiance_at_altitude(earth, 0.0, sun_deg * kDegree) *
            std::max(0.0, std::sin(sun_deg * kDegree));
        const glm::dvec3 card = direct + sky;
        const double held = sky_value(card, sky);
        const double unheld = aerial::night_exposure(earth, card) * aerial::luminance(sky) / kPi;
        const double share = aerial::luminance(sky) / aerial::luminance(card);
        std::printf("sun %5.1f deg: sky shown at %.3f (card rule alone %.3f), sky's share %.2f\n",
                    sun_deg, held, unheld, share);
        EXPECT_LE(held, unheld * (1.0 + 1e-12));
        if (unheld > night.max_sky_value) {
            EXPECT_GE(held, night.max_sky_value * 0.999) << sun_deg;
            // In log exposure, the sky's share of the way to the hold.
            EXPECT_NEAR(std::log(held),
                        std::log(unheld) - share * std::log(unheld / night.max_sky_value), 1e-9)
                << sun_deg;
        }
        if (sun_deg < 0.0) {
            EXPECT_NEAR(held, night.max_sky_value, 1e-6) << sun_deg;
        }
        last_sky = held;
    }
    EXPECT_GT(last_sky, 0.0);
    // A full moon 45 degrees up, the sun far below: the card rule alone.
    aerial::MoonPosition full;
    full.elevation_rad = 45.0 * kDegree;
    full.distance_km = 384400.0;
    const aerial::Atmosphere lit = aerial::moonlit(earth, full);
    const glm::dvec3 moon_sky = aerial::sky_ambient(lit, 0.0, full.elevation_rad).value();
    const glm::dvec3 moon = aerial::sun_irradiance_at_altitude(lit, 0.0, full.elevation_rad) *
                                std::sin(full.elevation_rad) +
                            moon_sky;
    EXPECT_EQ(aerial::night_exposure(earth, moon, moon_sky), aerial::night_exposure(earth, moon));
}

TEST(NightExposure, PurkinjeShiftKeepsLuminanceAndTurnsBlueAtNight) {
    const glm::dvec3 orange{0.8, 0.5, 0.2};
    EXPECT_EQ(aerial::rod_share(10.0), 0.0);
    EXPECT_EQ(aerial::rod_share(0.001), 1.0);
    EXPECT_NEAR(aerial::rod_share(std::sqrt(5.0 * 0.005)), 0.5, 1e-12);
    EXPECT_EQ(aerial::purkinje_shift(orange, 10.0), orange);
    const glm::dvec3 night = aerial::purkinje_shift(orange, 0.001);
    EXPECT_NEAR(aerial::luminance(night), aerial::luminance(orange), 1e-12);
    EXPECT_GT(night.z, night.x) << "blue over red under rod vision";
    EXPECT_NEAR(night.z / night.y, 1.27 / 0.97, 1e-12);
}

}  // namespace

namespace {

TEST(Stars, AppearanceGrowsWithTheMarginAboveTheLimit) {
    aerial::VisibleStar at_limit;
    at_limit.apparent_magnitude = at_limit.limiting_magnitude = 6.0;
    aerial::VisibleStar bright = at_limit;
    bright.apparent_magnitude = 1.0;
    const auto faint = aerial::star_appearance(at_limit, 0.001);
    const auto vivid = aerial::star_appearance(bright, 0.001);
    EXPECT_FLOAT_EQ(faint.brightness, 0.15f);
    EXPECT_FLOAT_EQ(faint.half_width_rad, 0.00075f);
    EXPECT_FLOAT_EQ(vivid.brightness, 1.0f);
    EXPECT_FLOAT_EQ(vivid.half_width_rad, 0.00225f);
    const auto glow = aerial::make_star_glow(16).value();
    EXPECT_EQ(glow.rgba.size(), 16u * 16u * 4u);
    EXPECT_GT(glow.rgba[4 * (8 * 16 + 8)], 200) << "bright in the middle";
    EXPECT_EQ(glow.rgba[0], 0) << "dark at the corner";
    EXPECT_EQ(aerial::make_star_glow(4).error().field, "size");
}

}  // namespace
