// The shading cache: the bound on the change of the 8-bit outputs is never exceeded (randomised
// meshes, presets, models and moves), is tight enough to skip typical frames, is infinite when
// anything but eye and sun changed; mesh_bounds skips NaN and reads AoS with stride and SoA.
// Prints the tightness (bound / actual) and the largest moves that still skip, for the notes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"

namespace {

using aerial::Model;
using aerial::ShadingKey;
using glm::dvec3;

constexpr double kInf = std::numeric_limits<double>::infinity();
/// The actual change is measured through display_value/to_unorm8's float arithmetic: rounding a
/// value to float and back moves it by up to 2^-24 relative, 1.5e-5 steps of 8 bits.
constexpr double kFloatNoiseLsb = 1e-4;
/// Changes this large are well above that noise: tightness ratios are taken over them.
constexpr double kMeasurableLsb = 0.01;

struct Mesh {
    std::vector<float> xyz;      ///< engine units, packed
    std::vector<float> normals;  ///< unit, packed
    std::size_t size() const { return xyz.size() / 3; }
    aerial::Positions positions() const { return aerial::Positions::aos(xyz.data(), size()); }
};

dvec3 random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> n;
    for (;;) {
        const dvec3 v(n(rng), n(rng), n(rng));
        if (glm::length(v) > 1e-6) return glm::normalize(v);
    }
}

double uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}
double log_uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::exp(uniform(rng, std::log(lo), std::log(hi)));
}

void add_vertex(Mesh& mesh, const dvec3& p_m, double mpu, std::mt19937_64& rng) {
    for (int k = 0; k < 3; ++k) mesh.xyz.push_back(float(p_m[k] / mpu));
    const dvec3 n = random_unit(rng);
    for (int k = 0; k < 3; ++k) mesh.normals.push_back(float(n[k]));
}

/// Points in a ball (metres in, engine units stored), a few on its surface.
Mesh vertex_cloud(std::mt19937_64& rng, const dvec3& centre_m, double radius_m, int n, double mpu) {
    Mesh mesh;
    for (int i = 0; i < n; ++i) {
        const double r = i % 4 == 0 ? radius_m : radius_m * std::cbrt(uniform(rng, 0.0, 1.0));
        add_vertex(mesh, centre_m + random_unit(rng) * r, mpu, rng);
    }
    return mesh;
}

/// A square height field of side `size_m` around `centre_m` (its z is the base height), with
/// ridges of amplitude `relief_m`; z is along `up` = +Z.
Mesh terrain(std::mt19937_64& rng, const dvec3& centre_m, double size_m, double relief_m, int n,
             double mpu) {
    Mesh mesh;
    const double fx = uniform(rng, 1.0, 4.0), fy = uniform(rng, 1.0, 4.0);
    const double px = uniform(rng, 0.0, 6.3), py = uniform(rng, 0.0, 6.3);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double u = double(i) / (n - 1) - 0.5, v = double(j) / (n - 1) - 0.5;
            const double z = relief_m * 0.5 *
                             (1.0 + std::sin(fx * 6.283 * u + px) * std::cos(fy * 6.283 * v + py));
            add_vertex(mesh, centre_m + dvec3(u * size_m, v * size_m, z), mpu, rng);
        }
    }
    return mesh;
}

