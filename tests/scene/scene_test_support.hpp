// What the scene tests that draw share (test_scene_renderer, test_adaptive_scene,
// test_robustness): a camera for the test's viewport, the hazy frame they shade, and a fixture
// that names the context it draws on and draws one frame of a scene onto a cleared image.
#pragma once

#include <cstdint>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/scene_renderer.hpp"
#include "gl_test_context.hpp"

namespace aerial_test {

/// A camera at `eye` looking at `target` (+Z up, the default field of view) for a viewport of
/// `aspect` = width / height.
inline aerial::scene::Camera scene_camera(const glm::dvec3& eye, const glm::dvec3& target,
                                          double aspect, double near_units = 1.0,
                                          double far_units = 30000.0) {
    aerial::scene::Camera c;
    c.eye = eye;
    c.target = target;
    c.aspect = aspect;
    c.near_units = near_units;
    c.far_units = far_units;
    return c;
}

/// Hazy air (the "hazy" preset) at exposure 8 with the sun towards `sun` (normalised here),
/// shaded to the height model.
inline aerial::scene::FrameSettings hazy_frame(const glm::dvec3& sun) {
    aerial::scene::FrameSettings s;
    s.atmosphere = aerial::atmosphere_preset("hazy").value();
    s.sun_dir = glm::normalize(sun);
    s.display.exposure = 8.0f;
    s.model = aerial::Model::height;
    return s;
}

/// DrawingTest that prints the context it runs on and draws scenes.
template <int Width, int Height>
class SceneDrawingTest : public DrawingTest<Width, Height> {
  protected:
    void SetUp() override {
        DrawingTest<Width, Height>::SetUp();
        if (this->ctx_) std::printf("context: %s\n", context_label(*this->ctx_).c_str());
    }

    /// One frame of `root` drawn by `r` on a black, cleared image filling the viewport; fails
    /// the test when rendering fails. With `report`, the frame's report is copied there.
    std::vector<std::uint8_t> draw(aerial::scene::SceneRenderer& r, const aerial::scene::Node& root,
                                   const aerial::scene::Camera& camera,
                                   const aerial::scene::FrameSettings& settings,
                                   aerial::scene::FrameReport* report = nullptr) {
        const aerial::gl::Api& gl = this->gl();
        gl.ClearColor(0, 0, 0, 1);
        gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        gl.Viewport(0, 0, Width, Height);
        auto result = r.render(root, camera, settings);
        EXPECT_TRUE(result) << result.error().message;
        if (result && report) *report = *result;
        gl.Finish();
        return this->ctx_->read_rgba8();
    }
};

}  // namespace aerial_test
