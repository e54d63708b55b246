// What an engine that makes its own draw calls needs from the C interface's GL part, on a
// headless context: two passes around the engine's draw call (with aerial's colours or the
// engine's one colour array), the check that reports a draw call that re-pointed aerial's colour
// arrays or changed the L_in pass's state, the state a material system's ARB program needs, and
// the driver's ARB limits with the program level they choose.
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/aerial.h"
#include "aerial/gl_api.hpp"
#include "gl_test_context.hpp"

namespace {

constexpr int kSize = 16;

/// A quad over the whole viewport at depth 0, counter-clockwise (front-facing), and the same
/// quad clockwise (back-facing) at the same depth: what a closed mesh's silhouette looks like to
/// the depth test EQUAL.
constexpr std::array<float, 12> kFront = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
constexpr std::array<float, 12> kBack = {-1, -1, 0, -1, 1, 0, 1, 1, 0, 1, -1, 0};

struct Engine {
    const aerial::gl::Api* api = nullptr;
    bool draw_back_face = false;
    const std::uint8_t* own_colours[2] = {nullptr, nullptr};  ///< per pass, or null: aerial's
    const std::uint8_t* repoint = nullptr;                    ///< the draw sets this colour array
    bool change_blend = false;                                ///< the draw applies a material

    void draw_quads() const {
        api->EnableClientState(GL_VERTEX_ARRAY);
        api->VertexPointer(3, GL_FLOAT, 0, kFront.data());
        api->DrawArrays(GL_QUADS, 0, 4);
        if (draw_back_face) {
            api->VertexPointer(3, GL_FLOAT, 0, kBack.data());
            api->DrawArrays(GL_QUADS, 0, 4);
        }
        api->DisableClientState(GL_VERTEX_ARRAY);
    }
};

void engine_draw(void* user) {
    const auto* e = static_cast<const Engine*>(user);
    if (e->repoint) e->api->ColorPointer(4, GL_UNSIGNED_BYTE, 0, e->repoint);
    e->draw_quads();
}

void engine_draw_pass(void* user, aerial_pass pass) {
    const auto* e = static_cast<const Engine*>(user);
    if (e->own_colours[pass]) {
        e->api->EnableClientState(GL_COLOR_ARRAY);
        e->api->ColorPointer(4, GL_UNSIGNED_BYTE, 0, e->own_colours[pass]);
    }
    if (e->repoint) e->api->ColorPointer(4, GL_UNSIGNED_BYTE, 0, e->repoint);
    if (e->change_blend) e->api->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    e->draw_quads();
    if (e->own_colours[pass]) e->api->DisableClientState(GL_COLOR_ARRAY);
}

/// Four vertices of one colour.
std::vector<std::uint8_t> flat(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    std::vector<std::uint8_t> c;
    for (int i = 0; i < 4; ++i) c.insert(c.end(), {r, g, b, 255});
    return c;
}

class EngineGl : public aerial_test::DrawingTest<kSize, kSize> {
  protected:
    void SetUp() override {
        DrawingTest::SetUp();
        ASSERT_EQ(aerial_gl_create(ctx_->loader(), ctx_->loader_user(), &gl_), AERIAL_OK)
            << aerial_last_error_message();
        engine_.api = &gl();
        colours_.primary = fex_.data();
        colours_.secondary = lin_.data();
        colours_.vertex_count = 4;
        options_.untextured = 1;
    }
    void TearDown() override { aerial_gl_destroy(gl_); }

    void clear() const {
        gl().ClearColor(0, 0, 0, 1);
        gl().Enable(GL_DEPTH_TEST);
        gl().DepthFunc(GL_LESS);
        gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    std::array<int, 3> centre_pixel() const {
        std::vector<std::uint8_t> pixels(4 * kSize * kSize);
        gl().ReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
        const std::size_t p = 4 * std::size_t((kSize / 2) * kSize + kSize / 2);
        return {pixels[p], pixels[p + 1], pixels[p + 2]};
    }
    static void expect_near(const std::array<int, 3>& got, const std::array<int, 3>& want) {
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1) << "channel " << c;
    }

