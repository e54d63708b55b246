// The 8-bit rule of the batch API on its SIMD paths. The one-pass path (hoffman-preetham, F_ex
// and L_in as RGBA8 only): its codes are the rule applied to the float path's values on every
// SIMD target but where a value lies within float rounding of a rounding boundary (the one-pass
// path folds 255 and the exposure into its constants), the same whatever the layout, strides,
// threads and tails; they are within half a step of the double model on a million vertices
// including extreme atmospheres, views and points; exposures near the float range take the
// general path; concurrent callers share the worker pool safely. The general path: every variant
// (F_ex, lit, L_in; both models, precisions and tone curves; AoS and SoA; threads) is the rule on
// its floats.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/batch.hpp"
#include "batch_outputs.hpp"
#include "extreme_sampler.hpp"
#include "forced_target.hpp"
#include "split_batch.hpp"

namespace {

using aerial::Kernel;
using aerial::Model;
using aerial::testing::ExtremeSampler;
using aerial::testing::ForcedTarget;

const char* kernel_name(Kernel k) { return k == Kernel::simd ? "simd" : "simd_fast"; }

/// One random hoffman-preetham frame of extreme inputs, its points (packed x, y, z floats) and
/// an exposure.
struct Case {
    aerial::Frame<float> frame;
    aerial::Frame<double> exact;
    std::vector<float> xyz;
    float exposure = 1.0f;
    std::size_t size() const { return xyz.size() / 3; }
};

/// The float nearest to v. Through a volatile: GCC 12 at -O3 was seen to drop the round trip
/// double -> float -> double on this sampler's values here.
double nearest_float(double v) {
    volatile float f = static_cast<float>(v);
    return double(f);
}

bool make_case(ExtremeSampler& random, std::size_t points, Case* out) {
    const aerial::Atmosphere a = random.atmosphere();
    aerial::View view = random.view(a);
    // The eye and the scale as float holds them, so that the double model sees the same
    // segment (10^6 m away from the origin, float moves the eye by centimetres, which coefficients
    // of 1 /m turn into whole 8-bit steps).
    view.eye = {nearest_float(view.eye.x), nearest_float(view.eye.y), nearest_float(view.eye.z)};
    view.meters_per_unit = nearest_float(view.meters_per_unit);
    auto frame = aerial::prepare_frame<float>(a, view, Model::hoffman_preetham);
    auto exact = aerial::prepare_frame<double>(a, view, Model::hoffman_preetham);
    if (!frame.ok() || !exact.ok()) return false;
    out->frame = *frame;
    out->exact = *exact;
    out->xyz.clear();
    for (std::size_t i = 0; i < points; ++i) {
        const glm::dvec3 p = random.point(view);
        for (int c = 0; c < 3; ++c) out->xyz.push_back(float(p[c]));
    }
    out->exposure = float(random.log_uniform(1e-3, 1e6));
    return true;
}

struct Codes {
    std::vector<std::uint8_t> extinction, in_scattering;
    std::size_t invalid = 0;
    // rule_on_floats only: per byte, how far 255 v + 1/2 of the float value v is from the nearest
    // integer (a rounding boundary of the rule).
    std::vector<double> extinction_margin, in_scattering_margin;
};

/// Distance of 255 clamp(v) + 1/2 from the nearest integer.
double boundary_margin(double v) {
    const double x = 255.0 * std::min(std::max(v, 0.0), 1.0) + 0.5;
    return std::abs(x - std::round(x));
}

/// The one-pass path: only F_ex and L_in as RGBA8, packed positions.
Codes one_pass(const Case& c, Kernel kernel, unsigned threads = 1,
               aerial::ToneCurve tone = aerial::ToneCurve::clamp) {
    Codes codes;
    codes.extinction.assign(4 * c.size(), 7);
    codes.in_scattering.assign(4 * c.size(), 7);
    aerial::BatchOutputs out;
    out.extinction_rgba8 = codes.extinction.data();
    out.in_scattering_rgba8 = codes.in_scattering.data();
    const auto settings = aerial_test::split_batch(kernel, threads, 256, {c.exposure, tone});
    const auto stats =
        aerial::shade_into(c.frame, aerial::Positions::aos(c.xyz.data(), c.size()), out, settings);
    EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    if (stats.ok()) codes.invalid = stats->invalid_vertices;
    return codes;
}

/// The float path of the same kernel (asking for floats turns the one-pass path off), and the
/// documented rule applied to its values.
Codes rule_on_floats(const Case& c, Kernel kernel,
                     aerial::ToneCurve tone = aerial::ToneCurve::clamp) {
    std::vector<float> f(3 * c.size()), l(3 * c.size());
    aerial::BatchOutputs out;
    out.extinction_rgb = f.data();
    out.in_scattering_rgb = l.data();
    aerial::BatchSettings settings;
    settings.kernel = kernel;
    settings.threads = 1;
    const auto stats =
        aerial::shade_into(c.frame, aerial::Positions::aos(c.xyz.data(), c.size()), out, settings);
    EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
    Codes codes;
    if (stats.ok()) codes.invalid = stats->invalid_vertices;
    const aerial::Display display{c.exposure, tone};
    for (std::size_t i = 0; i < c.size(); ++i) {
        for (int ch = 0; ch < 3; ++ch) {
            const float shown = aerial::display_value(display, l[3 * i + ch]);
            codes.extinction.push_back(aerial::to_unorm8(f[3 * i + ch]));
            codes.in_scattering.push_back(aerial::to_unorm8(shown));
            codes.extinction_margin.push_back(boundary_margin(f[3 * i + ch]));
            codes.in_scattering_margin.push_back(boundary_margin(shown));
        }
        codes.extinction.push_back(255);
        codes.in_scattering.push_back(255);
        codes.extinction_margin.push_back(0.5);
        codes.in_scattering_margin.push_back(0.5);
    }
    return codes;
}

/// Where the one-pass codes may differ from the rule on the float path's values: by one step,
/// and only where 255 v + 1/2 lies this close to a rounding boundary (the two paths' values
/// differ by a few float roundings, relative 1e-6 at most: 2.6e-4 steps at 255).
constexpr double kTieMargin = 1e-3;

/// Asserts that the one-pass codes `got` are the rule on the float path's values `want` (from
/// rule_on_floats) but at ties: one step, within kTieMargin of a boundary. Returns the ties.
std::size_t expect_rule_but_at_ties(const Codes& got, const Codes& want,
                                    double tie_margin = kTieMargin) {
    std::size_t ties = 0;
    auto check = [&](const char* what, const std::vector<std::uint8_t>& a,
                     const std::vector<std::uint8_t>& b, const std::vector<double>& margin) {
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (a[i] == b[i]) continue;
            ++ties;
            ASSERT_TRUE(std::abs(int(a[i]) - int(b[i])) == 1 && margin[i] <= tie_margin)
                << what << " byte " << i << ": " << int(a[i]) << " against the rule's " << int(b[i])
                << ", 255 v + 1/2 " << margin[i] << " from a boundary";
        }
    };
    check("F_ex", got.extinction, want.extinction, want.extinction_margin);
    if (!::testing::Test::HasFatalFailure()) {
        check("L_in", got.in_scattering, want.in_scattering, want.in_scattering_margin);
    }
    return ties;
}