/// The three 8-bit outputs of every vertex before rounding (value x 255), 9 per vertex.
std::vector<double> shade_unrounded(const ShadingKey& key, const Mesh& mesh) {
    const auto frame = aerial::prepare_frame<double>(key.atmosphere, key.view, key.model);
    EXPECT_TRUE(frame.ok());
    std::vector<double> out;
    out.reserve(mesh.size() * 9);
    const dvec3 sun = frame->view.sun_dir;
    for (std::size_t v = 0; v < mesh.size(); ++v) {
        const dvec3 p(mesh.xyz[3 * v], mesh.xyz[3 * v + 1], mesh.xyz[3 * v + 2]);
        const dvec3 n(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]);
        const auto s = aerial::scatter(*frame, p);
        const double n_dot_l = std::max(glm::dot(n, sun), 0.0);
        for (int c = 0; c < 3; ++c) {
            const double lit = double(key.albedo[c]) * s.extinction[c] *
                               (s.sun_irradiance[c] * n_dot_l + double(key.ambient[c]));
            const float f = float(s.extinction[c]);
            out.push_back(255.0 * double(f > 0.0f ? (f < 1.0f ? f : 1.0f) : 0.0f));
            out.push_back(255.0 *
                          double(aerial::display_value(key.display, float(s.in_scattering[c]))));
            out.push_back(255.0 * double(aerial::display_value(key.display, float(lit))));
        }
    }
    return out;
}

double actual_change_lsb(const ShadingKey& a, const ShadingKey& b, const Mesh& mesh) {
    const std::vector<double> x = shade_unrounded(a, mesh), y = shade_unrounded(b, mesh);
    double worst = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(y[i] - x[i]));
    return worst;
}

/// sun turned by `angle` about a random axis perpendicular to it.
dvec3 turn(const dvec3& sun, double angle, std::mt19937_64& rng) {
    const dvec3 axis = glm::normalize(glm::cross(sun, random_unit(rng)));
    return glm::normalize(sun * std::cos(angle) + glm::cross(axis, sun) * std::sin(angle));
}

dvec3 sun_at(double elevation_rad, double azimuth_rad) {
    return dvec3(std::cos(elevation_rad) * std::sin(azimuth_rad),
                 std::cos(elevation_rad) * std::cos(azimuth_rad), std::sin(elevation_rad));
}

aerial::Atmosphere preset(const std::string& name) { return *aerial::atmosphere_preset(name); }

struct Stats {
    std::vector<double> ratios;  ///< bound / actual where both are meaningful
    void add(double bound, double actual) {
        if (std::isfinite(bound) && actual > kMeasurableLsb) ratios.push_back(bound / actual);
    }
    double quantile(double q) {
        if (ratios.empty()) return std::nan("");
        std::sort(ratios.begin(), ratios.end());
        return ratios[std::min(ratios.size() - 1, std::size_t(q * double(ratios.size())))];
    }
};

// ---- (1) soundness ----------------------------------------------------------------------------

