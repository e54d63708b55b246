// The one-pass RGBA8 path for the height model and the lit colour (F_ex x (E_sun max(N.L, 0) +
// ambient) x albedo): its codes are the 8-bit rule applied to the float path's values, bit for
// bit, on every SIMD target, layout, output set and thread count; and the lit codes of both
// models are within half a step (plus the float noise measured here) of the double model.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/batch.hpp"
#include "extreme_sampler.hpp"
#include "forced_target.hpp"
#include "split_batch.hpp"

namespace {

using aerial::Kernel;
using aerial::Model;
using aerial::testing::ExtremeSampler;
using aerial::testing::ForcedTarget;

struct Vertex {
    float position[3];
    float normal[3];
};

/// One frame, its vertices (position and normal in one record), lighting and exposure.
struct Scene {
    aerial::Frame<float> frame;
    std::vector<Vertex> v;
    aerial::Lighting lighting;
    float exposure = 1.0f;
};

bool make_scene(ExtremeSampler& random, Model model, std::size_t points, Scene* out) {
    const aerial::Atmosphere a = random.atmosphere();
    const aerial::View view = random.view(a);
    const auto frame = aerial::testing::extreme_frame<float>(a, view, model);
    if (!frame.ok()) return false;
    out->frame = *frame;
    out->v.resize(points);
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    for (auto& vertex : out->v) {
        const glm::dvec3 p = random.point(view);
        // Mostly unit normals, some facing away from the sun, a few not numbers.
        const glm::dvec3 n = random.chance(0.01) ? glm::dvec3(kNaN) : random.unit();
        for (int c = 0; c < 3; ++c) {
            vertex.position[c] = float(p[c]);
            vertex.normal[c] = float(n[c]);
        }
    }
    out->lighting.normals = out->v.data()->normal;
    out->lighting.normal_stride_bytes = sizeof(Vertex);
    out->lighting.ambient = {float(random.uniform(0, 0.1)), float(random.uniform(0, 0.1)),
                             float(random.uniform(0, 0.2))};
    out->lighting.albedo = {float(random.uniform(0, 1)), float(random.uniform(0, 1)),
                            float(random.uniform(0, 1))};
    out->exposure = float(random.log_uniform(1e-3, 1e6));
    return true;
}

struct Codes {
    std::vector<std::uint8_t> extinction, lit, in_scattering;
    std::size_t invalid = 0;
    unsigned threads_used = 0;
};

/// Only RGBA8 outputs (the `which` bits: 1 F_ex, 2 lit, 4 L_in): the one-pass path. Packed
/// positions and normals when `packed`, else the interleaved records.
Codes one_pass(const Scene& s, Kernel kernel, int which, bool packed, unsigned threads) {
    const std::size_t n = s.v.size();
    std::vector<float> xyz, normals;
    for (const Vertex& vertex : s.v) {
        xyz.insert(xyz.end(), vertex.position, vertex.position + 3);
        normals.insert(normals.end(), vertex.normal, vertex.normal + 3);
    }
    aerial::Lighting lighting = s.lighting;
    if (packed) {
        lighting.normals = normals.data();
        lighting.normal_stride_bytes = 0;
    }
    Codes codes;
    codes.extinction.assign(4 * n, 7);
    codes.lit.assign(4 * n, 7);
    codes.in_scattering.assign(4 * n, 7);
    aerial::BatchOutputs out;
    if (which & 1) out.extinction_rgba8 = codes.extinction.data();
    if (which & 2) out.lit_rgba8 = codes.lit.data();
    if (which & 4) out.in_scattering_rgba8 = codes.in_scattering.data();
    auto settings = aerial_test::split_batch(kernel, threads, 128, {s.exposure});
    settings.lighting = &lighting;
    const auto positions = packed ? aerial::Positions::aos(xyz.data(), n)
                                  : aerial::Positions::aos(s.v.data()->position, n, sizeof(Vertex));
    const auto stats = aerial::shade_into(s.frame, positions, out, settings);
    EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    if (stats.ok()) {
        codes.invalid = stats->invalid_vertices;
        codes.threads_used = stats->threads_used;
    }
    return codes;
}

/// The float path of the same kernel (asking for floats turns the one-pass path off), and the
/// documented rules applied to its values: the lit colour as batch.hpp defines it, then the
/// 8-bit rule after the exposure.
Codes rule_on_floats(const Scene& s, Kernel kernel) {
    const std::size_t n = s.v.size();
    std::vector<float> f(3 * n), l(3 * n), sun(3 * n);
    aerial::BatchOutputs out;
    out.extinction_rgb = f.data();
    out.in_scattering_rgb = l.data();
    out.sun_irradiance_rgb = sun.data();
    aerial::BatchSettings settings;
    settings.kernel = kernel;
    settings.threads = 1;
    const auto stats = aerial::shade_into(
        s.frame, aerial::Positions::aos(s.v.data()->position, n, sizeof(Vertex)), out, settings);
    EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    Codes codes;
    if (stats.ok()) codes.invalid = stats->invalid_vertices;
    const aerial::Display display{s.exposure, aerial::ToneCurve::clamp};
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 normal(s.v[i].normal[0], s.v[i].normal[1], s.v[i].normal[2]);
        const float n_dot_l = std::max(glm::dot(normal, s.frame.sun_dir), 0.0f);
        for (int c = 0; c < 3; ++c) {
            const float lit = f[3 * i + c] * s.lighting.albedo[c] *
                              (sun[3 * i + c] * n_dot_l + s.lighting.ambient[c]);
            codes.extinction.push_back(aerial::to_unorm8(f[3 * i + c]));
            codes.lit.push_back(aerial::to_unorm8(aerial::display_value(display, lit)));
            codes.in_scattering.push_back(
                aerial::to_unorm8(aerial::display_value(display, l[3 * i + c])));
        }
        codes.extinction.push_back(255);
        codes.lit.push_back(255);
        codes.in_scattering.push_back(255);
    }
    return codes;
}

