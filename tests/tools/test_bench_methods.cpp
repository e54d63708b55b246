// aerial-bench's two extra methods (tools/bench/methods.hpp): FlightGear's fog function and the
// lookup-texture path of the 2002 talk — the closed forms, the images against the per-vertex
// CPU path, and that both put back every piece of GL state they change.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "aerial/aerial.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/headless.hpp"
#include "aerial/scene_file.hpp"
#include "aerial/validation/scene_render.hpp"
#include "bench/frame_gl.hpp"
#include "bench/methods.hpp"

namespace {

using aerial::bench::FlightGearFog;
using aerial::bench::LutTexture;

constexpr int kWidth = 96, kHeight = 64;
/// Largest difference of the lookup-texture image from the per-vertex colours of the same model
/// (2 measured on llvmpipe, plus one step for other rasterisers' filter weights).
constexpr int kLutToleranceLsb = 3;
/// fg-fog against exp(-x - x^4) evaluated where the pixel's ray meets the ground: the fog
/// coordinate is interpolated between vertices 830 m apart (2 measured on llvmpipe, plus one).
constexpr int kFogToleranceLsb = 3;

// A flat ground seen from 300 m, the sun 30 deg up beside the view: distances of 0.3 to 20 km.
constexpr const char* kScene = R"({
  "camera": {"eye": [0, -10000, 300], "look_at": [0, 0, 0], "near": 10, "far": 40000},
  "sun": {"elevation_deg": 30, "azimuth_deg": 40},
  "atmosphere": "earth", "model": "hoffman-preetham",
  "display": {"exposure": 12, "tone": "clamp"},
  "texture": {"kind": "checker", "size": 64, "cells": 8},
  "terrain": {"size": 40000, "resolution": 48, "height_amplitude": 0, "texture_repeat": 2000}
})";

TEST(FlightGearFog, FactorIsExpOfMinusXMinusXToTheFourth) {
    const double visibility = 5000.0;
    EXPECT_DOUBLE_EQ(aerial::bench::flightgear_fog_factor(0.0, visibility), 1.0);
    EXPECT_NEAR(aerial::bench::flightgear_fog_factor(visibility, visibility), std::exp(-2.0),
                1e-15);
    EXPECT_NEAR(aerial::bench::flightgear_fog_factor(0.5 * visibility, visibility),
                std::exp(-0.5 - 0.0625), 1e-15);
    EXPECT_NEAR(aerial::bench::flightgear_fog_factor(2.0 * visibility, visibility), std::exp(-18.0),
                1e-20);
    EXPECT_DOUBLE_EQ(aerial::bench::flightgear_fog_factor(1000.0, 0.0), 1.0)
        << "no visibility means no fog, not a division by zero";
}

TEST(FlightGearFog, VisibilityIsOneGreenAttenuationLengthAtTheEye) {
    const aerial::Atmosphere earth = aerial::atmosphere_preset("earth").value();
    aerial::View view;
    view.eye = {0.0, 0.0, 0.0};
    const auto frame = aerial::prepare_frame<float>(earth, view, aerial::Model::height).value();
    const FlightGearFog fog = aerial::bench::flightgear_fog(frame, aerial::Display{8.0f});
    const double extinction_green =
        earth.rayleigh_scattering[1] + earth.mie_scattering[1] + earth.mie_absorption[1];
    EXPECT_NEAR(fog.visibility_m, 1.0 / extinction_green, 1e-3 / extinction_green);
    const aerial::validation::FogParameters gl_fog =
        aerial::validation::fog_parameters(frame, aerial::Display{8.0f});
    for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(fog.colour[c], gl_fog.colour[c]) << "the haze colour of gl-fog, channel " << c;
    }
}

class BenchMethodsGl : public ::testing::Test {
  protected:
    void SetUp() override {
        auto ctx =
            aerial::headless::Context::create({aerial::headless::Platform::osmesa, kWidth, kHeight});
        ASSERT_TRUE(ctx.ok()) << ctx.error().message;
        ctx_.emplace(std::move(ctx).value());
        auto scene = aerial::scene::scene_file_from_json(kScene);
        ASSERT_TRUE(scene.ok()) << scene.error().message;
        scene_ = scene.value();
        mesh_ = aerial::scene::scene_geometry(scene_);
        frame_ = aerial::prepare_frame<float>(scene_.atmosphere, scene_.view(),
                                              aerial::Model::hoffman_preetham)
                     .value();
    }
    const aerial::gl::Api& gl() const { return ctx_->api(); }