TEST(ShadingCache, BoundIsNeverExceededForRandomMeshesAtmospheresAndMoves) {
    std::mt19937_64 rng(20240611);
    const auto& presets = aerial::atmosphere_preset_names();
    const double mpus[3] = {1.0, 0.01, 2.5};
    int trials = 0, finite = 0, skipped = 0, failures = 0;
    double closest = 0.0;  // largest actual / bound
    std::string closest_case;
    Stats stats[2];
    for (int trial = 0; trial < 6000; ++trial) {
        const Model model = trial % 2 ? Model::height : Model::hoffman_preetham;
        const std::string& atmosphere = presets[std::size_t(trial / 2) % presets.size()];
        const double mpu = mpus[std::size_t(trial / 10) % 3];
        ShadingKey a;
        a.atmosphere = preset(atmosphere);
        a.model = model;
        a.view.meters_per_unit = mpu;
        const double eye_altitude = log_uniform(rng, 1.0, 3000.0);
        const dvec3 eye_m(uniform(rng, -2000, 2000), uniform(rng, -2000, 2000), eye_altitude);
        a.view.eye = eye_m / mpu;
        // The sun anywhere from just below the horizon to near the zenith; every tenth scene with
        // a low sun, where the sun's transmittance changes fastest.
        const double elevation =
            trial % 10 == 7 ? log_uniform(rng, 1e-3, 0.1) : uniform(rng, -0.1, 1.5);
        a.view.sun_dir = sun_at(elevation, uniform(rng, 0.0, 6.3));
        a.display.exposure = float(log_uniform(rng, 1.0, 50.0));
        a.display.tone = trial % 3 ? aerial::ToneCurve::clamp : aerial::ToneCurve::exponential;
        for (int c = 0; c < 3; ++c) {
            a.ambient[c] = float(uniform(rng, 0.0, 0.3));
            a.albedo[c] = float(uniform(rng, 0.2, 1.0));
        }

        // A mesh 10 m .. 50 km away, sometimes around the eye.
        const double distance = log_uniform(rng, 10.0, 50000.0);
        const double heading = uniform(rng, 0.0, 6.3);
        const dvec3 direction(std::sin(heading), std::cos(heading), 0.0);
        Mesh mesh;
        if (trial % 4 < 2) {
            const double radius = distance * uniform(rng, 0.01, trial % 8 == 0 ? 1.5 : 0.8);
            dvec3 centre = eye_m + direction * distance;
            centre.z = std::max(radius, eye_altitude * uniform(rng, 0.0, 2.0));
            mesh = vertex_cloud(rng, centre, radius, 120, mpu);
        } else {
            const double size = distance * uniform(rng, 0.1, trial % 8 == 2 ? 3.0 : 1.5);
            const dvec3 centre(eye_m.x + direction.x * distance, eye_m.y + direction.y * distance,
                               uniform(rng, 0.0, 300.0));
            mesh = terrain(rng, centre, size, std::min(0.1 * size, 2000.0) * uniform(rng, 0, 1), 12,
                           mpu);
        }
        aerial::MeshBounds bounds = aerial::mesh_bounds(mesh.positions());

        // A small move: eye by 1 mm .. 100 m (random, vertical, or towards the mesh), sun by
        // 1e-6 .. 0.05 rad; sometimes only one of them.
        ShadingKey b = a;
        const double move = log_uniform(rng, 1e-3, 100.0);
        const int kind = int(rng() % 4);
        const dvec3 towards = glm::normalize(bounds.centre * mpu - eye_m);
        const dvec3 move_dir = kind == 0 ? dvec3(0, 0, 1) : kind == 1 ? towards : random_unit(rng);
        if (trial % 5 != 4) b.view.eye = (eye_m + move_dir * move) / mpu;
        if (trial % 5 != 3)
            b.view.sun_dir = turn(a.view.sun_dir, log_uniform(rng, 1e-6, 0.05), rng);

        // Every third scene in a +Y-up world (the same scene turned: x, y, z -> x, z, -y).
        if (trial % 3 == 1) {
            auto turn_world = [](const dvec3& v) { return dvec3(v.x, v.z, -v.y); };
            for (ShadingKey* k : {&a, &b}) {
                k->view.eye = turn_world(k->view.eye);
                k->view.sun_dir = turn_world(k->view.sun_dir);
                k->view.up = turn_world(k->view.up);
            }
            for (std::vector<float>* v : {&mesh.xyz, &mesh.normals}) {
                for (std::size_t i = 0; i < v->size(); i += 3) {
                    const float y = (*v)[i + 1];
                    (*v)[i + 1] = (*v)[i + 2];
                    (*v)[i + 2] = -y;
                }
            }
            bounds = aerial::mesh_bounds(mesh.positions());
        }

        const double bound = aerial::max_change_lsb(a, b, bounds);
        const double actual = actual_change_lsb(a, b, mesh);
        ++trials;
        if (std::isfinite(bound)) ++finite;
        if (bound < aerial::kSkipBelowLsb) ++skipped;
        stats[model == Model::height].add(bound, actual);
        char description[256];
        std::snprintf(description, sizeof description,
                      "%s %s, mesh %g m away (r=%g m), eye move %g m, sun turn %g rad, "
                      "sun elevation %.3f rad",
                      atmosphere.c_str(), std::string(aerial::model_name(model)).c_str(), distance,
                      bounds.radius * mpu, move,
                      std::atan2(glm::length(glm::cross(a.view.sun_dir, b.view.sun_dir)),
                                 glm::dot(a.view.sun_dir, b.view.sun_dir)),
                      std::asin(glm::dot(a.view.sun_dir, a.view.up)));
        if (actual > bound + kFloatNoiseLsb) {
            ADD_FAILURE() << "the cache's bound is exceeded (" << actual << " > " << bound
                          << " steps): " << description;
            if (++failures == 10) break;
        }
        if (std::isfinite(bound) && actual > kMeasurableLsb && actual / bound > closest) {
            closest = actual / bound;
            closest_case = description;
        }
    }
    std::printf("soundness: %d trials, bound finite in %d, below 0.5 LSB in %d\n", trials, finite,
                skipped);
    std::printf("  largest actual/bound %.3f (%s)\n", closest, closest_case.c_str());
    const char* names[2] = {"hoffman-preetham", "height"};
    for (int m = 0; m < 2; ++m) {
        std::printf("  %-16s bound/actual: min %.2f, median %.1f, 90%% %.1f (%zu cases)\n",
                    names[m], stats[m].quantile(0.0), stats[m].quantile(0.5),
                    stats[m].quantile(0.9), stats[m].ratios.size());
    }
}

