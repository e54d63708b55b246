// Accuracy of the per-vertex models against the `reference` model, on the cases the foundation
// issue names. Each test prints the worst errors it saw, so that a run of
//   build/bin/test_core_accuracy
// is also the table quoted in the docs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "test_scale.hpp"

namespace {

using aerial::Atmosphere;
using aerial::Model;
using aerial::View;
using glm::dvec3;

/// Worst relative errors of one model over a set of cases.
struct Worst {
    double extinction = 0.0;
    double in_scattering = 0.0;
    std::string where_in_scattering;

    void add(const aerial::Scattering<double>& got, const aerial::Scattering<double>& ref,
             const std::string& where) {
        for (int c = 0; c < 3; ++c) {
            extinction = std::max(extinction, std::abs(got.extinction[c] / ref.extinction[c] - 1));
            const double e = std::abs(got.in_scattering[c] / ref.in_scattering[c] - 1);
            if (e > in_scattering) {
                in_scattering = e;
                where_in_scattering = where + " channel " + std::to_string(c);
            }
        }
    }
    void print(const char* table, Model m) const {
        std::printf("| %-44s | %-16s | %8.3f %% | %8.3f %% |\n", table,
                    std::string(aerial::model_name(m)).c_str(), 100 * extinction,
                    100 * in_scattering);
    }
};

dvec3 sun_from_degrees(double elevation_deg, double azimuth_deg) {
    const double el = elevation_deg * aerial::kPi / 180, az = azimuth_deg * aerial::kPi / 180;
    return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

/// A point at horizontal (great-circle chord) distance `distance_m` along +Y from the origin, at
/// altitude `altitude_m` above the sphere.
dvec3 point_on_sphere(const Atmosphere& a, double distance_m, double altitude_m) {
    const double r = a.planet_radius_m + altitude_m;
    return {0.0, distance_m, std::sqrt(r * r - distance_m * distance_m) - a.planet_radius_m};
}

/// Runs `models` over the ground-level set: eye and target altitudes from `altitudes`, horizontal
/// distances up to `max_distance_m`, sun elevations from `min_sun_deg` up, four azimuths.
void ground_level_set(const std::vector<double>& altitudes, double max_distance_m,
                      double min_sun_deg, const std::function<void(const View&, dvec3)>& visit) {
    const Atmosphere a;
    for (double eye_alt : altitudes) {
        for (double target_alt : altitudes) {
            for (double d : {1000.0, 0.5 * max_distance_m, max_distance_m}) {
                for (double elevation : {min_sun_deg, 30.0, 60.0, 90.0}) {
                    for (double azimuth : {0.0, 60.0, 120.0, 180.0}) {
                        View v;
                        v.eye = {0.0, 0.0, eye_alt};
                        v.sun_dir = sun_from_degrees(std::max(elevation, min_sun_deg), azimuth);
                        visit(v, point_on_sphere(a, d, target_alt));
                    }
                }
            }
        }
    }
}

std::string describe(const View& v, dvec3 p) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "eye z=%g, target (%g, %g, %g), sun (%.3f, %.3f, %.3f)",
                  v.eye.z, p.x, p.y, p.z, v.sun_dir.x, v.sun_dir.y, v.sun_dir.z);
    return buffer;
}

/// What a model is measured against: `height`, which has the higher orders of scattering,
/// against the `reference`; the 2002 model, which has none, against `single-scattering`.
Model truth_for(Model m) {
    return m == Model::height ? Model::reference : Model::single_scattering;
}

Worst worst_over_ground_set(Model m, const std::vector<double>& altitudes, double max_distance_m,
                            double min_sun_deg) {
    Worst worst;
    ground_level_set(altitudes, max_distance_m, min_sun_deg, [&](const View& v, dvec3 p) {
        const auto ref = aerial::evaluate(Atmosphere{}, v, truth_for(m), p);
        const auto got = aerial::evaluate(Atmosphere{}, v, m, p);
        ASSERT_TRUE(ref.ok() && got.ok());
        worst.add(*got, *ref, describe(v, p));
    });
    return worst;
}

