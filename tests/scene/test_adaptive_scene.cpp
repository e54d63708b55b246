// Adaptive meshes in the scene graph (aerial/adaptive_scene.hpp): OpenMesh meshes as MeshData,
// an adaptive terrain node refined, morphed, shaded and drawn by SceneRenderer (the image once
// refinement and morph settle equals that of a plain node of the same mesh), the adaptive sky
// drawer, and the errors of both.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "aerial/adaptive_scene.hpp"
#include "aerial/scene_renderer.hpp"
#include "gl_test_context.hpp"
#include "scene_test_support.hpp"

namespace {

using namespace aerial::scene;
namespace mesh = aerial::mesh;

constexpr int kWidth = 128, kHeight = 72;
constexpr int kMorphUpdates = 3;

mesh::Heightfield hills() { return mesh::rolling_hills(-4000.0, 0.0, 8000.0, 120.0, 1500.0); }

std::shared_ptr<mesh::AdaptiveMesh> adaptive_hills() {
    const mesh::Heightfield field = hills();
    auto base = mesh::terrain_grid(field, 4, 4);
    EXPECT_TRUE(base) << base.error().message;
    mesh::AdaptiveSettings settings;
    settings.split_lsb = 1.0f;
    settings.morph_updates = kMorphUpdates;
    settings.max_vertices = 3000;
    settings.time_slice_ms = 0.0;
    settings.colour.texel = glm::vec3(0.8f);
    settings.colour.display.exposure = 8.0f;
    auto adaptive = mesh::AdaptiveMesh::create(std::move(base.value()),
                                               mesh::Surface::terrain(field), settings);
    EXPECT_TRUE(adaptive) << adaptive.error().message;
    return std::make_shared<mesh::AdaptiveMesh>(std::move(adaptive.value()));
}

std::shared_ptr<const Texture> grey_texture() {
    auto t = std::make_shared<Texture>();
    t->width = t->height = 2;
    t->rgb.assign(12, 204);
    return t;
}

Camera low_camera() {
    return aerial_test::scene_camera({0.0, 200.0, 150.0}, {0.0, 8000.0, 0.0},
                                     double(kWidth) / kHeight, 5.0, 20000.0);
}

FrameSettings hazy_settings() {
    FrameSettings s = aerial_test::hazy_frame({0.2, 0.6, 0.3});
    s.policy = false;
    s.ambient = glm::vec3(0.02f);
    return s;
}

TEST(MeshDataFrom, KeepsEverySlotTheLiveFacesAndGivesTexcoordsAndNormals) {
    mesh::Heightfield flat;
    flat.height_m = [](double, double) { return 5.0; };
    flat.size_x_m = flat.size_y_m = 100.0;
    auto grid = mesh::terrain_grid(flat, 2, 2);
    ASSERT_TRUE(grid);
    const MeshData plain = mesh_data_from(*grid);
    EXPECT_EQ(plain.vertex_count(), 9u);
    EXPECT_EQ(plain.indices.size(), 8u * 3u);
    EXPECT_TRUE(plain.texcoords.empty());
    EXPECT_TRUE(plain.normals.empty());
    EXPECT_FALSE(validate(plain));

    const MeshData full = mesh_data_from(*grid, 50.0, true);
    ASSERT_EQ(full.texcoords.size(), 2u * 9u);
    for (std::size_t i = 0; i < 9; ++i) {
        EXPECT_FLOAT_EQ(full.texcoords[2 * i], full.positions[3 * i] / 50.0f);
        EXPECT_FLOAT_EQ(full.texcoords[2 * i + 1], full.positions[3 * i + 1] / 50.0f);
        // A flat field: every normal is +z (the faces are counter-clockwise seen from above).
        EXPECT_NEAR(full.normals[3 * i + 2], 1.0f, 1e-6f) << "vertex " << i;
    }

    // A deleted face is left out, its vertices stay (index = vertex handle).
    mesh::Mesh m = *grid;
    m.delete_face(*m.faces_begin(), false);
    const MeshData without = mesh_data_from(m);
    EXPECT_EQ(without.vertex_count(), 9u);
    EXPECT_EQ(without.indices.size(), 7u * 3u);
}

class AdaptiveSceneTest : public aerial_test::SceneDrawingTest<kWidth, kHeight> {
  protected:
    std::vector<std::uint8_t> draw(SceneRenderer& r, const Node& root, FrameReport* report) {
        return SceneDrawingTest::draw(r, root, low_camera(), hazy_settings(), report);
    }