// ---- (2) usefulness ---------------------------------------------------------------------------

/// A typical scene: eye a few hundred metres up, terrain 1 .. 20 km ahead.
struct Scene {
    ShadingKey key;
    Mesh mesh;
    aerial::MeshBounds bounds;
};

Scene typical_scene(const std::string& atmosphere, Model model, double sun_elevation_rad,
                    double eye_altitude_m, std::mt19937_64& rng) {
    Scene scene;
    scene.key.atmosphere = preset(atmosphere);
    scene.key.model = model;
    scene.key.view.eye = dvec3(0, 0, eye_altitude_m);
    scene.key.view.sun_dir = sun_at(sun_elevation_rad, 0.7);
    scene.key.display.exposure = 20.0f;
    scene.key.ambient = glm::vec3(0.1f);
    scene.key.albedo = glm::vec3(0.6f);
    // Terrain 1 .. 20 km ahead along +Y, 20 km wide, 300 m of relief.
    const int n = 24;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double x = (double(i) / (n - 1) - 0.5) * 20000.0;
            const double y = 1000.0 + double(j) / (n - 1) * 19000.0;
            const double z = 150.0 * (1.0 + std::sin(x * 7e-4) * std::cos(y * 5e-4));
            add_vertex(scene.mesh, dvec3(x, y, z), 1.0, rng);
        }
    }
    scene.bounds = aerial::mesh_bounds(scene.mesh.positions());
    return scene;
}

ShadingKey moved(const ShadingKey& key, const dvec3& eye_move_m, double sun_turn_rad) {
    ShadingKey b = key;
    b.view.eye += eye_move_m / key.view.meters_per_unit;
    // Turn the sun in its vertical plane (its elevation changes, the hardest direction for E_sun).
    const double elevation = std::asin(key.view.sun_dir.z) + sun_turn_rad;
    const double azimuth = std::atan2(key.view.sun_dir.x, key.view.sun_dir.y);
    b.view.sun_dir = sun_at(elevation, azimuth);
    return b;
}