TEST(OnePassRgba8, CodesAreTheRuleOnTheFloatPathButAtTiesOnEveryTarget) {
    const auto targets = aerial::validation::simd_test_targets();
    ASSERT_FALSE(targets.empty());
    for (Kernel kernel : {Kernel::simd, Kernel::simd_fast}) {
        // Codes of the best target, to compare the others with.
        std::vector<Codes> best;
        for (const std::string& target : targets) {
            SCOPED_TRACE(std::string("target ") + target + ", kernel " + kernel_name(kernel));
            const ForcedTarget forced(target);
            ASSERT_TRUE(forced.ok());
            ExtremeSampler random(71);
            std::size_t checked = 0, cases = 0, differing = 0, compared = 0, ties = 0;
            int largest_difference = 0;
            while (cases < 60) {
                Case c;
                if (!make_case(random, 1001, &c)) continue;
                const Codes got = one_pass(c, kernel);
                const Codes want = rule_on_floats(c, kernel);
                ASSERT_EQ(got.invalid, want.invalid);
                SCOPED_TRACE("case " + std::to_string(cases) + ", exposure " +
                             std::to_string(c.exposure));
                ties += expect_rule_but_at_ties(got, want);
                if (HasFatalFailure()) return;
                if (&target == &targets.front()) {
                    best.push_back(got);
                } else {
                    auto compare = [&](const std::vector<std::uint8_t>& a,
                                       const std::vector<std::uint8_t>& b) {
                        for (std::size_t i = 0; i < a.size(); ++i) {
                            const int d = std::abs(int(a[i]) - int(b[i]));
                            largest_difference = std::max(largest_difference, d);
                            differing += d != 0;
                            ++compared;
                        }
                    };
                    compare(got.extinction, best[cases].extinction);
                    compare(got.in_scattering, best[cases].in_scattering);
                }
                checked += c.size();
                ++cases;
            }
            std::printf(
                "%s one-pass RGBA8 on %s: %zu vertices, codes = rule on the floats but for %zu "
                "ties; against %s: %zu of %zu bytes differ, by at most %d\n",
                kernel_name(kernel), target.c_str(), checked, ties, targets.front().c_str(),
                differing, compared, largest_difference);
            // Targets differ in their reciprocal square root estimate and in fused
            // multiply-adds, so a value on a rounding boundary may round either way: one step.
            EXPECT_LE(largest_difference, 1);
        }
    }
}

