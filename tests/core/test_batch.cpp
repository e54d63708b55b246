// The batch API: every variant against the per-vertex model, layouts, threads, the 8-bit rule,
// errors, and the accuracy of the accurate SIMD path on a million vertices.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/batch.hpp"
#include "batch_outputs.hpp"
#include "split_batch.hpp"

namespace {

using aerial::Model;

/// An interleaved vertex as an engine would store it: position, normal, texcoord.
struct Vertex {
    float position[3];
    float normal[3];
    float uv[2];
};

std::vector<Vertex> random_scene(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> horizontal(-30000.0f, 30000.0f), height(-50.0f, 3000.0f),
        unit(-1.0f, 1.0f);
    std::vector<Vertex> v(n);
    for (auto& x : v) {
        x.position[0] = horizontal(rng);
        x.position[1] = horizontal(rng);
        x.position[2] = height(rng);
        glm::vec3 normal(unit(rng), unit(rng), 1.0f);
        normal = glm::normalize(normal);
        std::memcpy(x.normal, &normal, sizeof x.normal);
        x.uv[0] = x.uv[1] = 0.0f;
    }
    return v;
}

aerial::Frame<float> frame_for(Model model, const char* preset = "earth") {
    aerial::View view;
    view.eye = {100.0, -200.0, 150.0};
    view.sun_dir = glm::normalize(glm::dvec3(0.2, 0.7, 0.3));
    return *aerial::prepare_frame<float>(*aerial::atmosphere_preset(preset), view, model);
}

TEST(UnormRule, RoundsHalfUpAndClamps) {
    EXPECT_EQ(aerial::to_unorm8(0.0f), 0);
    EXPECT_EQ(aerial::to_unorm8(1.0f), 255);
    EXPECT_EQ(aerial::to_unorm8(-3.0f), 0);
    EXPECT_EQ(aerial::to_unorm8(7.0f), 255);
    EXPECT_EQ(aerial::to_unorm8(std::nanf("")), 0);
    EXPECT_EQ(aerial::to_unorm8(0.49f / 255.0f), 0);
    EXPECT_EQ(aerial::to_unorm8(0.51f / 255.0f), 1);
    EXPECT_EQ(aerial::to_unorm8(127.5f / 255.0f + 1e-6f), 128);
    EXPECT_EQ(aerial::to_unorm8(127.49f / 255.0f), 127);
}

TEST(Display, ToneCurvesMapIntoTheUnitInterval) {
    aerial::Display clamp{2.0f, aerial::ToneCurve::clamp};
    EXPECT_FLOAT_EQ(aerial::display_value(clamp, 0.25f), 0.5f);
    EXPECT_FLOAT_EQ(aerial::display_value(clamp, 3.0f), 1.0f);
    aerial::Display exponential{1.0f, aerial::ToneCurve::exponential};
    EXPECT_FLOAT_EQ(aerial::display_value(exponential, 1.0f), 1.0f - std::exp(-1.0f));
    EXPECT_LT(aerial::display_value(exponential, 100.0f), 1.0f + 1e-7f);
    EXPECT_EQ(aerial::display_value(exponential, 0.0f), 0.0f);
}

/// Shades `vertices` with every output on, returning them in one struct.
struct AllOutputs {
    std::vector<std::uint8_t> extinction, lit, in_scattering;
    std::vector<float> extinction_rgb, in_scattering_rgb, sun_rgb;
    aerial::BatchStats stats;
};

AllOutputs shade_all(const aerial::Frame<float>& frame, const std::vector<Vertex>& v,
                     aerial::Kernel kernel, unsigned threads, const aerial::Lighting& lighting,
                     float exposure = 30.0f) {
    AllOutputs o;
    const std::size_t n = v.size();
    o.extinction.assign(4 * n, 7);
    o.lit.assign(4 * n, 7);
    o.in_scattering.assign(4 * n, 7);
    o.extinction_rgb.assign(3 * n, -1.0f);
    o.in_scattering_rgb.assign(3 * n, -1.0f);
    o.sun_rgb.assign(3 * n, -1.0f);
    aerial::BatchOutputs out = aerial_test::floats_and_codes(
        o.extinction_rgb, o.in_scattering_rgb, o.sun_rgb, o.extinction, o.in_scattering);
    out.lit_rgba8 = o.lit.data();
    auto settings = aerial_test::split_batch(kernel, threads, 1000, {exposure});
    settings.lighting = &lighting;
    const auto positions = aerial::Positions::aos(v.data()->position, n, sizeof(Vertex));
    const auto stats = aerial::shade_into(frame, positions, out, settings);
    EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    if (stats.ok()) o.stats = *stats;
    return o;
}

aerial::Lighting lighting_for(const std::vector<Vertex>& v) {
    aerial::Lighting lighting;
    lighting.normals = v.data()->normal;
    lighting.normal_stride_bytes = sizeof(Vertex);
    lighting.ambient = {0.02f, 0.03f, 0.05f};
    lighting.albedo = {0.8f, 0.7f, 0.6f};
    return lighting;
}

TEST(Batch, ScalarKernelIsThePerVertexModelAndTheRule) {
    // The scalar kernel is scatter<float> through the batch driver: every output must be what the
    // documented rules make of it, code for code, at each vertex's own index and stride.
    const auto v = random_scene(3000, 1);
    const aerial::Lighting lighting = lighting_for(v);
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        const auto frame = frame_for(model);
        const AllOutputs o = shade_all(frame, v, aerial::Kernel::scalar, 1, lighting);
        const aerial::Display display{30.0f, aerial::ToneCurve::clamp};
        for (std::size_t i = 0; i < v.size(); ++i) {
            const glm::vec3 p(v[i].position[0], v[i].position[1], v[i].position[2]);
            const auto s = aerial::scatter(frame, p);
            const glm::vec3 n(v[i].normal[0], v[i].normal[1], v[i].normal[2]);
            const float n_dot_l = std::max(glm::dot(n, frame.sun_dir), 0.0f);
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(o.extinction_rgb[3 * i + c], s.extinction[c]);
                ASSERT_EQ(o.in_scattering_rgb[3 * i + c], s.in_scattering[c]);
                ASSERT_EQ(o.sun_rgb[3 * i + c], s.sun_irradiance[c]);
                ASSERT_EQ(o.extinction[4 * i + c], aerial::to_unorm8(s.extinction[c]));
                ASSERT_EQ(o.in_scattering[4 * i + c],
                          aerial::to_unorm8(aerial::display_value(display, s.in_scattering[c])));
                const float lit = s.extinction[c] * lighting.albedo[c] *
                                  (s.sun_irradiance[c] * n_dot_l + lighting.ambient[c]);
                ASSERT_EQ(o.lit[4 * i + c], aerial::to_unorm8(aerial::display_value(display, lit)))
                    << "vertex " << i << " channel " << c;
            }
            ASSERT_EQ(o.extinction[4 * i + 3], 255);
            ASSERT_EQ(o.lit[4 * i + 3], 255);
            ASSERT_EQ(o.in_scattering[4 * i + 3], 255);
        }
    }
}