// The 2002 model's constant sea-level density is exact only at sea level, and its single E_sun
// (at the eye) ignores that the sun's elevation changes by distance/R along the ray (0.27 deg over
// 30 km: 5 % of E_sun at a 5 deg sun). Where those hold it is within 1 %.
TEST(Accuracy, HoffmanPreethamWithinOnePercentNearSeaLevel) {
    const Worst long_rays =
        worst_over_ground_set(Model::hoffman_preetham, {0.0, 10.0}, 30000.0, 20.0);
    long_rays.print("sea level (<=10 m), rays <=30 km, sun >=20 deg", Model::hoffman_preetham);
    EXPECT_LT(long_rays.extinction, 0.01);
    EXPECT_LT(long_rays.in_scattering, 0.01) << long_rays.where_in_scattering;
    const Worst low_sun = worst_over_ground_set(Model::hoffman_preetham, {0.0, 2.0}, 5000.0, 10.0);
    low_sun.print("sea level (<=2 m), rays <=5 km, sun >=10 deg", Model::hoffman_preetham);
    EXPECT_LT(low_sun.extinction, 0.01);
    EXPECT_LT(low_sun.in_scattering, 0.01) << low_sun.where_in_scattering;
}

TEST(Accuracy, HoffmanPreethamFailsAboveSeaLevelAsTheConstantDensityImplies) {
    // Pins the known failure region: at 2 km the Mie density is exp(-2000/1200) = 19 % of the
    // sea-level value the model uses.
    const Worst w = worst_over_ground_set(Model::hoffman_preetham, {0.0, 2000.0}, 30000.0, 5.0);
    w.print("eye and target <=2 km, rays <=30 km, sun >=5", Model::hoffman_preetham);
    EXPECT_GT(w.extinction, 0.10);
    EXPECT_GT(w.in_scattering, 0.50);
}

TEST(Accuracy, HeightModelAtGroundLevel) {
    const Worst sea = worst_over_ground_set(Model::height, {0.0, 10.0}, 30000.0, 5.0);
    sea.print("sea level (<=10 m), rays <=30 km, sun >=5 deg", Model::height);
    EXPECT_LT(sea.extinction, 0.001);
    // Against the reference with every order: 1.14 % measured (its higher orders from the
    // coarser table and the slice cut at the eye; docs/models.md).
    EXPECT_LT(sea.in_scattering, 0.015) << sea.where_in_scattering;
    const Worst low = worst_over_ground_set(Model::height, {0.0, 1000.0, 2000.0}, 30000.0, 5.0);
    low.print("eye and target <=2 km, rays <=30 km, sun >=5", Model::height);
    EXPECT_LT(low.extinction, 0.001);
    // Worst case (3 %): a 5 deg sun, 30 km rays climbing or descending 2 km, where the two
    // components' share of the light changes along the ray (see docs/models.md, where each model
    // fails).
    EXPECT_LT(low.in_scattering, 0.04) << low.where_in_scattering;
}