TEST(ShadingCache, TypicalFrameToFrameMovesNeedNoUpdate) {
    std::mt19937_64 rng(7);
    Stats stats;
    for (const char* atmosphere : {"earth", "hp2002", "hazy", "foggy", "mars"}) {
        for (Model model : {Model::hoffman_preetham, Model::height}) {
            for (double elevation : {0.1, 0.3, 0.8, 1.4}) {
                const Scene scene = typical_scene(atmosphere, model, elevation, 300.0, rng);
                aerial::ShadingCache cache;
                cache.bounds = scene.bounds;
                EXPECT_TRUE(cache.needs_update(scene.key)) << "never shaded";
                cache.mark_shaded(scene.key);
                EXPECT_FALSE(cache.needs_update(scene.key)) << "same key";
                const ShadingKey next = moved(scene.key, dvec3(0.006, 0.008, 0.0), 1e-5);
                const double bound = aerial::max_change_lsb(scene.key, next, scene.bounds);
                const double actual = actual_change_lsb(scene.key, next, scene.mesh);
                stats.add(bound, actual);
                // In fog the bound of the higher orders (the shape's slopes over its table, which
                // changes fast over the fog layer's altitudes) is loose, so those frames are
                // shaded again (docs/models.md, "When shading can be skipped").
                const bool loose = model == Model::height && std::string(atmosphere) == "foggy";
                if (loose) {
                    std::printf("foggy height, sun elevation %.1f rad: bound %.2f steps\n",
                                elevation, bound);
                    EXPECT_LE(actual, bound + kFloatNoiseLsb);
                    continue;
                }
                EXPECT_FALSE(cache.needs_update(next))
                    << atmosphere << " " << aerial::model_name(model) << " sun elevation "
                    << elevation << ": bound " << bound << " steps for 1 cm and 1e-5 rad";
                EXPECT_LE(actual, bound + kFloatNoiseLsb);
            }
        }
    }
    std::printf("typical frame (1 cm, 1e-5 rad): bound/actual min %.2f, median %.1f, max %.1f\n",
                stats.quantile(0.0), stats.quantile(0.5), stats.quantile(1.0));
}

/// Largest x in [lo, hi] (log bisection) for which change(x) < 0.5.
template <class F>
double largest_skip(F change, double lo, double hi) {
    if (!(change(lo) < aerial::kSkipBelowLsb)) return 0.0;
    if (change(hi) < aerial::kSkipBelowLsb) return hi;
    for (int i = 0; i < 40; ++i) {
        const double mid = std::sqrt(lo * hi);
        (change(mid) < aerial::kSkipBelowLsb ? lo : hi) = mid;
    }
    return lo;
}

TEST(ShadingCache, LargestMovesThatStillSkip) {
    std::mt19937_64 rng(11);
    std::printf("largest move that still skips: bound says / a true change of 0.5 LSB needs\n");
    std::printf("  %-8s %-16s %-9s %-21s %-21s %-21s\n", "preset", "model", "sun elev",
                "eye sideways (m)", "eye up (m)", "sun (rad)");
    for (const char* atmosphere : {"earth", "hazy", "foggy"}) {
        for (Model model : {Model::hoffman_preetham, Model::height}) {
            for (double elevation : {0.1, 0.8}) {
                const Scene scene = typical_scene(atmosphere, model, elevation, 300.0, rng);
                auto bound = [&](const ShadingKey& b) {
                    return aerial::max_change_lsb(scene.key, b, scene.bounds);
                };
                auto actual = [&](const ShadingKey& b) {
                    return actual_change_lsb(scene.key, b, scene.mesh);
                };
                const dvec3 side(1, 0, 0), up(0, 0, 1);
                auto side_move = [&](double m) { return moved(scene.key, side * m, 0.0); };
                auto up_move = [&](double m) { return moved(scene.key, up * m, 0.0); };
                auto sun_move = [&](double r) { return moved(scene.key, dvec3(0.0), r); };
                // The largest move in [lo, hi] the bound lets skip, and the one the truth does.
                auto skips = [&](auto move, double lo, double hi) {
                    return std::make_pair(
                        largest_skip([&](double x) { return bound(move(x)); }, lo, hi),
                        largest_skip([&](double x) { return actual(move(x)); }, lo, hi));
                };
                const auto [side_bound, side_true] = skips(side_move, 1e-4, 1e4);
                const auto [up_bound, up_true] = skips(up_move, 1e-4, 1e4);
                const auto [sun_bound, sun_true] = skips(sun_move, 1e-8, 0.1);
                std::printf("  %-8s %-16s %-9.2f %9.3g / %-9.3g %9.3g / %-9.3g %9.2g / %-9.2g\n",
                            atmosphere, std::string(aerial::model_name(model)).c_str(), elevation,
                            side_bound, side_true, up_bound, up_true, sun_bound, sun_true);
                EXPECT_LE(side_bound, side_true * 1.0001);
                EXPECT_LE(up_bound, up_true * 1.0001);
                EXPECT_LE(sun_bound, sun_true * 1.0001);
            }
        }
    }
}