// The exponential tone curve on the one-pass path (Highway's expm1 where display_value calls
// std::exp): the rule on the float path's values but where a value lies on a rounding boundary.
TEST(OnePassRgba8, ExponentialToneIsTheRuleOnTheFloatPathButAtTies) {
    for (Kernel kernel : {Kernel::simd, Kernel::simd_fast}) {
        SCOPED_TRACE(kernel_name(kernel));
        ExtremeSampler random(73);
        std::size_t cases = 0, ties = 0, bytes = 0;
        while (cases < 60) {
            Case c;
            if (!make_case(random, 1001, &c)) continue;
            const Codes got = one_pass(c, kernel, 1, aerial::ToneCurve::exponential);
            const Codes want = rule_on_floats(c, kernel, aerial::ToneCurve::exponential);
            ASSERT_EQ(got.invalid, want.invalid);
            // The fast kernel's exponential (relative error 6.6e-6 near 1) moves 1 - exp(-x) by
            // up to 1.7e-3 steps.
            ties +=
                expect_rule_but_at_ties(got, want, kernel == Kernel::simd_fast ? 2e-3 : kTieMargin);
            if (HasFatalFailure()) return;
            bytes += got.extinction.size() + got.in_scattering.size();
            ++cases;
        }
        std::printf("%s one-pass RGBA8, exponential tone: %zu of %zu bytes are ties\n",
                    kernel_name(kernel), ties, bytes);
    }
}