TEST(Accuracy, FromTenKilometresLookingAtGroundFourteenKilometresAway) {
    // The case where the constant-density model is known to be off by 1.5-2.5x.
    const Atmosphere a;
    Worst height, hp;
    double hp_min_ratio = 1e9, hp_max_ratio = 0.0;
    for (double elevation : {5.0, 10.0, 20.0, 45.0, 90.0}) {
        for (double azimuth : {0.0, 45.0, 90.0, 135.0, 180.0}) {
            View v;
            v.eye = {0.0, 0.0, 10000.0};
            v.sun_dir = sun_from_degrees(elevation, azimuth);
            const dvec3 p{0.0, std::sqrt(14000.0 * 14000.0 - 10000.0 * 10000.0), 0.0};
            const auto ref = *aerial::evaluate(a, v, Model::single_scattering, p);
            height.add(*aerial::evaluate(a, v, Model::height, p),
                       *aerial::evaluate(a, v, Model::reference, p), describe(v, p));
            const auto h = *aerial::evaluate(a, v, Model::hoffman_preetham, p);
            hp.add(h, ref, describe(v, p));
            for (int c = 0; c < 3; ++c) {
                hp_min_ratio = std::min(hp_min_ratio, h.in_scattering[c] / ref.in_scattering[c]);
                hp_max_ratio = std::max(hp_max_ratio, h.in_scattering[c] / ref.in_scattering[c]);
            }
        }
    }
    height.print("eye 10 km, ground 14 km away, sun >=5 deg", Model::height);
    hp.print("eye 10 km, ground 14 km away, sun >=5 deg", Model::hoffman_preetham);
    std::printf("  hoffman-preetham L_in / reference: %.2f .. %.2f\n", hp_min_ratio, hp_max_ratio);
    EXPECT_LT(height.extinction, 0.03);
    EXPECT_LT(height.in_scattering, 0.10) << height.where_in_scattering;
    // The constant-density model overestimates everywhere here (measured 1.7x to 3.6x; the
    // largest with a 5 deg sun behind the camera).
    EXPECT_GT(hp_min_ratio, 1.5);
}

TEST(Accuracy, HeightBeatsHoffmanPreethamOnEveryPreset) {
    // Not a tolerance, an ordering: per preset, the height model's worst in-scattering error over
    // a mixed set of views is below the 2002 model's. A thin dense fog layer (`foggy`, 163 m
    // scale height) with a low sun is where the height model's 3-node sunlight quadrature errs
    // most: up to 60 % (docs/models.md: where each model fails).
    for (const auto& name : aerial::atmosphere_preset_names()) {
        const Atmosphere a = *aerial::atmosphere_preset(name);
        Worst height, hp;
        for (double eye_alt : {2.0, 300.0, 2000.0}) {
            for (double target_alt : {0.0, 500.0}) {
                for (double d : {300.0, 2000.0, 10000.0}) {
                    for (double elevation : {5.0, 30.0, 90.0}) {
                        for (double azimuth : {0.0, 90.0, 180.0}) {
                            View v;
                            v.eye = {0.0, 0.0, eye_alt};
                            v.sun_dir = sun_from_degrees(elevation, azimuth);
                            const dvec3 p = point_on_sphere(a, d, target_alt);
                            const auto ref = *aerial::evaluate(a, v, Model::reference, p);
                            height.add(*aerial::evaluate(a, v, Model::height, p), ref,
                                       describe(v, p));
                            hp.add(*aerial::evaluate(a, v, Model::hoffman_preetham, p), ref,
                                   describe(v, p));
                        }
                    }
                }
            }
        }
        const std::string table = "preset " + name + ", eye <=2 km, rays <=10 km";
        height.print(table.c_str(), Model::height);
        hp.print(table.c_str(), Model::hoffman_preetham);
        EXPECT_LT(height.in_scattering, hp.in_scattering) << name;
        EXPECT_LT(height.extinction, hp.extinction + 1e-12) << name;
    }
}

}  // namespace

namespace {

/// 8-bit steps of L_in at exposure 8 (GL's clamp) between two results, worst channel.
double lin_steps(const aerial::Scattering<double>& a, const aerial::Scattering<double>& b) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        auto code = [](double l) { return 255.0 * std::min(1.0, 8.0 * l); };
        worst = std::max(worst, std::abs(code(a.in_scattering[c]) - code(b.in_scattering[c])));
    }
    return worst;
}

}  // namespace

