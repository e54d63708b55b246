// Coordinate conventions: the module takes any up axis and either handedness. A scene in a
// left-handed, Y-up world (Irrlicht, Direct3D-style engines) is the mirror image of a right-handed,
// Z-up one: its positions, eye, target, sun and up are those of the twin with y and z swapped.
// Shading depends only on distances, angles and altitudes along `up`, which the mirror keeps, and
// a right-handed look-at of mirrored points sees the twin's image flipped left to right. So the
// two frames must agree pixel for pixel once one of them is flipped, through every backend.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/mat4x4.hpp>

#include "aerial/scene_file.hpp"
#include "aerial/scene_renderer.hpp"
#include "gl_test_context.hpp"

namespace {

using aerial::scene::Backend;
using aerial::scene::Camera;
using aerial::scene::FrameSettings;
using aerial::scene::RendererOptions;
using aerial::scene::SceneRenderer;

constexpr int kWidth = 160, kHeight = 120;

/// (x, y, z) -> (x, z, y): a right-handed Z-up world as a left-handed Y-up one.
const glm::dmat4 kSwapYZ(1, 0, 0, 0,  //
                         0, 0, 1, 0,  //
                         0, 1, 0, 0,  //
                         0, 0, 0, 1);

glm::dvec3 mirrored(const glm::dvec3& v) { return glm::dvec3(kSwapYZ * glm::dvec4(v, 0.0)); }

std::vector<std::uint8_t> flipped_left_to_right(const std::vector<std::uint8_t>& rgba) {
    std::vector<std::uint8_t> out(rgba.size());
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            std::copy_n(&rgba[4 * (std::size_t(y) * kWidth + x)], 4,
                        &out[4 * (std::size_t(y) * kWidth + (kWidth - 1 - x))]);
        }
    }
    return out;
}

class Conventions : public aerial_test::DrawingTest<kWidth, kHeight> {
  protected:
    /// One frame of the scene file through `backend`, mirrored into a Y-up left-handed world or
    /// not.
    std::vector<std::uint8_t> frame(const aerial::scene::SceneFile& file, Backend backend,
                                    bool y_up_left_handed) {
        RendererOptions options;
        options.backend = backend;
        auto renderer = SceneRenderer::create(gl(), options);
        EXPECT_TRUE(renderer) << renderer.error().message;
        if (!renderer) return {};
        auto root = aerial::scene::scene_graph(file);
        Camera camera = file.camera_for(kWidth, kHeight);
        FrameSettings settings = file.frame_settings();
        if (y_up_left_handed) {
            root->transform = kSwapYZ * root->transform;
            camera.eye = mirrored(camera.eye);
            camera.target = mirrored(camera.target);
            camera.up = mirrored(camera.up);
            settings.up = mirrored(settings.up);
            settings.sun_dir = mirrored(settings.sun_dir);
        }
        gl().Viewport(0, 0, kWidth, kHeight);
        gl().ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        auto report = renderer.value().render(*root, camera, settings);
        EXPECT_TRUE(report) << report.error().message;
        return ctx_->read_rgba8();
    }
};

TEST_F(Conventions, AYUpLeftHandedSceneIsTheMirrorImageOfItsZUpRightHandedTwin) {
    const auto file = aerial::scene::load_scene_file(AERIAL_CONVENTIONS_SCENE);
    ASSERT_TRUE(file) << file.error().message;
    std::vector<Backend> backends{Backend::cpu};
    if (gl().caps.vertex_program) backends.push_back(Backend::arb);
    for (Backend backend : backends) {
        SCOPED_TRACE(backend == Backend::cpu ? "cpu" : "arb");
        const auto z_up = frame(*file, backend, false);
        const auto y_up = flipped_left_to_right(frame(*file, backend, true));
        ASSERT_EQ(z_up.size(), y_up.size());
        const auto d = aerial_test::compare_rgb(z_up, y_up);
        // The vertex colours agree (within float rounding of the swapped components), and so do
        // the pixels but for two effects that are not mirror-symmetric in the rasteriser: its
        // interpolation rounds a pixel's colour one step either way (measured: 4 % of the pixels
        // on llvmpipe), and where an edge crosses a pixel centre exactly its fill rule gives the
        // pixel to the other triangle.
        EXPECT_LE(d.over1, std::size_t(kWidth * kHeight / 1000))
            << d.over1 << " pixels differ by more than one step; worst " << d.max_lsb
            << " at pixel " << d.pixel << ": " << aerial_test::pixel_text(z_up, d.pixel)
            << " against " << aerial_test::pixel_text(y_up, d.pixel);
        EXPECT_LE(d.differ, std::size_t(kWidth * kHeight / 10)) << d.differ << " pixels differ";
        std::printf("  %s: %zu pixels differ, %zu by more than one step, worst %d\n",
                    backend == Backend::cpu ? "cpu" : "arb", d.differ, d.over1, d.max_lsb);
        std::size_t lit = 0;
        for (std::size_t p = 0; p < z_up.size(); p += 4) lit += z_up[p] + z_up[p + 1] > 0;
        EXPECT_GT(lit, std::size_t(kWidth * kHeight / 2)) << "the frame shows the scene";
    }
}

}  // namespace