const char* kernel_name(Kernel k) { return k == Kernel::simd ? "simd" : "simd_fast"; }

std::string name(Model model) { return std::string(aerial::model_name(model)); }

TEST(OnePassRgba8, HeightAndLitCodesAreTheRuleOnTheFloatPathOnEveryTarget) {
    const auto targets = aerial::validation::simd_test_targets();
    ASSERT_FALSE(targets.empty());
    for (const std::string& target : targets) {
        const ForcedTarget forced(target);
        ASSERT_TRUE(forced.ok());
        for (Model model : {Model::height, Model::hoffman_preetham}) {
            for (Kernel kernel : {Kernel::simd, Kernel::simd_fast}) {
                SCOPED_TRACE("target " + target + ", " + name(model) + ", " + kernel_name(kernel));
                ExtremeSampler random(91);
                std::size_t vertices = 0;
                int cases = 0;
                while (cases < 16) {
                    Scene s;
                    // Sizes around multiples of the widest step (2 x 16 lanes), to cover tails.
                    if (!make_scene(random, model, 300 + 31 * std::size_t(cases), &s)) continue;
                    const Codes want = rule_on_floats(s, kernel);
                    // Every output set with the lit colour or the height model, both layouts;
                    // two threads on some.
                    for (int which : {7, 2, 3, 6, 1, 5}) {
                        const bool packed = (cases + which) % 2 == 0;
                        const unsigned threads = cases % 4 == 0 ? 2u : 1u;
                        const Codes got = one_pass(s, kernel, which, packed, threads);
                        ASSERT_EQ(got.invalid, want.invalid);
                        ASSERT_EQ(got.threads_used, threads);
                        for (std::size_t i = 0; i < got.lit.size(); ++i) {
                            if (which & 1) {
                                ASSERT_EQ(int(got.extinction[i]), int(want.extinction[i]))
                                    << "F_ex byte " << i << " of case " << cases;
                            }
                            if (which & 2) {
                                ASSERT_EQ(int(got.lit[i]), int(want.lit[i]))
                                    << "lit byte " << i << " of case " << cases << ", exposure "
                                    << s.exposure << (packed ? ", packed" : ", records");
                            }
                            if (which & 4) {
                                ASSERT_EQ(int(got.in_scattering[i]), int(want.in_scattering[i]))
                                    << "L_in byte " << i << " of case " << cases;
                            }
                        }
                    }
                    vertices += s.v.size();
                    ++cases;
                }
                std::printf("%s %s one-pass on %s: %zu vertices, codes = rule on the floats\n",
                            name(model).c_str(), kernel_name(kernel), target.c_str(), vertices);
            }
        }
    }
}