/// How far a kernel may stray from the double-precision model: in relative terms for the float
/// outputs, in 8-bit steps (before rounding) for the codes.
struct KernelBound {
    aerial::Kernel kernel;
    double relative;
    double code_lsb;
};

TEST(Batch, EveryVariantStaysWithinItsBoundOfTheDoubleModel) {
    // Every kernel against scatter<double> (an independent precision of the per-vertex model):
    // scalar and simd keep every code within half a step of the exact value plus float rounding,
    // simd_fast within one step (batch.hpp). Relative bounds: measured on this scene (scalar
    // 4.8e-6, simd 1.2e-6, simd_fast 1.3e-5) with a factor of two.
    const auto v = random_scene(3000, 1);
    const aerial::Lighting lighting = lighting_for(v);
    for (const KernelBound bound : {KernelBound{aerial::Kernel::scalar, 1e-5, 0.5 + 2e-3},
                                    KernelBound{aerial::Kernel::simd, 2.5e-6, 0.5 + 2e-3},
                                    KernelBound{aerial::Kernel::simd_fast, 2.5e-5, 1.0}}) {
        for (Model model : {Model::hoffman_preetham, Model::height}) {
            aerial::View view;
            view.eye = {100.0, -200.0, 150.0};
            view.sun_dir = glm::normalize(glm::dvec3(0.2, 0.7, 0.3));
            const auto exact =
                *aerial::prepare_frame<double>(*aerial::atmosphere_preset("earth"), view, model);
            const AllOutputs o = shade_all(frame_for(model), v, bound.kernel, 1, lighting);
            double worst_relative = 0.0, worst_lsb = 0.0;
            for (std::size_t i = 0; i < v.size(); ++i) {
                const glm::dvec3 p(v[i].position[0], v[i].position[1], v[i].position[2]);
                const auto s = aerial::scatter(exact, p);
                const glm::dvec3 n(v[i].normal[0], v[i].normal[1], v[i].normal[2]);
                const double n_dot_l = std::max(glm::dot(n, exact.sun_dir), 0.0);
                for (int c = 0; c < 3; ++c) {
                    const double lit = s.extinction[c] * lighting.albedo[c] *
                                       (s.sun_irradiance[c] * n_dot_l + lighting.ambient[c]);
                    const double pairs[3][2] = {
                        {o.extinction_rgb[3 * i + c], s.extinction[c]},
                        {o.in_scattering_rgb[3 * i + c], s.in_scattering[c]},
                        {o.sun_rgb[3 * i + c], s.sun_irradiance[c]}};
                    for (const auto& pair : pairs) {
                        worst_relative = std::max(
                            worst_relative, std::abs(pair[0] - pair[1]) / std::max(pair[1], 1e-30));
                    }
                    const double codes[3][2] = {
                        {double(o.extinction[4 * i + c]), 255.0 * std::min(s.extinction[c], 1.0)},
                        {double(o.in_scattering[4 * i + c]),
                         255.0 * std::min(30.0 * s.in_scattering[c], 1.0)},
                        {double(o.lit[4 * i + c]), 255.0 * std::min(30.0 * lit, 1.0)}};
                    for (const auto& code : codes) {
                        worst_lsb = std::max(worst_lsb, std::abs(code[0] - code[1]));
                    }
                }
            }
            EXPECT_LE(worst_relative, bound.relative)
                << "kernel " << int(bound.kernel) << " model " << int(model);
            EXPECT_LE(worst_lsb, bound.code_lsb)
                << "kernel " << int(bound.kernel) << " model " << int(model);
            std::printf("kernel %d model %d: relative %.3g, codes %.4f LSB\n", int(bound.kernel),
                        int(model), worst_relative, worst_lsb);
        }
    }
}