TEST(Accuracy, HeightWithItsHigherOrdersIsWithinTwoStepsOfTheReferenceOnTerrain) {
    // Terrain 1-30 km from an eye at 300 m, the sun from 60 deg to 6 deg below the horizon at
    // three azimuths, exposure 8: L_in of `height` against `reference` in 8-bit steps, with its
    // higher orders and without them (Frame::multiple_scattering reset).
    // Bounds: earth within 2 steps (the target); hazy a regression bound of what is measured
    // (3.1 steps at a 60 deg sun, the higher orders 1-3 % low on rays climbing through haze).
    const struct {
        const char* preset;
        double max_steps;
    } presets[] = {{"earth", 2.0}, {"hazy", 3.5}};
    for (const auto& preset : presets) {
        const Atmosphere a = *aerial::atmosphere_preset(preset.preset);
        for (double elevation : {60.0, 20.0, 5.0, 2.0, -2.0, -6.0}) {
            double with = 0.0, without = 0.0;
            for (double azimuth : {0.0, 90.0, 180.0}) {
                View v;
                v.eye = {0.0, 0.0, 300.0};
                v.sun_dir = sun_from_degrees(elevation, azimuth);
                const auto height = *aerial::prepare_frame<double>(a, v, Model::height);
                auto single = height;
                single.multiple_scattering.reset();
                const auto reference = *aerial::prepare_frame<double>(a, v, Model::reference);
                for (double d : {1000.0, 3000.0, 10000.0, 30000.0}) {
                    for (double view_azimuth : {0.0, 45.0, 90.0, 180.0}) {
                        const double t = view_azimuth * aerial::kPi / 180.0;
                        const dvec3 on_ground = point_on_sphere(a, d, 0.0);
                        const dvec3 p(on_ground.y * std::sin(t), on_ground.y * std::cos(t),
                                      on_ground.z);
                        const auto ref = aerial::scatter(reference, p);
                        with = std::max(with, lin_steps(aerial::scatter(height, p), ref));
                        without = std::max(without, lin_steps(aerial::scatter(single, p), ref));
                    }
                }
            }
            std::printf("| %-6s | %5.1f deg | %5.1f | %5.1f |\n", preset.preset, elevation, with,
                        without);
            EXPECT_LE(with, preset.max_steps) << preset.preset << " sun " << elevation;
            EXPECT_LT(with, without + 0.5) << preset.preset << " sun " << elevation;
        }
    }
}

/// RMSE and largest error, in 8-bit steps of the display (exposure, then clamped as GL does).
struct DisplayError {
    double sum_squares = 0.0, max = 0.0;
    long count = 0;
    void add(double got, double want, double exposure) {
        const auto code = [&](double v) { return 255.0 * std::clamp(v * exposure, 0.0, 1.0); };
        const double e = code(got) - code(want);
        sum_squares += e * e;
        max = std::max(max, std::abs(e));
        ++count;
    }
    double rmse() const { return count ? std::sqrt(sum_squares / double(count)) : 0.0; }
};