TEST(OnePassRgba8, EveryLayoutStrideOutputAndThreadCountGivesTheSameCodes) {
    struct Vertex {
        float position[3];
        float normal[3];
    };
    ExtremeSampler random(72);
    int cases = 0;
    while (cases < 12) {
        Case c;
        if (!make_case(random, 3000 + std::size_t(cases) * 37, &c)) continue;
        ++cases;
        const std::size_t n = c.size();
        std::vector<Vertex> strided(n);
        std::vector<float> x(n), y(n), z(n);
        for (std::size_t i = 0; i < n; ++i) {
            std::memcpy(strided[i].position, &c.xyz[3 * i], 3 * sizeof(float));
            x[i] = c.xyz[3 * i];
            y[i] = c.xyz[3 * i + 1];
            z[i] = c.xyz[3 * i + 2];
        }
        const aerial::Positions layouts[] = {
            aerial::Positions::aos(c.xyz.data(), n),
            aerial::Positions::aos(strided.data()->position, n, sizeof(Vertex)),
            aerial::Positions::soa(x.data(), y.data(), z.data(), n)};
        for (Kernel kernel : {Kernel::simd, Kernel::simd_fast}) {
            // The codes of packed positions and words on one thread.
            const Codes want = one_pass(c, kernel);
            for (const auto& positions : layouts) {
                for (std::size_t stride : {std::size_t(4), std::size_t(12)}) {
                    for (unsigned threads : {1u, 2u, 3u}) {
                        for (int which = 1; which <= 3; ++which) {
                            // Colours written into a buffer with a gap after each: the gaps
                            // must stay as they were.
                            std::vector<std::uint8_t> e(stride * n, 0xAB), l(stride * n, 0xCD);
                            aerial::BatchOutputs out;
                            if (which & 1) out.extinction_rgba8 = e.data();
                            if (which & 2) out.in_scattering_rgba8 = l.data();
                            out.extinction_rgba8_stride = stride;
                            out.in_scattering_rgba8_stride = stride;
                            const auto settings =
                                aerial_test::split_batch(kernel, threads, 500, {c.exposure});
                            const auto stats =
                                aerial::shade_into(c.frame, positions, out, settings);
                            ASSERT_TRUE(stats.ok()) << stats.error().message;
                            EXPECT_EQ(stats->invalid_vertices, want.invalid);
                            EXPECT_EQ(stats->threads_used, threads);
                            for (std::size_t i = 0; i < n; ++i) {
                                for (std::size_t b = 0; b < stride; ++b) {
                                    const std::uint8_t ge = e[stride * i + b];
                                    const std::uint8_t gl = l[stride * i + b];
                                    const bool colour = b < 4;
                                    ASSERT_EQ(ge, colour && (which & 1) ? want.extinction[4 * i + b]
                                                                        : 0xAB)
                                        << "F_ex vertex " << i << " byte " << b << " stride "
                                        << stride << " threads " << threads;
                                    ASSERT_EQ(gl, colour && (which & 2)
                                                      ? want.in_scattering[4 * i + b]
                                                      : 0xCD)
                                        << "L_in vertex " << i << " byte " << b << " stride "
                                        << stride << " threads " << threads;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

/// |code - 255 clamp(v)| for the exact value v: at most 0.5 where the code is v's rounding.
double code_error(std::uint8_t code, double v) {
    return std::abs(double(code) - 255.0 * std::min(std::max(v, 0.0), 1.0));
}

TEST(OnePassRgba8, CodesWithinHalfAStepOfTheDoubleModelOnAMillionVertices) {
    // Extreme atmospheres, views and points; the exposure maps each frame's brightest L_in
    // (double model) to 1. The accurate kernel's codes must be the exact value's rounding but
    // where the exact value lies within float noise of a rounding boundary.
    ExtremeSampler random(73);
    struct Worst {
        double extinction = 0, in_scattering = 0;
    } worst[2];
    std::size_t vertices = 0;
    while (vertices < 1'000'000) {
        Case c;
        if (!make_case(random, 5000, &c)) continue;
        std::vector<aerial::Scattering<double>> truth(c.size());
        double brightest = 0.0;
        for (std::size_t i = 0; i < c.size(); ++i) {
            const glm::dvec3 p(c.xyz[3 * i], c.xyz[3 * i + 1], c.xyz[3 * i + 2]);
            truth[i] = aerial::scatter(c.exact, p);
            for (int ch = 0; ch < 3; ++ch) {
                ASSERT_TRUE(std::isfinite(truth[i].in_scattering[ch]));
                brightest = std::max(brightest, truth[i].in_scattering[ch]);
            }
        }
        c.exposure = brightest > 1e-30 && brightest < 1e30 ? float(1.0 / brightest) : 1.0f;
        for (int k = 0; k < 2; ++k) {
            const Codes got = one_pass(c, k == 0 ? Kernel::simd : Kernel::simd_fast, 2);
            for (std::size_t i = 0; i < c.size(); ++i) {
                for (int ch = 0; ch < 3; ++ch) {
                    worst[k].extinction =
                        std::max(worst[k].extinction,
                                 code_error(got.extinction[4 * i + ch], truth[i].extinction[ch]));
                    worst[k].in_scattering =
                        std::max(worst[k].in_scattering,
                                 code_error(got.in_scattering[4 * i + ch],
                                            double(c.exposure) * truth[i].in_scattering[ch]));
                }
                ASSERT_EQ(got.extinction[4 * i + 3], 255);
                ASSERT_EQ(got.in_scattering[4 * i + 3], 255);
            }
        }
        vertices += c.size();
    }
    std::printf(
        "one-pass RGBA8 codes vs the double model over %zu vertices: simd F_ex %.5f L_in %.5f "
        "LSB, simd_fast F_ex %.5f L_in %.5f LSB (0.5 = exact rounding)\n",
        vertices, worst[0].extinction, worst[0].in_scattering, worst[1].extinction,
        worst[1].in_scattering);
    EXPECT_LE(worst[0].extinction, 0.5 + 1e-3);
    EXPECT_LE(worst[0].in_scattering, 0.5 + 1e-3);
    // The fast kernel's exponential (relative error 6.6e-6) moves a value by at most 0.002 LSB.
    EXPECT_LE(worst[1].extinction, 0.5 + 5e-3);
    EXPECT_LE(worst[1].in_scattering, 0.5 + 5e-3);
}

TEST(BatchRule, EveryVariantIsTheRuleOnItsKernelsFloats) {
    // The general path (any output set): each RGBA8 output is the documented rule applied to the
    // float values the same kernel gives, for both models, both SIMD precisions, both tone
    // curves, strided AoS and SoA positions, on one thread and on several (which must agree).
    struct Vertex {
        float position[3];
        float normal[3];
    };
    ExtremeSampler random(75);
    constexpr std::size_t n = 2500;
    std::vector<Vertex> v(n);
    std::vector<float> x(n), y(n), z(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 p(random.uniform(-3e4, 3e4), random.uniform(-3e4, 3e4),
                           random.uniform(-50, 3000));
        const glm::dvec3 normal = random.unit();
        for (int c = 0; c < 3; ++c) {
            v[i].position[c] = float(p[c]);
            v[i].normal[c] = float(normal[c]);
        }
        x[i] = v[i].position[0];
        y[i] = v[i].position[1];
        z[i] = v[i].position[2];
    }
    aerial::Lighting lighting;
    lighting.normals = v.data()->normal;
    lighting.normal_stride_bytes = sizeof(Vertex);
    lighting.ambient = {0.02f, 0.03f, 0.05f};
    lighting.albedo = {0.8f, 0.7f, 0.6f};
    aerial::View view;
    view.eye = {100.0, -200.0, 150.0};
    view.sun_dir = glm::normalize(glm::dvec3(0.2, 0.7, 0.3));
    const aerial::Positions layouts[] = {
        aerial::Positions::aos(v.data()->position, n, sizeof(Vertex)),
        aerial::Positions::soa(x.data(), y.data(), z.data(), n)};
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        const auto frame =
            *aerial::prepare_frame<float>(*aerial::atmosphere_preset("earth"), view, model);
        for (Kernel kernel : {Kernel::simd, Kernel::simd_fast}) {
            for (auto tone : {aerial::ToneCurve::clamp, aerial::ToneCurve::exponential}) {
                std::vector<std::uint8_t> first_codes;
                for (const auto& positions : layouts) {
                    for (unsigned threads : {1u, 2u}) {
                        SCOPED_TRACE(std::string(aerial::model_name(model)) + " " +
                                     kernel_name(kernel) + " threads " + std::to_string(threads));
                        std::vector<std::uint8_t> e(4 * n), lit(4 * n), l(4 * n);
                        std::vector<float> f(3 * n), li(3 * n), sun(3 * n);
                        aerial::BatchOutputs out = aerial_test::floats_and_codes(f, li, sun, e, l);
                        out.lit_rgba8 = lit.data();
                        auto settings =
                            aerial_test::split_batch(kernel, threads, 500, {30.0f, tone});
                        settings.lighting = &lighting;
                        const auto stats = aerial::shade_into(frame, positions, out, settings);
                        ASSERT_TRUE(stats.ok()) << stats.error().message;
                        EXPECT_EQ(stats->threads_used, threads);
                        for (std::size_t i = 0; i < n; ++i) {
                            const glm::vec3 normal(v[i].normal[0], v[i].normal[1], v[i].normal[2]);
                            const float n_dot_l = std::max(glm::dot(normal, frame.sun_dir), 0.0f);
                            for (int c = 0; c < 3; ++c) {
                                const float fe = f[3 * i + c], le = li[3 * i + c];
                                ASSERT_TRUE(std::isfinite(fe) && std::isfinite(le));
                                ASSERT_EQ(e[4 * i + c], aerial::to_unorm8(fe)) << "vertex " << i;
                                ASSERT_EQ(l[4 * i + c], aerial::to_unorm8(aerial::display_value(
                                                            settings.display, le)))
                                    << "vertex " << i;
                                const float lit_value =
                                    fe * lighting.albedo[c] *
                                    (sun[3 * i + c] * n_dot_l + lighting.ambient[c]);
                                ASSERT_EQ(lit[4 * i + c], aerial::to_unorm8(aerial::display_value(
                                                              settings.display, lit_value)))
                                    << "vertex " << i;
                            }
                            ASSERT_EQ(e[4 * i + 3], 255);
                            ASSERT_EQ(lit[4 * i + 3], 255);
                            ASSERT_EQ(l[4 * i + 3], 255);
                        }
                        std::vector<std::uint8_t> codes = e;
                        codes.insert(codes.end(), lit.begin(), lit.end());
                        codes.insert(codes.end(), l.begin(), l.end());
                        if (first_codes.empty()) {
                            first_codes = codes;
                        } else {
                            EXPECT_EQ(codes, first_codes) << "layouts and thread counts differ";
                        }
                    }
                }
            }
        }
    }
}

TEST(OnePassRgba8, ExposuresNearTheFloatRangeKeepTheRuleAndTheEye) {
    // The one-pass path folds the exposure into its L_in constants; where that product could
    // overflow (exposure times irradiance beyond the float range), an infinite constant times
    // the zero path at the eye would be NaN: such calls take the general path. Either way the
    // codes are the rule on the floats (but at ties) and the eye itself gets F_ex 255, L_in 0.
    // Sun irradiance 100 (the folded Rayleigh constant is about 3.6 exposure) and exposures
    // from 1e20 to 3e38, with and without the overflow.
    ExtremeSampler random(74);
    aerial::Atmosphere a;
    a.sun_irradiance = {100.0, 100.0, 100.0};
    for (const float exposure : {1e20f, 1e30f, 5e37f, 1e38f, 3e38f}) {
        for (const double g : {0.0, 0.8, 0.99}) {
            a.mie_g = g;
            aerial::View view = random.view(a);
            view.eye = {0.0, 0.0, 100.0};
            view.meters_per_unit = 1.0;
            const auto frame = aerial::prepare_frame<float>(a, view, Model::hoffman_preetham);
            ASSERT_TRUE(frame.ok()) << frame.error().message;
            Case c;
            c.frame = *frame;
            c.exposure = exposure;
            c.xyz = {0.0f, 0.0f, 100.0f};  // the eye
            for (int i = 0; i < 2000; ++i) {
                const glm::dvec3 p = random.point(view);
                for (int k = 0; k < 3; ++k) c.xyz.push_back(float(p[k]));
            }
            for (Kernel kernel : {Kernel::simd, Kernel::simd_fast}) {
                SCOPED_TRACE(std::string(kernel_name(kernel)) + ", exposure " +
                             std::to_string(exposure) + ", g " + std::to_string(g));
                const Codes got = one_pass(c, kernel);
                const Codes want = rule_on_floats(c, kernel);
                ASSERT_EQ(got.invalid, want.invalid);
                for (int ch = 0; ch < 3; ++ch) {
                    EXPECT_EQ(int(got.extinction[ch]), 255) << "F_ex at the eye";
                    EXPECT_EQ(int(got.in_scattering[ch]), 0) << "L_in at the eye";
                }
                expect_rule_but_at_ties(got, want);
                if (HasFatalFailure()) return;
            }
        }
    }
}

TEST(OnePassRgba8, ConcurrentCallersShareTheWorkersSafely) {
    // Application threads calling at once: one gets the worker pool, the others work alone;
    // every result must be the single-threaded one.
    ExtremeSampler random(74);
    Case c;
    while (!make_case(random, 60000, &c)) {
    }
    const Codes want = one_pass(c, Kernel::simd, 1);
    std::vector<Codes> got(3);
    std::vector<std::thread> callers;
    for (std::size_t t = 0; t < got.size(); ++t) {
        callers.emplace_back([&, t] {
            for (int r = 0; r < 4; ++r) got[t] = one_pass(c, Kernel::simd, 2);
        });
    }
    for (auto& t : callers) t.join();
    for (const Codes& g : got) {
        EXPECT_EQ(g.extinction, want.extinction);
        EXPECT_EQ(g.in_scattering, want.in_scattering);
        EXPECT_EQ(g.invalid, want.invalid);
    }
}

TEST(OnePassRgba8, AChildOfForkWorksAloneAndFinishes) {
    // The parent's workers do not exist in a child process: a batch there must run on the
    // child's own thread instead of waiting for them.
    ExtremeSampler random(76);
    Case c;
    while (!make_case(random, 40000, &c)) {
    }
    const Codes want = one_pass(c, Kernel::simd, 2);  // starts the workers here
    const pid_t child = fork();
    ASSERT_GE(child, 0) << "fork failed";
    if (child == 0) {
        std::vector<std::uint8_t> e(4 * c.size());
        aerial::BatchOutputs out;
        out.extinction_rgba8 = e.data();
        aerial::BatchSettings settings;
        settings.threads = 2;
        settings.min_vertices_per_thread = 256;
        const auto stats = aerial::shade_into(
            c.frame, aerial::Positions::aos(c.xyz.data(), c.size()), out, settings);
        const bool ok = stats.ok() && stats->threads_used == 1 && e == want.extinction;
        _exit(ok ? 0 : 1);
    }
    int status = 0;
    pid_t done = 0;
    for (int waited_ms = 0; waited_ms < 60000 && done == 0; waited_ms += 10) {
        done = waitpid(child, &status, WNOHANG);
        if (done == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (done == 0) {
        kill(child, SIGKILL);
        waitpid(child, &status, 0);
        FAIL() << "the child's batch did not finish within 60 s (waiting for absent workers?)";
    }
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0)
        << "the child's batch used other threads or gave other codes than the parent's";
}

}  // namespace