TEST(Batch, ThreadsGiveBitIdenticalResults) {
    const auto v = random_scene(50000, 2);
    const aerial::Lighting lighting = lighting_for(v);
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        const auto frame = frame_for(model);
        const AllOutputs one = shade_all(frame, v, aerial::Kernel::simd, 1, lighting);
        const AllOutputs many = shade_all(frame, v, aerial::Kernel::simd, 4, lighting);
        EXPECT_EQ(one.stats.threads_used, 1u);
        EXPECT_GT(many.stats.threads_used, 1u);
        EXPECT_EQ(one.extinction, many.extinction);
        EXPECT_EQ(one.lit, many.lit);
        EXPECT_EQ(one.in_scattering, many.in_scattering);
        EXPECT_EQ(one.in_scattering_rgb, many.in_scattering_rgb);
    }
}

TEST(Batch, SmallBatchesStayOnTheCallersThread) {
    const auto v = random_scene(1000, 3);
    std::vector<std::uint8_t> out(4 * v.size());
    aerial::BatchOutputs outputs;
    outputs.extinction_rgba8 = out.data();
    aerial::BatchSettings settings;
    settings.threads = 8;  // min_vertices_per_thread (32768) decides
    const auto stats = aerial::shade_into(
        frame_for(Model::height),
        aerial::Positions::aos(v.data()->position, v.size(), sizeof(Vertex)), outputs, settings);
    ASSERT_TRUE(stats.ok());
    EXPECT_EQ(stats->threads_used, 1u);
}