    aerial_gl* gl_ = nullptr;
    Engine engine_;
    std::vector<std::uint8_t> fex_ = flat(128, 128, 128), lin_ = flat(40, 60, 80);
    std::vector<std::uint8_t> white_ = flat(255, 255, 255);
    aerial_vertex_colours colours_{};
    aerial_draw_options options_{};
};

TEST_F(EngineGl, TwoPassesAroundTheEnginesDrawAddLInOnce) {
    clear();
    ASSERT_EQ(aerial_gl_draw_two_pass(gl_, &options_, &colours_, engine_draw_pass, &engine_),
              AERIAL_OK)
        << aerial_last_error_message();
    expect_near(centre_pixel(), {168, 188, 208});
}

TEST_F(EngineGl, TheEnginesOneColourArrayHoldsFExThenLIn) {
    engine_.own_colours[AERIAL_PASS_EXTINCTION] = fex_.data();
    engine_.own_colours[AERIAL_PASS_IN_SCATTERING] = lin_.data();
    clear();
    ASSERT_EQ(aerial_gl_draw_two_pass(gl_, &options_, nullptr, engine_draw_pass, &engine_),
              AERIAL_OK)
        << aerial_last_error_message();
    expect_near(centre_pixel(), {168, 188, 208});
}

TEST_F(EngineGl, BackFacesAtASilhouetteDoNotGetLInTwice) {
    engine_.draw_back_face = true;  // the engine does not cull
    // The engine's culling kept (off): the back face passes depth EQUAL and adds L_in again.
    clear();
    ASSERT_EQ(aerial_gl_draw_two_pass(gl_, &options_, &colours_, engine_draw_pass, &engine_),
              AERIAL_OK);
    expect_near(centre_pixel(), {208, 248, 255});
    options_.cull_back_faces = 1;
    clear();
    ASSERT_EQ(aerial_gl_draw_two_pass(gl_, &options_, &colours_, engine_draw_pass, &engine_),
              AERIAL_OK);
    expect_near(centre_pixel(), {168, 188, 208});
    EXPECT_EQ(gl().IsEnabled(GL_CULL_FACE), GL_FALSE);  // restored
}

TEST_F(EngineGl, ADrawThatRepointsTheColourArrayIsReportedNotDrawnSilentlyWrong) {
    engine_.repoint = white_.data();
    clear();
    EXPECT_EQ(aerial_gl_draw_two_pass(gl_, &options_, &colours_, engine_draw_pass, &engine_),
              AERIAL_ERROR_ENGINE_STATE);
    EXPECT_STREQ(aerial_last_error_field(), "engine.colour_array");
    EXPECT_NE(std::string(aerial_last_error_message()).find("re-pointed"), std::string::npos)
        << aerial_last_error_message();
    for (aerial_path path : {AERIAL_PATH_SECONDARY_COLOR, AERIAL_PATH_TWO_PASS}) {
        options_.path = path;
        EXPECT_EQ(aerial_gl_draw_colours(gl_, &options_, &colours_, engine_draw, &engine_, nullptr),
                  AERIAL_ERROR_ENGINE_STATE)
            << "path " << path;
        EXPECT_STREQ(aerial_last_error_field(), "engine.colour_array");
    }
    // The engine's state is back as it was: no colour array left enabled.
    EXPECT_EQ(gl().IsEnabled(GL_COLOR_ARRAY), GL_FALSE);
}

TEST_F(EngineGl, ADrawThatAppliesItsMaterialInTheLInPassIsReported) {
    engine_.change_blend = true;
    clear();
    EXPECT_EQ(aerial_gl_draw_two_pass(gl_, &options_, &colours_, engine_draw_pass, &engine_),
              AERIAL_ERROR_ENGINE_STATE);
    EXPECT_STREQ(aerial_last_error_field(), "engine.blend");
    EXPECT_EQ(gl().IsEnabled(GL_BLEND), GL_FALSE);
}

TEST_F(EngineGl, ProgramStateSetsColourSumAndPutsItBack) {
    gl().TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    ASSERT_EQ(gl().IsEnabled(GL_COLOR_SUM), GL_FALSE);
    ASSERT_EQ(aerial_gl_set_program_state(gl_, nullptr), AERIAL_OK) << aerial_last_error_message();
    EXPECT_EQ(gl().IsEnabled(GL_COLOR_SUM), GL_TRUE);
    GLint mode = 0;
    gl().GetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &mode);
    EXPECT_EQ(mode, GL_MODULATE);
    EXPECT_EQ(aerial_gl_set_program_state(gl_, nullptr), AERIAL_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(aerial_gl_restore_program_state(gl_), AERIAL_OK);
    EXPECT_EQ(gl().IsEnabled(GL_COLOR_SUM), GL_FALSE);
    gl().GetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &mode);
    EXPECT_EQ(mode, GL_REPLACE);
    EXPECT_EQ(aerial_gl_restore_program_state(gl_), AERIAL_ERROR_INVALID_ARGUMENT);
}