// ---- (3) anything but eye and sun ---------------------------------------------------------------

TEST(ShadingCache, AnyChangeButEyeAndSunIsInfinite) {
    ShadingKey a;
    a.view.eye = dvec3(0, 0, 100);
    a.view.sun_dir = sun_at(0.5, 0.3);
    const aerial::MeshBounds bounds{dvec3(0, 5000, 0), 1000.0};
    std::vector<std::pair<const char*, ShadingKey>> changed;
    auto with = [&](const char* what, auto edit) {
        ShadingKey b = a;
        edit(b);
        changed.emplace_back(what, b);
    };
    with("rayleigh_scattering", [](ShadingKey& k) { k.atmosphere.rayleigh_scattering.y *= 1.01; });
    with("mie_scattering", [](ShadingKey& k) { k.atmosphere.mie_scattering.x *= 1.01; });
    with("mie_absorption", [](ShadingKey& k) { k.atmosphere.mie_absorption.z = 1e-7; });
    with("mie_g", [](ShadingKey& k) { k.atmosphere.mie_g = 0.79; });
    with("rayleigh_scale_height_m",
         [](ShadingKey& k) { k.atmosphere.rayleigh_scale_height_m = 8001; });
    with("mie_scale_height_m", [](ShadingKey& k) { k.atmosphere.mie_scale_height_m = 1201; });
    with("planet_radius_m", [](ShadingKey& k) { k.atmosphere.planet_radius_m += 1.0; });
    with("atmosphere_radius_m", [](ShadingKey& k) { k.atmosphere.atmosphere_radius_m += 1.0; });
    with("sun_irradiance", [](ShadingKey& k) { k.atmosphere.sun_irradiance.x = 1.01; });
    with("model", [](ShadingKey& k) { k.model = Model::hoffman_preetham; });
    with("display.exposure", [](ShadingKey& k) { k.display.exposure = 1.01f; });
    with("display.tone", [](ShadingKey& k) { k.display.tone = aerial::ToneCurve::exponential; });
    with("ambient", [](ShadingKey& k) { k.ambient.y = 0.01f; });
    with("albedo", [](ShadingKey& k) { k.albedo.z = 0.99f; });
    with("view.up", [](ShadingKey& k) { k.view.up = glm::normalize(dvec3(0, 1e-3, 1)); });
    with("view.meters_per_unit", [](ShadingKey& k) { k.view.meters_per_unit = 1.0001; });
    for (const auto& [what, b] : changed) {
        EXPECT_EQ(aerial::max_change_lsb(a, b, bounds), kInf) << what;
        EXPECT_EQ(aerial::max_change_lsb(b, a, bounds), kInf) << what;
        aerial::ShadingCache cache;
        cache.bounds = bounds;
        cache.mark_shaded(a);
        EXPECT_TRUE(cache.needs_update(b)) << what;
    }
    // The same key never changes anything, whatever the model; eye and sun moves are finite.
    for (Model m : aerial::all_models()) {
        ShadingKey k = a;
        k.model = m;
        EXPECT_EQ(aerial::max_change_lsb(k, k, bounds), 0.0) << aerial::model_name(m);
    }
    EXPECT_LT(aerial::max_change_lsb(a, moved(a, dvec3(0.01, 0, 0), 1e-5), bounds), 0.5);
}

