// Off-screen contexts (aerial::headless) and the run-time GL loader (aerial::gl::load_api): each
// platform gives a compatibility context that renders and reads back, names its renderer, and
// reports what it offers; bad sizes and a missing loader are clear errors.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "aerial/gl_api.hpp"
#include "aerial/headless.hpp"

namespace {

using aerial::headless::Context;
using aerial::headless::Platform;

class HeadlessContext : public ::testing::TestWithParam<Platform> {};

TEST_P(HeadlessContext, ClearsAndReadsBackTopRowFirst) {
    auto ctx = Context::create({GetParam(), 8, 4});
    ASSERT_TRUE(ctx.ok()) << ctx.error().message;
    const aerial::gl::Api& gl = ctx->api();
    EXPECT_FALSE(gl.caps.renderer.empty());
    ::testing::Test::RecordProperty("GL_RENDERER", gl.caps.renderer);
    gl.ClearColor(1.0f, 0.5f, 0.0f, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    // A red bottom row drawn with scissor: read_rgba8() must put it last.
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(0, 0, 8, 1);
    gl.ClearColor(0.0f, 0.0f, 1.0f, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    gl.Disable(GL_SCISSOR_TEST);
    const auto pixels = ctx->read_rgba8();
    ASSERT_EQ(pixels.size(), 8u * 4u * 4u);
    EXPECT_EQ(pixels[0], 255);
    EXPECT_NEAR(pixels[1], 128, 1);
    EXPECT_EQ(pixels[2], 0);
    const std::size_t last_row = 3 * 8 * 4;
    EXPECT_EQ(pixels[last_row + 0], 0) << "the bottom row must come last";
    EXPECT_EQ(pixels[last_row + 2], 255) << "the bottom row must come last";
    EXPECT_EQ(gl.GetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST_P(HeadlessContext, OffersTheFixedFunctionExtensionsOfMesa) {
    auto ctx = Context::create({GetParam(), 4, 4});
    ASSERT_TRUE(ctx.ok()) << ctx.error().message;
    const aerial::gl::Caps& caps = ctx->api().caps;
    EXPECT_TRUE(caps.at_least(1, 4)) << caps.version;
    EXPECT_TRUE(caps.multitexture);
    EXPECT_TRUE(caps.texture_env_combine);
    EXPECT_TRUE(caps.fog_coord);
    EXPECT_GE(caps.max_texture_units, 2);
    // Secondary colour and vertex programs are offered unless MESA_EXTENSION_OVERRIDE removes
    // them (the fallback tests do exactly that).
    const char* override_env = std::getenv("MESA_EXTENSION_OVERRIDE");
    if (override_env == nullptr) {
        EXPECT_TRUE(caps.secondary_color);
        EXPECT_TRUE(caps.vertex_program);
    }
}

TEST_P(HeadlessContext, RejectsSizesOutsideTheRange) {
    auto wide = Context::create({GetParam(), 0, 4});
    ASSERT_FALSE(wide.ok());
    EXPECT_EQ(wide.error().field, "width");
    auto tall = Context::create({GetParam(), 4, 9000});
    ASSERT_FALSE(tall.ok());
    EXPECT_EQ(tall.error().field, "height");
}

INSTANTIATE_TEST_SUITE_P(Platforms, HeadlessContext,
                         ::testing::Values(Platform::osmesa, Platform::egl),
                         [](const ::testing::TestParamInfo<Platform>& p) {
                             return std::string(aerial::headless::platform_name(p.param));
                         });

TEST(GlLoader, NullLoaderIsAnError) {
    auto api = aerial::gl::load_api(nullptr, nullptr);
    ASSERT_FALSE(api.ok());
    EXPECT_EQ(api.error().field, "load");
}

TEST(GlLoader, LoaderThatFindsNothingNamesTheFirstMissingFunction) {
    auto api = aerial::gl::load_api([](void*, const char*) -> void* { return nullptr; }, nullptr);
    ASSERT_FALSE(api.ok());
    EXPECT_EQ(api.error().field, "glGetString");
    EXPECT_NE(api.error().message.find("not found"), std::string::npos) << api.error().message;
}

TEST(GlLoader, ExtensionsMatchWholeWordsOnly) {
    aerial::gl::Caps caps;
    caps.extensions = "GL_ARB_vertex_program GL_EXT_secondary_color_x GL_EXT_fog_coord";
    EXPECT_TRUE(caps.has_extension("GL_ARB_vertex_program"));
    EXPECT_TRUE(caps.has_extension("GL_EXT_fog_coord"));
    EXPECT_FALSE(caps.has_extension("GL_EXT_secondary_color"));
    EXPECT_FALSE(caps.has_extension("GL_ARB_vertex"));
    EXPECT_FALSE(caps.has_extension(""));
}

}  // namespace