/// |code - 255 clamp(v)| for the exact value v: at most 0.5 where the code is v's rounding.
double code_error(std::uint8_t code, double v) {
    return std::abs(double(code) - 255.0 * std::min(std::max(v, 0.0), 1.0));
}

TEST(OnePassRgba8, LitCodesWithinHalfAStepOfTheDoubleModel) {
    // Presets, eyes from the ground to 3 km, the sun from below the horizon to the zenith,
    // terrain points up to 30 km away; the exposure maps each frame's brightest lit colour
    // (double model) to 1. The accurate kernel's codes must be the exact value's rounding but
    // for float noise.
    ExtremeSampler random(92);
    const char* presets[] = {"earth", "hp2002", "hazy", "foggy", "mars"};
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        double worst[2] = {0.0, 0.0};
        std::size_t vertices = 0;
        for (int frame_index = 0; frame_index < 400; ++frame_index) {
            const auto atmosphere = aerial::atmosphere_preset(presets[frame_index % 5]);
            ASSERT_TRUE(atmosphere.ok());
            aerial::View view;
            view.eye = {0.0, 0.0, random.uniform(2.0, 3000.0)};
            const double elevation = random.uniform(-0.1, 1.5);
            const double azimuth = random.uniform(0.0, 6.283);
            view.sun_dir = {std::cos(elevation) * std::cos(azimuth),
                            std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
            const auto frame_f = aerial::prepare_frame<float>(*atmosphere, view, model);
            const auto frame_d = aerial::prepare_frame<double>(*atmosphere, view, model);
            ASSERT_TRUE(frame_f.ok() && frame_d.ok());
            Scene s;
            s.frame = *frame_f;
            s.v.resize(2500);
            for (auto& vertex : s.v) {
                const double r = random.log_uniform(1.0, 3e4), a = random.uniform(0.0, 6.283);
                const glm::dvec3 n = random.unit();
                const float p[3] = {float(r * std::cos(a)), float(r * std::sin(a)),
                                    float(random.uniform(0.0, 300.0))};
                for (int c = 0; c < 3; ++c) {
                    vertex.position[c] = p[c];
                    vertex.normal[c] = float(n[c]);
                }
            }
            s.lighting.normals = s.v.data()->normal;
            s.lighting.normal_stride_bytes = sizeof(Vertex);
            s.lighting.ambient = {0.02f, 0.03f, 0.05f};
            s.lighting.albedo = {0.8f, 0.7f, 0.6f};
            std::vector<glm::dvec3> truth(s.v.size());
            double brightest = 0.0;
            for (std::size_t i = 0; i < s.v.size(); ++i) {
                const Vertex& vertex = s.v[i];
                const glm::dvec3 p(vertex.position[0], vertex.position[1], vertex.position[2]);
                const glm::dvec3 normal(vertex.normal[0], vertex.normal[1], vertex.normal[2]);
                const auto exact = aerial::scatter(*frame_d, p);
                const double n_dot_l =
                    std::max(glm::dot(normal, glm::dvec3(frame_f->sun_dir)), 0.0);
                for (int c = 0; c < 3; ++c) {
                    truth[i][c] =
                        exact.extinction[c] * double(s.lighting.albedo[c]) *
                        (exact.sun_irradiance[c] * n_dot_l + double(s.lighting.ambient[c]));
                    brightest = std::max(brightest, truth[i][c]);
                }
            }
            s.exposure = brightest > 0.0 ? float(1.0 / brightest) : 1.0f;
            for (int k = 0; k < 2; ++k) {
                const Codes got =
                    one_pass(s, k == 0 ? Kernel::simd : Kernel::simd_fast, 2, false, 1);
                for (std::size_t i = 0; i < s.v.size(); ++i) {
                    for (int c = 0; c < 3; ++c) {
                        worst[k] = std::max(
                            worst[k], code_error(got.lit[4 * i + c], s.exposure * truth[i][c]));
                    }
                }
            }
            vertices += s.v.size();
        }
        std::printf(
            "%s lit codes vs the double model over %zu vertices: simd %.5f LSB, simd_fast %.5f "
            "LSB (0.5 = exact rounding)\n",
            name(model).c_str(), vertices, worst[0], worst[1]);
        EXPECT_LE(worst[0], 0.5 + 1e-2) << name(model);
        EXPECT_LE(worst[1], 0.5 + 5e-2) << name(model);
    }
}

}  // namespace
