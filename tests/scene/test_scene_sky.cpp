// The scene renderer's built-in sky dome and sky ambient without a GL context: the dome is the
// core sky (make_sky_dome_mesh, shade_sky_dome of prepare_sky, the method per model) with a skirt,
// its virtual dome is fitted again only beyond the refit rule, and the ambient is
// aerial::sky_ambient at sea level, estimated again only when the sun turns a quarter degree.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/scene_renderer.hpp"
#include "aerial/sky.hpp"
#include "aerial/sun.hpp"
#include "frame_plan.hpp"
#include "sky_dome.hpp"

namespace {

using aerial::Model;
using aerial::SkyMethod;
using aerial::scene::detail::SkyDome;

constexpr double kDeg = aerial::kPi / 180.0;

aerial::scene::FrameSettings settings_with_sun(double elevation_deg, Model model) {
    aerial::scene::FrameSettings s;
    const double e = elevation_deg * kDeg;
    s.sun_dir = {0.6 * std::cos(e), 0.8 * std::cos(e), std::sin(e)};
    s.display.exposure = 8.0f;
    s.model = model;
    return s;
}

aerial::View view_of(const aerial::scene::FrameSettings& s, const glm::dvec3& eye) {
    aerial::View v;
    v.eye = eye;
    v.sun_dir = s.sun_dir;
    v.up = s.up;
    v.meters_per_unit = s.meters_per_unit;
    return v;
}

TEST(SceneSkyDome, ColoursAreTheCoreSkysShadeSkyDomeWithTheMethodOfTheModel) {
    const glm::dvec3 eye{0.0, 0.0, 300.0};
    for (Model model : {Model::hoffman_preetham, Model::height, Model::reference}) {
        const auto s = settings_with_sun(8.0, model);
        SkyDome dome(aerial::kSkyDomeRings, aerial::kSkyDomeSegments);
        auto sky = dome.prepare(s, eye);
        ASSERT_TRUE(sky.ok()) << sky.error().message;
        const SkyMethod expected =
            model == Model::height ? SkyMethod::dome_height : SkyMethod::dome_hp;
        EXPECT_EQ(sky->method, expected) << aerial::model_name(model);
        const std::vector<std::uint8_t>& colours = dome.shade(*sky, s.display);

        // The same dome from the core alone: a fresh prepare_sky (its own fit) and mesh.
        auto core = aerial::prepare_sky(s.atmosphere, view_of(s, eye), expected);
        ASSERT_TRUE(core.ok());
        auto mesh = aerial::make_sky_dome_mesh(aerial::kSkyDomeRings, aerial::kSkyDomeSegments);
        ASSERT_TRUE(mesh.ok());
        const std::vector<glm::dvec3> radiance = aerial::shade_sky_dome(*core, *mesh);
        const std::size_t n = mesh->directions.size(), segments = std::size_t(mesh->segments);
        ASSERT_EQ(dome.directions().size(), n + segments);
        ASSERT_EQ(colours.size(), 4 * (n + segments));
        for (std::size_t v = 0; v < n + segments; ++v) {
            // The skirt (after the mesh) repeats ring 0 (the mesh's first vertices).
            const glm::dvec3& l = radiance[v < n ? v : v - n];
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(colours[4 * v + std::size_t(c)],
                          aerial::to_unorm8(aerial::display_value(s.display, float(l[c]))))
                    << "vertex " << v << " channel " << c;
            }
            ASSERT_EQ(colours[4 * v + 3], 255);
        }
        for (std::size_t v = 0; v < n; ++v) {
            EXPECT_LT(glm::length(dome.directions()[v] - mesh->directions[v]), 1e-12);
        }
        for (std::size_t j = 0; j < segments; ++j) {
            const glm::dvec3 d = dome.directions()[n + j];
            EXPECT_NEAR(std::asin(d.z), aerial::scene::detail::kSkirtElevationRad, 1e-12);
            EXPECT_LT(glm::length(glm::normalize(glm::dvec3(d.x, d.y, 0.0)) - mesh->directions[j]),
                      1e-12);
        }
        EXPECT_EQ(dome.indices().size(), mesh->indices.size() + 6 * segments);
    }
}

TEST(SceneSkyDome, RefitsOnlyWhenTheAtmosphereChangesOrTheEyeMovesMoreThan25m) {
    auto s = settings_with_sun(30.0, Model::hoffman_preetham);
    SkyDome dome(aerial::kSkyDomeRings, aerial::kSkyDomeSegments);
    ASSERT_TRUE(dome.prepare(s, {0.0, 0.0, 100.0}).ok());
    EXPECT_EQ(dome.fits(), 1);
    ASSERT_TRUE(dome.prepare(s, {500.0, -200.0, 120.0}).ok());  // 20 m up, anywhere level
    s.sun_dir = glm::normalize(glm::dvec3(0.1, 0.2, 1.0));      // the sun plays no part
    ASSERT_TRUE(dome.prepare(s, {0.0, 0.0, 80.0}).ok());
    EXPECT_EQ(dome.fits(), 1);
    ASSERT_TRUE(dome.prepare(s, {0.0, 0.0, 130.0}).ok());  // 30 m from the fit at 100 m
    EXPECT_EQ(dome.fits(), 2);
    s.atmosphere.mie_g = 0.7;
    ASSERT_TRUE(dome.prepare(s, {0.0, 0.0, 130.0}).ok());
    EXPECT_EQ(dome.fits(), 3);
    // height needs no virtual dome.
    s.model = Model::height;
    ASSERT_TRUE(dome.prepare(s, {0.0, 0.0, 5000.0}).ok());
    EXPECT_EQ(dome.fits(), 3);
}

TEST(SceneSkyAmbient, IsTheCoreSkyAmbientAtSeaLevelWhateverTheModel) {
    aerial::scene::detail::SkyAmbientCache cache;
    auto s = settings_with_sun(20.0, Model::height);
    s.ambient = glm::vec3(-1.0f);
    const glm::vec3 ambient = aerial::scene::detail::frame_ambient(cache, s);
    aerial::SkyAmbientOptions options;
    options.elevation_steps = 8;
    options.azimuth_steps = 16;
    const auto core = aerial::sky_ambient(s.atmosphere, 0.0, 20.0 * kDeg, options);
    ASSERT_TRUE(core.ok());
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ambient[c], float((*core)[c]), 1e-6f * ambient[c]);
    EXPECT_GT(ambient.b, ambient.r) << "blue skylight";
    // The model no longer matters; a 0.1 deg turn keeps the estimate, 0.3 deg makes a new one.
    s.model = Model::hoffman_preetham;
    EXPECT_EQ(aerial::scene::detail::frame_ambient(cache, s), ambient);
    const auto turned = [&](double elevation_deg) {
        auto t = s;
        t.sun_dir = settings_with_sun(elevation_deg, s.model).sun_dir;
        return aerial::scene::detail::frame_ambient(cache, t);
    };
    EXPECT_EQ(turned(20.1), ambient);
    EXPECT_NE(turned(20.3), ambient);
    // A given ambient is used as it is.
    s.ambient = glm::vec3(0.01f, 0.02f, 0.03f);
    EXPECT_EQ(aerial::scene::detail::frame_ambient(cache, s), s.ambient);
}

}  // namespace