TEST(Batch, SoaStridedAndPackedAosLayoutsAgree) {
    const auto v = random_scene(777, 4);
    std::vector<float> x, y, z;
    for (const auto& p : v) {
        x.push_back(p.position[0]);
        y.push_back(p.position[1]);
        z.push_back(p.position[2]);
    }
    const auto frame = frame_for(Model::height);
    std::vector<std::uint8_t> a(4 * v.size()), b(4 * v.size());
    aerial::BatchOutputs out_a, out_b;
    out_a.in_scattering_rgba8 = a.data();
    out_b.in_scattering_rgba8 = b.data();
    ASSERT_TRUE(
        aerial::shade_into(
            frame, aerial::Positions::aos(v.data()->position, v.size(), sizeof(Vertex)), out_a)
            .ok());
    ASSERT_TRUE(aerial::shade_into(
                    frame, aerial::Positions::soa(x.data(), y.data(), z.data(), x.size()), out_b)
                    .ok());
    EXPECT_EQ(a, b);
    // Tightly packed records take the SIMD deinterleaving path.
    std::vector<float> packed;
    for (const auto& p : v) packed.insert(packed.end(), p.position, p.position + 3);
    std::vector<std::uint8_t> c(4 * v.size());
    aerial::BatchOutputs out_c;
    out_c.in_scattering_rgba8 = c.data();
    ASSERT_TRUE(
        aerial::shade_into(frame, aerial::Positions::aos(packed.data(), v.size()), out_c).ok());
    EXPECT_EQ(a, c);
}

TEST(Batch, StridedOutputsLeaveTheGapsAlone) {
    // Colours written into an interleaved engine buffer must not touch the other attributes.
    const auto v = random_scene(300, 5);
    struct Out {
        std::uint8_t colour[4];
        std::uint32_t untouched;
    };
    std::vector<Out> buffer(v.size(), Out{{0, 0, 0, 0}, 0xDEADBEEF});
    aerial::BatchOutputs outputs;
    outputs.extinction_rgba8 = buffer.data()->colour;
    outputs.extinction_rgba8_stride = sizeof(Out);
    ASSERT_TRUE(aerial::shade_into(
                    frame_for(Model::hoffman_preetham),
                    aerial::Positions::aos(v.data()->position, v.size(), sizeof(Vertex)), outputs)
                    .ok());
    for (const auto& o : buffer) {
        EXPECT_EQ(o.untouched, 0xDEADBEEFu);
        EXPECT_EQ(o.colour[3], 255);
    }
}

TEST(Batch, InvalidVerticesAreNeutralAndCounted) {
    std::vector<float> xyz = {0, 1000, 0, NAN, 0, 0, 0, INFINITY, 0, 1e13f, 0, 0, 5, 5, 5};
    std::vector<float> f(3 * 5), l(3 * 5);
    aerial::BatchOutputs out;
    out.extinction_rgb = f.data();
    out.in_scattering_rgb = l.data();
    for (auto kernel : {aerial::Kernel::scalar, aerial::Kernel::simd, aerial::Kernel::simd_fast}) {
        aerial::BatchSettings settings;
        settings.kernel = kernel;
        const auto stats = aerial::shade_into(frame_for(Model::height),
                                              aerial::Positions::aos(xyz.data(), 5), out, settings);
        ASSERT_TRUE(stats.ok());
        EXPECT_EQ(stats->invalid_vertices, 3u);
        for (int i = 1; i <= 3; ++i) {
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(f[3 * i + c], 1.0f);
                EXPECT_EQ(l[3 * i + c], 0.0f);
            }
        }
        EXPECT_LT(f[1], 1.0f) << "the valid vertex 1 km away is shaded";
    }
}