TEST(Accuracy, TwilightSkyAndTerrainAgainstTheReference) {
    // The sun from 10 deg above to 6 deg below the horizon, the eye at 300 m, the sample game's
    // exposure (its grey card with the key raised to 0.8, at most 3.5 times a zenith sun's, and
    // after sunset following the skylight down): the sky as engines draw it (height_chained) in
    // 10 x 24 directions to the atmosphere's top, and a 16 km terrain (13 x 13 points, grey,
    // lit by the sun and the skylight), against the reference with every order.
    // Target 2 steps RMSE. Bounds: the terrain within it everywhere; two regression bounds of
    // what is measured on the sky: `earth` with the sun 4-6 deg down (2.95 and 2.85: on horizon
    // rays of hundreds of kilometres the shape, cut with the eye's sun, and level's 3.5 deg sun
    // rows) and `hazy` at a 10 deg sun (2.11: the forward lobe near the horizon).
    // At AERIAL_TEST_SCALE below 1 (the sanitizer stage) `earth` only.
    aerial::ReferenceOptions every_order;
    every_order.multiple_scattering = true;
    std::printf("| preset | sun | exposure | sky RMSE (max) | terrain RMSE (max) |\n");
    const std::vector<std::string> presets = aerial::testing::test_scale() < 1.0
                                                 ? std::vector<std::string>{"earth"}
                                                 : std::vector<std::string>{"earth", "hazy"};
    for (const std::string& name : presets) {
        const char* preset = name.c_str();
        const Atmosphere a = *aerial::atmosphere_preset(preset);
        const double h = 300.0;
        const auto skylight_at_sunset = *aerial::sky_ambient(a, h, 0.0);
        for (double elevation : {10.0, 5.0, 2.0, 0.0, -2.0, -4.0, -6.0}) {
            const double e = elevation * aerial::kPi / 180.0;
            View v;
            v.eye = {0.0, 0.0, h};
            v.sun_dir = sun_from_degrees(elevation, 0.0);
            const auto skylight = *aerial::sky_ambient(a, h, e);
            aerial::ExposureOptions options;
            options.key = 0.8;
            options.max_gain = 3.5;
            double exposure = aerial::auto_exposure(aerial::sun_irradiance_at_altitude(a, h, e), e,
                                                    skylight, a.sun_irradiance, options);
            if (e < 0.0) {
                exposure *= std::max(
                    1.0, aerial::luminance(skylight_at_sunset) / aerial::luminance(skylight));
            }
            const auto sky = *aerial::prepare_sky(a, v, aerial::SkyMethod::height_chained);
            DisplayError sky_error, terrain_error;
            const double r0 = a.planet_radius_m + h, top = a.atmosphere_radius_m;
            for (int i = 0; i < 10; ++i) {
                for (int j = 0; j < 24; ++j) {
                    const double up = (i == 0 ? 0.5 : 9.0 * i) * aerial::kPi / 180.0;
                    const double around = 15.0 * j * aerial::kPi / 180.0;
                    const dvec3 d(std::cos(up) * std::cos(around), std::cos(up) * std::sin(around),
                                  std::sin(up));
                    const double b = r0 * d.z;
                    const double length = -b + std::sqrt(b * b - (r0 * r0 - top * top));
                    const dvec3 got = aerial::sky_radiance(sky, d);
                    const auto want =
                        aerial::reference_scattering(a, v, v.eye + d * length, every_order);
                    for (int c = 0; c < 3; ++c)
                        sky_error.add(got[c], want.in_scattering[c], exposure);
                }
            }
            const auto height = *aerial::prepare_frame<double>(a, v, Model::height);
            const double albedo = 0.3 / aerial::kPi;
            for (int i = 0; i < 13; ++i) {
                for (int j = 0; j < 13; ++j) {
                    const dvec3 p(-8000.0 + i * 16000.0 / 12.0, -8000.0 + j * 16000.0 / 12.0,
                                  150.0 + 150.0 * std::sin(0.7 * i) * std::cos(0.5 * j));
                    const auto got = aerial::scatter(height, p);
                    const auto want = aerial::reference_scattering(a, v, p, every_order);
                    for (int c = 0; c < 3; ++c) {
                        const auto lit = [&](const aerial::Scattering<double>& s) {
                            const double light =
                                s.sun_irradiance[c] * std::max(0.0, std::sin(e)) + skylight[c];
                            return albedo * light * s.extinction[c] + s.in_scattering[c];
                        };
                        terrain_error.add(lit(got), lit(want), exposure);
                    }
                }
            }
            std::printf("| %-6s | %5.1f deg | %7.1f | %4.2f (%4.1f) | %4.2f (%4.1f) |\n", preset,
                        elevation, exposure, sky_error.rmse(), sky_error.max, terrain_error.rmse(),
                        terrain_error.max);
            const double sky_bound = name == "earth" && elevation <= -4.0  ? 3.1
                                     : name == "hazy" && elevation == 10.0 ? 2.2
                                                                           : 2.0;
            EXPECT_LE(sky_error.rmse(), sky_bound) << preset << " sun " << elevation;
            EXPECT_LE(terrain_error.rmse(), 2.0) << preset << " sun " << elevation;
        }
    }
}