TEST(ShadingCache, WhatCannotBeBoundedIsInfinite) {
    ShadingKey a;
    a.view.eye = dvec3(0, 0, 100);
    a.view.sun_dir = sun_at(0.5, 0.3);
    const aerial::MeshBounds bounds{dvec3(0, 5000, 0), 1000.0};
    const ShadingKey b = moved(a, dvec3(0.01, 0, 0), 1e-5);
    // The reference model: no bound is derived for it.
    ShadingKey ra = a, rb = b;
    ra.model = rb.model = Model::reference;
    EXPECT_EQ(aerial::max_change_lsb(ra, rb, bounds), kInf);
    // The height model with the sun at the horizon of part of the mesh: the model's sun switches
    // off in a step there. The sun is 0.03 deg up at the eye, set 5 km behind it (the zenith
    // turns by 5 km / 6360 km = 0.045 deg).
    ShadingKey la = a;
    la.view.sun_dir = sun_at(0.0005, 0.0);
    const aerial::MeshBounds behind{dvec3(0, -5000, 0), 1000.0};
    EXPECT_EQ(aerial::max_change_lsb(la, moved(la, dvec3(0.01, 0, 0), 1e-5), behind), kInf);
    EXPECT_LT(aerial::max_change_lsb(la, moved(la, dvec3(0.01, 0, 0), 1e-5), bounds), kInf);
    ShadingKey lh = la;
    lh.model = Model::hoffman_preetham;  // E_sun at the eye is exact: finite
    EXPECT_LT(aerial::max_change_lsb(lh, moved(lh, dvec3(0.01, 0, 0), 1e-5), behind), kInf);
    // Invalid keys.
    ShadingKey bad = b;
    bad.view.sun_dir = dvec3(0, 0, 2);
    EXPECT_EQ(aerial::max_change_lsb(a, bad, bounds), kInf);
    bad = b;
    bad.display.exposure = 0.0f;
    EXPECT_FALSE(aerial::prepare_shading_key(bad).ok());
    // Meshes reaching kMaxDistanceM, and NaN bounds.
    EXPECT_EQ(aerial::max_change_lsb(a, b, {dvec3(0, 0, 0), 2e12}), kInf);
    EXPECT_EQ(aerial::max_change_lsb(a, b, {dvec3(0, std::nan(""), 0), 1.0}), kInf);
    // An empty mesh has nothing to change.
    EXPECT_EQ(aerial::max_change_lsb(a, b, {dvec3(0.0), -1.0}), 0.0);
    // The eye inside the mesh, the vertex at the eye: still finite (the phase term carries s).
    EXPECT_LT(aerial::max_change_lsb(a, b, {a.view.eye, 100.0}), kInf);
}

TEST(ShadingCache, CacheFollowsTheBound) {
    std::mt19937_64 rng(3);
    const Scene scene = typical_scene("earth", Model::height, 0.5, 300.0, rng);
    aerial::ShadingCache cache;
    cache.bounds = scene.bounds;
    const auto now = aerial::prepare_shading_key(scene.key);
    ASSERT_TRUE(now.ok());
    EXPECT_TRUE(cache.needs_update(*now));
    cache.mark_shaded(*now);
    EXPECT_FALSE(cache.needs_update(*now));
    const auto near = aerial::prepare_shading_key(moved(scene.key, dvec3(0.01, 0, 0), 0.0));
    const auto far = aerial::prepare_shading_key(moved(scene.key, dvec3(500, 0, 0), 0.0));
    EXPECT_FALSE(cache.needs_update(*near));
    EXPECT_TRUE(cache.needs_update(*far));
    cache.invalidate();
    EXPECT_TRUE(cache.needs_update(*now));
    // An invalid key recorded as shaded forces a re-shade.
    ShadingKey bad = scene.key;
    bad.view.up = dvec3(0.0);
    cache.mark_shaded(bad);
    EXPECT_FALSE(cache.shaded_with.has_value());
    EXPECT_TRUE(cache.needs_update(scene.key));
}

// ---- (4) mesh_bounds --------------------------------------------------------------------------