    /// The adaptive mesh as it is now, as a plain terrain node drawn by a fresh renderer.
    std::vector<std::uint8_t> draw_plain(const mesh::AdaptiveMesh& adaptive) {
        auto root = make_group("world");
        root->add(make_terrain_tile(
            "hills", std::make_shared<MeshData>(mesh_data_from(adaptive.mesh(), 250.0, true)),
            grey_texture(), glm::vec3(0.3f)));
        auto fresh = SceneRenderer::create(gl());
        EXPECT_TRUE(fresh) << fresh.error().message;
        return fresh ? draw(fresh.value(), *root, nullptr) : std::vector<std::uint8_t>{};
    }
};

TEST_F(AdaptiveSceneTest, TheRendererRefinesMorphsAndDrawsAnAdaptiveTerrain) {
    auto adaptive = adaptive_hills();
    const std::size_t base_vertices = adaptive->mesh().n_vertices();
    auto root = make_group("world");
    root->add(make_adaptive_terrain("hills", adaptive, grey_texture(), 250.0, glm::vec3(0.3f)));
    auto renderer = SceneRenderer::create(gl());
    ASSERT_TRUE(renderer) << renderer.error().message;

    FrameReport first;
    draw(renderer.value(), *root, &first);
    ASSERT_EQ(first.nodes.size(), 1u);
    EXPECT_EQ(first.nodes[0].method, Method::height);
    EXPECT_GT(adaptive->mesh().n_vertices(), base_vertices) << "the first frame refined nothing";
    EXPECT_EQ(first.nodes[0].vertices, adaptive->mesh().n_vertices());

    // Same view: refinement finishes and every new vertex blends in within morph_updates frames.
    std::vector<std::uint8_t> settled;
    for (int i = 0; i < 4 * kMorphUpdates; ++i) settled = draw(renderer.value(), *root, nullptr);
    const std::size_t before = adaptive->mesh().n_vertices();
    FrameReport again;
    const auto last = draw(renderer.value(), *root, &again);
    EXPECT_EQ(adaptive->mesh().n_vertices(), before) << "refinement did not settle";
    EXPECT_EQ(aerial_test::compare_rgb(last, settled).max_lsb, 0);

    // What it shows then: a plain terrain node of the same mesh, drawn by a fresh renderer.
    const auto plain = draw_plain(*adaptive);
    const auto d = aerial_test::compare_rgb(last, plain);
    EXPECT_EQ(d.max_lsb, 0) << "at pixel " << d.pixel << ": adaptive "
                            << aerial_test::pixel_text(last, d.pixel) << ", plain "
                            << aerial_test::pixel_text(plain, d.pixel);
}

TEST_F(AdaptiveSceneTest, NewVerticesMorphInRatherThanPop) {
    auto adaptive = adaptive_hills();
    auto root = make_group("world");
    root->add(make_adaptive_terrain("hills", adaptive, grey_texture(), 250.0, glm::vec3(0.3f)));
    auto renderer = SceneRenderer::create(gl());
    ASSERT_TRUE(renderer);
    // Unrefined, the plain base mesh; after one adaptive frame the image has barely moved from
    // it (new vertices start at the colour interpolated from their parents), and it reaches the
    // refined image over the morph.
    const auto base = draw_plain(*adaptive);
    const auto first = draw(renderer.value(), *root, nullptr);
    std::vector<std::uint8_t> settled;
    for (int i = 0; i < 4 * kMorphUpdates; ++i) settled = draw(renderer.value(), *root, nullptr);
    // Colours only: where refinement moved the silhouette, terrain meets the black background.
    // The mean over the pixels terrain covers in both: a few pixels where refinement moved one
    // hill in front of another change as much in the first frame as later.
    auto colour_change = [&base](const std::vector<std::uint8_t>& image) {
        double sum = 0.0;
        long count = 0;
        for (std::size_t p = 0; 4 * p + 3 < std::min(image.size(), base.size()); ++p) {
            const bool both = (image[4 * p] | image[4 * p + 1] | image[4 * p + 2]) != 0 &&
                              (base[4 * p] | base[4 * p + 1] | base[4 * p + 2]) != 0;
            for (std::size_t c = 0; both && c < 3; ++c) {
                sum += std::abs(int(image[4 * p + c]) - int(base[4 * p + c]));
                ++count;
            }
        }
        return count > 0 ? sum / double(count) : 0.0;
    };
    const double first_to_base = colour_change(first);
    const double settled_to_base = colour_change(settled);
    std::printf("mean colour change from the base mesh: first frame %.3f, settled %.3f steps\n",
                first_to_base, settled_to_base);
    EXPECT_GT(settled_to_base, 0.05)
        << "refinement changed nothing visible: the test shows nothing";
    EXPECT_LT(first_to_base, 0.5 * settled_to_base);
}

TEST_F(AdaptiveSceneTest, AnAdaptiveNodeUnderATransformIsAnErrorNamingIt) {
    auto root = make_group("world");
    Node* group = root->add(make_group("moved"));
    group->transform[3][0] = 10.0;
    group->add(make_adaptive_mesh("hills", adaptive_hills()));
    auto renderer = SceneRenderer::create(gl());
    ASSERT_TRUE(renderer);
    auto result = renderer.value().render(*root, low_camera(), hazy_settings());
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().field, "hills");
    EXPECT_EQ(result.error().message,
              "aerial::scene::SceneRenderer::render(): hills: expected the identity as the world "
              "transform (an adaptive node is refined in world coordinates), got another "
              "transform");
}

