// The moon as the scene renderer's second light (FrameSettings::moon): which lights a frame is
// shaded with, a frame with both as the sum of a frame with each (cpu and arb backends, the dome
// and the cubemap sky), a left-out light changing the frame by less than a step, the GL state,
// and bad input.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/adaptive_scene.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/scene_sky.hpp"
#include "aerial/sky_gl.hpp"
#include "gl_test_context.hpp"
#include "scene_test_support.hpp"

namespace {

using namespace aerial::scene;

constexpr int kWidth = 128, kHeight = 72;
constexpr double kDegree = 3.14159265358979323846 / 180.0;
/// A full moon at its mean distance: moonlight_fraction.
constexpr double kFullMoon = 2.4e-6;

/// Terrain (lit, textured) under a sky dome and a sun.
struct NightScene {
    std::unique_ptr<Node> root = make_group("world");
    NightScene() {
        root->add(make_sky_dome());
        root->add(make_sun());
        auto texture = std::make_shared<Texture>();
        texture->width = texture->height = 4;
        for (int i = 0; i < 16; ++i) {
            const std::uint8_t v = (i % 2) ? 230 : 160;
            texture->rgb.insert(texture->rgb.end(), {v, v, std::uint8_t(v - 40)});
        }
        ProceduralTerrain terrain;
        terrain.amplitude = 300;
        for (int j = 0; j < 3; ++j) {
            for (int i = -1; i < 1; ++i) {
                HeightfieldSpec spec;
                spec.origin_x = i * 2000.0;
                spec.origin_y = j * 2000.0;
                spec.size = 2000.0;
                spec.resolution = 17;
                auto mesh = heightfield_mesh(
                    spec, [&](double x, double y) { return procedural_height(terrain, x, y); });
                root->add(make_terrain_tile("tile " + std::to_string(i) + " " + std::to_string(j),
                                            std::make_shared<MeshData>(std::move(mesh.value())),
                                            texture, glm::vec3(0.3f)));
            }
        }
    }
};

/// Half terrain, half sky.
Camera night_camera() {
    return aerial_test::scene_camera({0, -500, 700}, {0, 3000, 500}, double(kWidth) / kHeight, 1.0,
                                     20000.0);
}

glm::dvec3 towards(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
    return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

/// Clear air, the sun at `sun_deg`, a moon of `fraction` 35 degrees up in the south-west, and an
/// exposure that shows a card lit by that moon at about 0.2.
FrameSettings moonlit_settings(double sun_deg, double fraction) {
    FrameSettings s;
    s.atmosphere = aerial::atmosphere_preset("earth").value();
    s.sun_dir = towards(sun_deg, 300.0);
    s.model = aerial::Model::height;
    s.moon = Moonlight{towards(35.0, 200.0), fraction};
    const double e = std::max({s.atmosphere.sun_irradiance.x, s.atmosphere.sun_irradiance.y,
                               s.atmosphere.sun_irradiance.z});
    s.display.exposure = float(0.2 / (0.3 * e * fraction * std::sin(35.0 * kDegree)));
    return s;
}

/// The moon's light alone, as one-light settings (what the renderer shades it with).
FrameSettings moon_alone(const FrameSettings& s) {
    FrameSettings m = s;
    m.sun_dir = s.moon->dir;
    m.atmosphere.sun_irradiance *= s.moon->fraction;
    m.moon.reset();
    return m;
}

FrameSettings sun_alone(const FrameSettings& s) {
    FrameSettings m = s;
    m.moon.reset();
    return m;
}

class TwoLightsTest : public aerial_test::SceneDrawingTest<kWidth, kHeight> {
  public:
    std::optional<SceneRenderer> make(Backend backend) {
        RendererOptions options;
        options.backend = backend;
        auto created = SceneRenderer::create(gl(), options);
        if (!created) return std::nullopt;
        return std::move(created.value());
    }
    std::vector<std::uint8_t> frame(SceneRenderer& r, const FrameSettings& s,
                                    FrameReport* report = nullptr) {
        return draw(r, *scene_.root, night_camera(), s, report);
    }
    NightScene scene_;
};

/// How far `both` is from the sum of `a` and `b`, over the pixels where the sum is below 250 in
/// every channel (not clipped).
struct SumDifference {
    int max_lsb = 0;
    std::size_t compared = 0;
    std::size_t over2 = 0;  ///< pixels off by more than 2 steps
};
SumDifference sum_difference(const std::vector<std::uint8_t>& both,
                             const std::vector<std::uint8_t>& a,
                             const std::vector<std::uint8_t>& b) {
    SumDifference d;
    for (std::size_t p = 0; p + 3 < both.size(); p += 4) {
        int sum[3], largest = 0;
        for (std::size_t c = 0; c < 3; ++c) {
            sum[c] = int(a[p + c]) + int(b[p + c]);
            largest = std::max(largest, sum[c]);
        }
        if (largest >= 250) continue;
        ++d.compared;
        int worst = 0;
        for (std::size_t c = 0; c < 3; ++c) worst = std::max(worst, std::abs(both[p + c] - sum[c]));
        d.max_lsb = std::max(d.max_lsb, worst);
        if (worst > 2) ++d.over2;
    }
    return d;
}

TEST_F(TwoLightsTest, EachFrameTakesTheLightsThatReachHalfAStep) {
    auto r = make(Backend::cpu);
    ASSERT_TRUE(r);
    FrameReport report;
    // Night: the sun 25 degrees down gives nothing at the moon's exposure.
    frame(*r, moonlit_settings(-25.0, kFullMoon), &report);
    EXPECT_EQ(report.lights, Lights::moon);
    // Twilight at the same exposure: the sun's sky and the moon's light both count.
    frame(*r, moonlit_settings(-7.0, kFullMoon), &report);
    EXPECT_EQ(report.lights, Lights::both);
    EXPECT_EQ(report.cache_hits, 0u);
    // Day at a day's exposure: the moon is far below a step.
    FrameSettings day = moonlit_settings(40.0, kFullMoon);
    day.display.exposure = 20.0f;
    frame(*r, day, &report);
    EXPECT_EQ(report.lights, Lights::sun);
    // No moon, or a new one: the sun.
    day.moon->fraction = 0.0;
    frame(*r, day, &report);
    EXPECT_EQ(report.lights, Lights::sun);
    // The policy off takes every light given.
    FrameSettings all = moonlit_settings(-25.0, kFullMoon);
    all.policy = false;
    frame(*r, all, &report);
    EXPECT_EQ(report.lights, Lights::both);
    EXPECT_STREQ(lights_name(Lights::both), "both");
}

/// A frame lit by both is the frame lit by the sun plus the frame lit by the moon: within 4 steps
/// and 2 at 99 % of the pixels (each of the three frames rounds its own colours; the cubemap's
/// texels are rounded before GL filters them).
void expect_sum(TwoLightsTest& t, SceneRenderer& r, const char* what) {
    // A bright moon in late twilight: both lights of the same order.
    FrameSettings both = moonlit_settings(-6.5, 40.0 * kFullMoon);
    both.policy = false;
    both.display.exposure *= 0.25f;  // no lit colour clipped (the texture multiplies it after)
    FrameReport report;
    const auto a = t.frame(r, sun_alone(both));
    const auto b = t.frame(r, moon_alone(both));
    const auto ab = t.frame(r, both, &report);
    EXPECT_EQ(report.lights, Lights::both) << what;
    const SumDifference d = sum_difference(ab, a, b);
    printf("%s: sum within %d steps, %zu of %zu pixels over 2\n", what, d.max_lsb, d.over2,
           d.compared);
    EXPECT_LE(d.max_lsb, 4) << what;
    EXPECT_LE(d.over2, d.compared / 100) << what;
    EXPECT_GT(d.compared, std::size_t(kWidth * kHeight) * 3 / 4) << what << ": mostly unclipped";
    // Both lights matter in this frame: each alone differs from the sum.
    EXPECT_GT(aerial_test::compare_rgb(ab, a).max_lsb, 8) << what;
    EXPECT_GT(aerial_test::compare_rgb(ab, b).max_lsb, 8) << what;
}

TEST_F(TwoLightsTest, BothLightsAreTheSumOfEachOnTheCpuBackend) {
    auto r = make(Backend::cpu);
    ASSERT_TRUE(r);
    expect_sum(*this, *r, "cpu, dome");
    if (!aerial::gl::cube_maps_supported(gl())) return;
    auto cubemap = make(Backend::cpu);
    ASSERT_TRUE(cubemap);
    CubemapSkyOptions options;
    options.cache.spread_updates = 1;
    ASSERT_TRUE(install_cubemap_sky(*cubemap, gl(), options));
    expect_sum(*this, *cubemap, "cpu, cubemap");
}

TEST_F(TwoLightsTest, BothLightsAreTheSumOfEachOnTheArbBackendInTwoPasses) {
    if (!gl().caps.vertex_program) GTEST_SKIP() << "no GL_ARB_vertex_program";
    auto r = make(Backend::arb);
    ASSERT_TRUE(r);
    expect_sum(*this, *r, "arb");
    // The second pass is drawn and every piece of GL state is put back.
    const auto before = aerial::gl::capture_state(gl());
    FrameSettings both = moonlit_settings(-6.5, 40.0 * kFullMoon);
    both.policy = false;
    FrameReport report;
    frame(*r, both, &report);
    const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
    EXPECT_TRUE(changed.empty()) << changed.front();
    EXPECT_EQ(report.vertices_shaded, 2 * report.vertices_drawn);
}

/// A light the rule leaves out changes no pixel by more than a step (policy on and off, with
/// an error target of 0 so that the policy takes no cheaper model).
TEST_F(TwoLightsTest, ALeftOutLightChangesTheFrameByAtMostOneStep) {
    for (Backend backend : {Backend::cpu, Backend::arb}) {
        if (backend == Backend::arb && !gl().caps.vertex_program) continue;
        auto r = make(backend);
        ASSERT_TRUE(r);
        // Night (the sun 25 degrees down) at the moon's exposure; day at a day's.
        for (double sun_deg : {-25.0, 40.0}) {
            FrameSettings on = moonlit_settings(sun_deg, kFullMoon);
            if (sun_deg > 0.0) on.display.exposure = 20.0f;
            on.error_target_lsb = 0.0;
            FrameSettings off = on;
            off.policy = false;
            FrameReport report;
            const auto a = frame(*r, on, &report);
            ASSERT_EQ(report.lights, sun_deg > 0.0 ? Lights::sun : Lights::moon)
                << backend_name(backend) << " " << sun_deg;
            const auto b = frame(*r, off, &report);
            ASSERT_EQ(report.lights, Lights::both);
            const auto d = aerial_test::compare_rgb(a, b);
            printf("%s, sun %.0f deg: one light against both within %d steps\n",
                   backend_name(backend), sun_deg, d.max_lsb);
            EXPECT_LE(d.max_lsb, 1)
                << backend_name(backend) << ", sun " << sun_deg << " deg: pixel " << d.pixel;
        }
    }
}

TEST_F(TwoLightsTest, TheAdaptiveSkyAddsTheMoonsSky) {
    auto r = make(Backend::cpu);
    ASSERT_TRUE(r);
    auto stats = std::make_shared<AdaptiveSkyStats>();
    r->set_sky_drawer(adaptive_sky_drawer({}, stats));
    FrameSettings both = moonlit_settings(-6.5, 40.0 * kFullMoon);
    both.policy = false;
    both.display.exposure *= 0.25f;
    const auto a = frame(*r, sun_alone(both));
    const auto ab = frame(*r, both);
    EXPECT_TRUE(stats->error.empty()) << stats->error;
    // The top row is sky: brighter with the moon's sky added.
    double sun = 0.0, sum = 0.0;
    for (int x = 0; x < kWidth; ++x) {
        const std::size_t p = 4 * (std::size_t(kHeight - 1) * kWidth + std::size_t(x));
        sun += a[p] + a[p + 1] + a[p + 2];
        sum += ab[p] + ab[p + 1] + ab[p + 2];
    }
    EXPECT_GT(sum, sun + 3.0 * kWidth) << "at least a step a channel brighter";
}

TEST_F(TwoLightsTest, TheMoonLightsTheTerrainAtNight) {
    auto r = make(Backend::cpu);
    ASSERT_TRUE(r);
    FrameSettings night = moonlit_settings(-25.0, kFullMoon);
    const auto lit = frame(*r, night, nullptr);
    night.moon->fraction = 0.0;
    const auto dark = frame(*r, night, nullptr);
    // The lower rows (terrain): moonlit, readable; without the moon, black.
    double moonlit = 0.0, moonless = 0.0;
    for (int x = 0; x < kWidth; ++x) {
        const std::size_t p = 4 * (std::size_t(kHeight - 4) * kWidth + std::size_t(x));
        moonlit += lit[p] + lit[p + 1] + lit[p + 2];
        moonless += dark[p] + dark[p + 1] + dark[p + 2];
    }
    EXPECT_GT(moonlit / (3.0 * kWidth), 20.0);
    EXPECT_LT(moonless / (3.0 * kWidth), 2.0);
}

TEST_F(TwoLightsTest, BadMoonIsAnErrorNamingTheField) {
    auto r = make(Backend::cpu);
    ASSERT_TRUE(r);
    FrameSettings s = moonlit_settings(-25.0, kFullMoon);
    s.moon->dir = {std::nan(""), 0.0, 1.0};
    auto result = r->render(*scene_.root, night_camera(), s);
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().field, "moon.dir") << result.error().message;
    s = moonlit_settings(-25.0, kFullMoon);
    s.moon->fraction = -1.0;
    result = r->render(*scene_.root, night_camera(), s);
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().field, "moon.fraction");
    EXPECT_NE(result.error().message.find("got -1"), std::string::npos) << result.error().message;
    s.moon->fraction = 0.5;
    result = r->render(*scene_.root, night_camera(), s);
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().field, "moon.fraction");
}

}  // namespace