    /// Clears, sets the camera and the texture, calls `draw_with` with the mesh's draw, reads
    /// the image back.
    std::vector<std::uint8_t> render(
        const std::function<void(const std::function<void()>&)>& draw_with) {
        const aerial::gl::Api& api = gl();
        api.Viewport(0, 0, kWidth, kHeight);
        api.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        api.Enable(GL_DEPTH_TEST);
        const auto m = aerial::bench::camera_matrices(scene_.camera_for(kWidth, kHeight));
        aerial::bench::load_matrix(api, GL_PROJECTION, m.projection);
        aerial::bench::load_matrix(api, GL_MODELVIEW, m.view);
        const aerial::bench::BoundTexture texture(api,
                                                  aerial::scene::scene_texture(scene_.texture));
        api.Color4f(1.0f, 1.0f, 1.0f, 1.0f);
        draw_with([&] {
            api.EnableClientState(GL_VERTEX_ARRAY);
            api.VertexPointer(3, GL_FLOAT, 0, mesh_.positions.data());
            api.EnableClientState(GL_TEXTURE_COORD_ARRAY);
            api.TexCoordPointer(2, GL_FLOAT, 0, mesh_.texcoords.data());
            api.DrawElements(GL_TRIANGLES, GLsizei(mesh_.indices.size()), GL_UNSIGNED_INT,
                             mesh_.indices.data());
            api.DisableClientState(GL_TEXTURE_COORD_ARRAY);
            api.DisableClientState(GL_VERTEX_ARRAY);
        });
        api.Finish();
        return ctx_->read_rgba8();
    }

    double farthest_m() const {
        double far = 0.0;
        for (std::size_t i = 0; i < mesh_.vertex_count(); ++i) {
            const glm::dvec3 p(mesh_.positions[3 * i], mesh_.positions[3 * i + 1],
                               mesh_.positions[3 * i + 2]);
            far = std::max(far, glm::length(p - scene_.camera.eye));
        }
        return far;
    }

    std::optional<aerial::headless::Context> ctx_;
    aerial::scene::SceneFile scene_;
    aerial::scene::MeshData mesh_;
    aerial::Frame<float> frame_;
};

/// Largest difference over the RGB channels of two RGBA8 images, and how many pixels differ.
std::pair<int, std::size_t> difference(const std::vector<std::uint8_t>& a,
                                       const std::vector<std::uint8_t>& b) {
    int largest = 0;
    std::size_t differing = 0;
    for (std::size_t i = 0; i < a.size(); i += 4) {
        int d = 0;
        for (std::size_t c = 0; c < 3; ++c)
            d = std::max(d, std::abs(int(a[i + c]) - int(b[i + c])));
        largest = std::max(largest, d);
        differing += d > 0;
    }
    return {largest, differing};
}

TEST_F(BenchMethodsGl, LutTextureRejectsModelsItCannotTabulate) {
    auto height =
        aerial::prepare_frame<float>(scene_.atmosphere, scene_.view(), aerial::Model::height)
            .value();
    auto lut = LutTexture::create(gl(), height, scene_.display, 1000.0);
    ASSERT_FALSE(lut.ok());
    EXPECT_EQ(lut.error().field, "model");
    auto no_range = LutTexture::create(gl(), frame_, scene_.display, 0.0);
    ASSERT_FALSE(no_range.ok());
    EXPECT_EQ(no_range.error().field, "max_distance_m");
}