TEST(MeshBounds, SkipsNonFiniteVerticesAndReadsAosWithStrideAndSoa) {
    const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
    // AoS records of 5 floats: x, y, z, u, v.
    const std::vector<float> records = {
        -1,  0,   0,  9, 9,  //
        3,   0,   0,  9, 9,  //
        nan, 100, 0,  9, 9,  //
        1,   2,   -2, 9, 9,  //
        0,   inf, 0,  9, 9,  //
    };
    const auto aos =
        aerial::mesh_bounds(aerial::Positions::aos(records.data(), 5, 5 * sizeof(float)));
    EXPECT_EQ(aos.centre, dvec3(1, 1, -1));
    EXPECT_EQ(aos.box_min, dvec3(-1, 0, -2));
    EXPECT_EQ(aos.box_max, dvec3(3, 2, 0));
    EXPECT_NEAR(aos.radius, std::sqrt(6.0), 1e-9);  // corners (-1,0,0) and (3,0,0): sqrt(4+1+1)
    const std::vector<float> x = {-1, 3, nan, 1, 0}, y = {0, 0, 100, 2, inf}, z = {0, 0, 0, -2, 0};
    const auto soa = aerial::mesh_bounds(aerial::Positions::soa(x.data(), y.data(), z.data(), 5));
    EXPECT_EQ(soa.centre, aos.centre);
    EXPECT_EQ(soa.radius, aos.radius);
    EXPECT_EQ(soa.box_min, aos.box_min);
    EXPECT_EQ(soa.box_max, aos.box_max);
    // Every finite vertex is inside.
    for (std::size_t i = 0; i < 5; ++i) {
        const dvec3 p(x[i], y[i], z[i]);
        if (std::isfinite(p.x) && std::isfinite(p.y)) {
            EXPECT_LE(glm::length(p - soa.centre), soa.radius);
        }
    }
    // No finite vertex, or no vertex at all: negative radius.
    const std::vector<float> all_nan = {nan, 0, 0, 0, nan, 0};
    EXPECT_LT(aerial::mesh_bounds(aerial::Positions::aos(all_nan.data(), 2)).radius, 0.0);
    EXPECT_LT(aerial::mesh_bounds(aerial::Positions::aos(nullptr, 0)).radius, 0.0);
    // Arrays shade_into would reject: never skipped.
    EXPECT_EQ(aerial::mesh_bounds(aerial::Positions::aos(nullptr, 3)).radius, kInf);
    aerial::Positions zero_stride = aerial::Positions::aos(records.data(), 2);
    zero_stride.stride_bytes = 0;
    EXPECT_EQ(aerial::mesh_bounds(zero_stride).radius, kInf);
}

TEST(ShadingCache, PreparedAndUnpreparedChecksAgree) {
    // The per-frame check takes a key prepared once per frame; it must decide exactly as the
    // check that prepares the key itself, for moves on both sides of the bound.
    std::mt19937_64 rng(5);
    const Scene scene = typical_scene("earth", Model::height, 0.5, 300.0, rng);
    aerial::ShadingCache cache;
    cache.bounds = scene.bounds;
    cache.mark_shaded(scene.key);
    std::uniform_real_distribution<double> step(-20.0, 20.0), turn(-2e-3, 2e-3);
    int updates = 0;
    const int n = 400;
    for (int i = 0; i < n; ++i) {
        const double scale = std::pow(10.0, -3.0 + 5.0 * i / n);  // 1 mm .. 100 m
        const ShadingKey key =
            moved(scene.key, scale * dvec3(step(rng), step(rng), 0.1 * step(rng)), turn(rng));
        const auto prepared = aerial::prepare_shading_key(key);
        ASSERT_TRUE(prepared.ok());
        const bool fast = cache.needs_update(*prepared);
        ASSERT_EQ(fast, cache.needs_update(key)) << "move " << i << " (scale " << scale << " m)";
        ASSERT_EQ(fast, !(aerial::max_change_lsb(*cache.shaded_with, *prepared, cache.bounds) <
                          aerial::kSkipBelowLsb));
        updates += fast;
    }
    // The sweep crosses the bound: some moves skip, some do not.
    EXPECT_GT(updates, 0);
    EXPECT_LT(updates, n);
}

}  // namespace