TEST(AdaptiveSceneGraph, ValidateNamesAnAdaptiveNodeOfTheWrongKindOrABadRepeat) {
    auto root = make_group("world");
    Node* sky = root->add(make_sky_dome());
    sky->adaptive = adaptive_hills();
    auto e = validate(*root);
    ASSERT_TRUE(e);
    EXPECT_NE(e->message.find("world/sky"), std::string::npos) << e->message;

    auto root2 = make_group("world");
    root2->add(make_adaptive_mesh("hills", adaptive_hills(), nullptr, -1.0));
    auto e2 = validate(*root2);
    ASSERT_TRUE(e2);
    EXPECT_NE(e2->message.find("texture_repeat"), std::string::npos) << e2->message;
}

TEST_F(AdaptiveSceneTest, TheAdaptiveSkyFillsItsStatsAndNamesABadOption) {
    auto root = make_group("world");
    root->add(make_sky_dome());
    auto renderer = SceneRenderer::create(gl());
    ASSERT_TRUE(renderer);
    auto stats = std::make_shared<AdaptiveSkyStats>();
    renderer.value().set_sky_drawer(adaptive_sky_drawer({}, stats));
    const auto image = draw(renderer.value(), *root, nullptr);
    EXPECT_TRUE(stats->error.empty()) << stats->error;
    EXPECT_GT(stats->vertices, 41u) << "the geodesic dome of frequency 4 was not refined";
    // The sky covers the upper half of the view.
    EXPECT_GT(int(image[4 * (kWidth / 2) + 2]), 0);

    AdaptiveSkyOptions bad;
    bad.skirt_depression_deg = 120.0;
    auto bad_stats = std::make_shared<AdaptiveSkyStats>();
    renderer.value().set_sky_drawer(adaptive_sky_drawer(bad, bad_stats));
    draw(renderer.value(), *root, nullptr);
    EXPECT_NE(bad_stats->error.find("skirt_depression_deg"), std::string::npos) << bad_stats->error;
}

}  // namespace