TEST(Batch, ErrorsNameWhatIsWrong) {
    const auto frame = frame_for(Model::height);
    std::vector<float> xyz(30, 1.0f);
    std::vector<std::uint8_t> rgba(40);
    aerial::BatchOutputs out;
    out.extinction_rgba8 = rgba.data();
    auto expect_error = [&](const aerial::Positions& p, const aerial::BatchOutputs& o,
                            const aerial::BatchSettings& s, const char* field) {
        const auto r = aerial::shade_into(frame, p, o, s);
        ASSERT_FALSE(r.ok()) << field;
        EXPECT_EQ(r.error().field, field);
        EXPECT_EQ(r.error().message.rfind(std::string("aerial::shade_into(): ") + field + ": ", 0),
                  0u)
            << r.error().message;
    };
    expect_error(aerial::Positions::aos(nullptr, 10), out, {}, "positions");
    expect_error(aerial::Positions::aos(xyz.data(), 10), aerial::BatchOutputs{}, {}, "outputs");
    aerial::BatchOutputs strided = out;
    strided.extinction_rgba8_stride = 3;
    expect_error(aerial::Positions::aos(xyz.data(), 10), strided, {}, "extinction_rgba8_stride");
    aerial::BatchOutputs lit;
    lit.lit_rgba8 = rgba.data();
    expect_error(aerial::Positions::aos(xyz.data(), 10), lit, {}, "lighting");
    aerial::BatchSettings dark;
    dark.display.exposure = 0.0f;
    expect_error(aerial::Positions::aos(xyz.data(), 10), out, dark, "display.exposure");
    // Nothing was written by the failed calls.
    for (std::uint8_t b : rgba) EXPECT_EQ(b, 0);
    // An empty batch is fine.
    EXPECT_TRUE(aerial::shade_into(frame, aerial::Positions::aos(nullptr, 0), out).ok());
}

TEST(Batch, AccuratePathWithinHalfAStepOfTheDoubleModelOnAMillionVertices) {
    // 8-bit codes from the SIMD path against the unrounded double-precision model: off by at
    // most 0.5 LSB before rounding, i.e. the code is the double's rounding except where the
    // double sits within float noise of a rounding boundary.
    constexpr std::size_t kVertices = 1'000'000;
    const auto v = random_scene(kVertices, 6);
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        aerial::View view;
        view.eye = {100.0, -200.0, 150.0};
        view.sun_dir = glm::normalize(glm::dvec3(0.2, 0.7, 0.3));
        const auto atmosphere = *aerial::atmosphere_preset("earth");
        const auto frame = *aerial::prepare_frame<float>(atmosphere, view, model);
        const auto exact = *aerial::prepare_frame<double>(atmosphere, view, model);
        std::vector<float> f(3 * kVertices), l(3 * kVertices);
        aerial::BatchOutputs out;
        out.extinction_rgb = f.data();
        out.in_scattering_rgb = l.data();
        ASSERT_TRUE(
            aerial::shade_into(
                frame, aerial::Positions::aos(v.data()->position, kVertices, sizeof(Vertex)), out)
                .ok());
        const double exposure = 30.0;  // brightest L_in of this scene ~ 1/30
        double worst_f = 0.0, worst_l = 0.0;
        for (std::size_t i = 0; i < kVertices; i += 1) {
            const glm::dvec3 p(v[i].position[0], v[i].position[1], v[i].position[2]);
            const auto s = aerial::scatter(exact, p);
            for (int c = 0; c < 3; ++c) {
                worst_f = std::max(worst_f, 255.0 * std::abs(f[3 * i + c] - s.extinction[c]));
                worst_l = std::max(worst_l,
                                   255.0 * exposure * std::abs(l[3 * i + c] - s.in_scattering[c]));
            }
        }
        std::printf(
            "%s accurate SIMD vs double: max |F_ex| error %.4f LSB, max |L_in| error %.4f "
            "LSB (exposure %g)\n",
            std::string(aerial::model_name(model)).c_str(), worst_f, worst_l, exposure);
        EXPECT_LT(worst_f, 0.5);
        EXPECT_LT(worst_l, 0.5);
    }
}

}  // namespace