TEST_F(BenchMethodsGl, LutTextureMatchesPerVertexColoursAndRestoresTheState) {
    // The per-vertex CPU path of the same model and mesh.
    const std::size_t n = mesh_.vertex_count();
    std::vector<std::uint8_t> primary(4 * n), secondary(4 * n);
    aerial::BatchOutputs out;
    out.extinction_rgba8 = primary.data();
    out.in_scattering_rgba8 = secondary.data();
    aerial::BatchSettings settings;
    settings.display = scene_.display;
    ASSERT_TRUE(
        aerial::shade_into(frame_, aerial::Positions::aos(mesh_.positions.data(), n), out, settings)
            .ok());
    aerial::gl::VertexColours colours;
    colours.primary = primary.data();
    colours.secondary = secondary.data();
    colours.vertex_count = n;
    const auto cpu = render([&](const std::function<void()>& draw) {
        ASSERT_TRUE(aerial::gl::draw_with_colours(gl(), {}, colours, draw).ok());
    });

    auto lut = LutTexture::create(gl(), frame_, scene_.display, farthest_m());
    ASSERT_TRUE(lut.ok()) << lut.error().message;
    std::vector<float> coords;
    lut->texcoords(frame_, mesh_.positions.data(), n, coords);
    aerial::gl::StateSnapshot before, after;
    const auto table = render([&](const std::function<void()>& draw) {
        before = aerial::gl::capture_state(gl());
        lut->draw(coords.data(), draw);
        after = aerial::gl::capture_state(gl());
    });
    const auto changed = aerial::gl::state_differences(before, after);
    EXPECT_TRUE(changed.empty()) << changed.front();
    // The tables hold the same closed form; they differ from interpolated vertex colours by the
    // 8-bit table entries and filter weights, and where a triangle's colours are not linear.
    const auto [largest, differing] = difference(cpu, table);
    RecordProperty("largest_lsb", largest);
    EXPECT_LE(largest, kLutToleranceLsb) << differing << " pixels differ";
    EXPECT_EQ(GLenum(GL_NO_ERROR), gl().GetError());
}

TEST_F(BenchMethodsGl, FlightGearFogDrawsTheFogFunctionAndRestoresTheState) {
    const auto height =
        aerial::prepare_frame<float>(scene_.atmosphere, scene_.view(), aerial::Model::height)
            .value();
    FlightGearFog fog = aerial::bench::flightgear_fog(height, scene_.display);
    fog.visibility_m = 4000.0;  // distances of 0.3 to 20 km: clear near, cut off far
    std::vector<float> coords;
    aerial::bench::flightgear_fog_coordinates(fog, height, mesh_.positions.data(),
                                              mesh_.vertex_count(), coords);
    const auto plain = render([](const std::function<void()>& draw) { draw(); });
    aerial::gl::StateSnapshot before, after;
    const auto fogged = render([&](const std::function<void()>& draw) {
        before = aerial::gl::capture_state(gl());
        ASSERT_FALSE(aerial::bench::draw_with_flightgear_fog(gl(), fog, coords.data(), draw));
        after = aerial::gl::capture_state(gl());
    });
    const auto changed = aerial::gl::state_differences(before, after);
    EXPECT_TRUE(changed.empty()) << changed.front();
    // Along the middle column: the ground each pixel shows (its ray from the eye meets z = 0),
    // fogged by f = exp(-x - x^4) towards the fog colour.
    const auto m = aerial::bench::camera_matrices(scene_.camera_for(kWidth, kHeight));
    const glm::dmat4 world_from_clip =
        glm::inverse(glm::dmat4(glm::mat4(m.projection)) * glm::dmat4(glm::mat4(m.view)));
    int checked = 0, largest = 0;
    for (int row = 0; row < kHeight; ++row) {  // row 0 is the top
        const double y_ndc = 1.0 - 2.0 * (row + 0.5) / kHeight;
        const glm::dvec4 p = world_from_clip * glm::dvec4(0.0, y_ndc, 1.0, 1.0);
        const glm::dvec3 dir = glm::normalize(glm::dvec3(p) / p.w - scene_.camera.eye);
        if (dir.z >= 0.0) continue;  // sky
        const double distance = -scene_.camera.eye.z / dir.z;
        if (distance > 19000.0) continue;  // beyond the ground's edge
        const double f = aerial::bench::flightgear_fog_factor(distance, fog.visibility_m);
        const std::uint8_t* a = &plain[4 * (std::size_t(row) * kWidth + kWidth / 2)];
        const std::uint8_t* b = &fogged[4 * (std::size_t(row) * kWidth + kWidth / 2)];
        for (int c = 0; c < 3; ++c) {
            const double expected = f * a[c] + (1.0 - f) * 255.0 * double(fog.colour[c]);
            largest = std::max(largest, int(std::lround(std::abs(expected - double(b[c])))));
        }
        ++checked;
    }
    RecordProperty("largest_lsb", largest);
    EXPECT_GT(checked, kHeight / 3);
    EXPECT_LE(largest, kFogToleranceLsb);
    EXPECT_EQ(GLenum(GL_NO_ERROR), gl().GetError());
}

}  // namespace