TEST_F(EngineGl, TheDriversLimitsChooseTheHeightProgramsLevel) {
    aerial_arb_limits native{};
    ASSERT_EQ(aerial_gl_arb_limits(gl_, &native), AERIAL_OK) << aerial_last_error_message();
    EXPECT_GE(native.max_instructions, 128);
    EXPECT_GE(native.max_temporaries, 12);
    aerial_arb_options options{};
    options.model = AERIAL_MODEL_HEIGHT;
    aerial_arb_info spec{};
    ASSERT_EQ(aerial_arb_describe(&options, &spec), AERIAL_OK);
    EXPECT_LE(spec.instructions, 128);
    EXPECT_EQ(spec.height_fidelity, AERIAL_HEIGHT_FIDELITY_SPEC_MINIMUM);
    options.limits = native;
    aerial_arb_info chosen{};
    ASSERT_EQ(aerial_arb_describe(&options, &chosen), AERIAL_OK);
    EXPECT_EQ(chosen.height_fidelity,
              AERIAL_HEIGHT_FIDELITY_MULTIPLE_SCATTERING);  // Mesa's limits are large
    EXPECT_GT(chosen.instructions, 128);
    EXPECT_GT(chosen.parameter_count, spec.parameter_count);
    // The level is the one aerial_arb_parameters fills.
    aerial_arb_options full = options;
    full.limits = aerial_arb_limits{};
    full.height_fidelity = AERIAL_HEIGHT_FIDELITY_FULL;
    aerial_arb_info info{};
    EXPECT_EQ(aerial_arb_describe(&full, &info), AERIAL_ERROR_ARB_PROGRAM);
    EXPECT_STREQ(aerial_last_error_field(), "instructions");
    full.limits.max_instructions = -1;
    EXPECT_EQ(aerial_arb_describe(&full, &info), AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "options.limits.max_instructions");
}

TEST(EngineArb, TheLayoutNamesEveryVectorAndTheModelMatrixFollowsTheFrame) {
    aerial_arb_options options{};
    options.model = AERIAL_MODEL_HEIGHT;
    options.parameter_base = 4;
    options.model_matrix = 1;
    aerial_arb_info info{};
    ASSERT_EQ(aerial_arb_describe(&options, &info), AERIAL_OK) << aerial_last_error_message();
    EXPECT_LE(info.instructions, 128);  // the spec minimum, with the model matrix
    size_t count = 0;
    ASSERT_EQ(aerial_arb_parameter_layout(&options, nullptr, 0, &count), AERIAL_OK);
    EXPECT_EQ(count, std::size_t(info.parameter_count));
    std::vector<aerial_arb_parameter> layout(count);
    EXPECT_EQ(aerial_arb_parameter_layout(&options, layout.data(), 1, &count),
              AERIAL_ERROR_BUFFER_TOO_SMALL);
    ASSERT_EQ(aerial_arb_parameter_layout(&options, layout.data(), layout.size(), &count),
              AERIAL_OK);
    for (std::size_t i = 0; i < layout.size(); ++i) {
        EXPECT_EQ(layout[i].index, 4 + int(i));
        EXPECT_STRNE(layout[i].name, "");
        EXPECT_STRNE(layout[i].meaning, "");
    }
    EXPECT_EQ(info.model_matrix_index, info.parameter_base + info.parameter_count - 3);
    EXPECT_STREQ(layout[std::size_t(info.model_matrix_index - 4)].name, "model0");

    const float m[16] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 10, 20, 30, 1};
    float rows[12];
    ASSERT_EQ(aerial_arb_model_matrix(&options, m, rows), AERIAL_OK);
    const float want[12] = {0, -1, 0, 10, 1, 0, 0, 20, 0, 0, 1, 30};
    for (int i = 0; i < 12; ++i) EXPECT_EQ(rows[i], want[i]) << i;
    float projective[16];
    std::copy(m, m + 16, projective);
    projective[3] = 1.0f;
    EXPECT_EQ(aerial_arb_model_matrix(&options, projective, rows), AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "model");
    options.model_matrix = 0;
    EXPECT_EQ(aerial_arb_model_matrix(&options, m, rows), AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "options.model_matrix");
    ASSERT_EQ(aerial_arb_describe(&options, &info), AERIAL_OK);
    EXPECT_EQ(info.model_matrix_index, -1);
}

}  // namespace
