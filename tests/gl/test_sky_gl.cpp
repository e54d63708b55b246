// The sky on the fixed pipeline (aerial/sky_gl.hpp) on a headless context: the GL sky box
// against the CPU cubemap sampler pixel by pixel, the sun sprite added where the sun is, every
// draw and upload leaving the GL state as it found it, and bad input.
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "aerial/aerial.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/headless.hpp"
#include "aerial/sky_gl.hpp"
#include "gl_test_context.hpp"

namespace {

using aerial::headless::Context;

constexpr int kSize = 64;     // viewport, pixels
constexpr int kCubemap = 32;  // texels a face
constexpr double kExposure = 12.0;
constexpr double kNear = 0.5, kFar = 1000.0;

/// Camera: a 90 deg square frustum looking along `forward` (world, z up).
struct Camera {
    glm::dvec3 forward, right, up;
    aerial::gl::SkyBoxView view;
};

Camera camera_looking(const glm::dvec3& forward_in) {
    Camera c;
    c.forward = glm::normalize(forward_in);
    c.right = glm::normalize(glm::cross(c.forward, glm::dvec3(0, 0, 1)));
    c.up = glm::cross(c.right, c.forward);
    auto& p = c.view.projection;
    p = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, -1, 0, 0, 0, 0};
    p[10] = float(-(kFar + kNear) / (kFar - kNear));
    p[14] = float(-2.0 * kFar * kNear / (kFar - kNear));
    // Rows of the world-to-eye rotation: right, up, -forward; stored column-major.
    auto& m = c.view.view_rotation;
    m = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    for (int col = 0; col < 3; ++col) {
        m[std::size_t(col * 4 + 0)] = float(c.right[col]);
        m[std::size_t(col * 4 + 1)] = float(c.up[col]);
        m[std::size_t(col * 4 + 2)] = float(-c.forward[col]);
    }
    return c;
}

/// World direction through the centre of pixel (x, row) of a read_rgba8 image (top row first).
glm::dvec3 pixel_direction(const Camera& c, int x, int row) {
    const double ndc_x = 2.0 * (x + 0.5) / kSize - 1.0;
    const double ndc_y = 2.0 * ((kSize - 1 - row) + 0.5) / kSize - 1.0;
    return glm::normalize(c.forward + ndc_x * c.right + ndc_y * c.up);
}

class SkyGl : public aerial_test::DrawingTest<kSize, kSize> {
  protected:
    void SetUp() override {
        DrawingTest::SetUp();
        if (HasFatalFailure()) return;
        // The sky and its cubemap are the same for every test: computed once per process.
        static const auto shared = [] {
            aerial::View view;
            view.eye = {0.0, 0.0, 100.0};
            const double e = 12.0 * aerial::kPi / 180.0;
            view.sun_dir =
                glm::normalize(glm::dvec3(0.9 * std::cos(e), 0.436 * std::cos(e), std::sin(e)));
            auto sky = aerial::prepare_sky(*aerial::atmosphere_preset("earth"), view,
                                           aerial::SkyMethod::height_chained);
            auto cubemap = aerial::compute_sky_cubemap(*sky, kCubemap);
            return std::make_pair(*sky, aerial::cubemap_to_rgba8(*cubemap, kExposure,
                                                                 aerial::ToneCurve::exponential));
        }();
        sky_.emplace(shared.first);
        faces_ = shared.second;
    }
    void clear() {
        gl().ClearColor(0, 0, 0, 1);
        gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }

    std::optional<aerial::SkyContext> sky_;
    std::array<std::vector<std::uint8_t>, 6> faces_;
};

TEST_F(SkyGl, SkyBoxMatchesTheCpuCubemapSamplerWithinOneStep) {
    if (!aerial::gl::cube_maps_supported(gl())) {
        EXPECT_EQ(aerial::gl::SkyCubemapTexture::create(gl(), faces_, kCubemap).error().field,
                  "cube_map");
        GTEST_SKIP() << "no cube maps on GL " << gl().caps.version;
    }
    // An engine's unusual unpack state must not garble the upload.
    gl().PixelStorei(GL_UNPACK_ROW_LENGTH, 7);
    gl().PixelStorei(GL_UNPACK_ALIGNMENT, 8);
    auto texture = aerial::gl::SkyCubemapTexture::create(gl(), faces_, kCubemap);
    ASSERT_TRUE(texture.ok()) << texture.error().message;
    int worst = 0;
    for (const glm::dvec3& forward :
         {glm::dvec3(1, 0.2, 0.15), glm::dvec3(-0.3, -1, 0.6), glm::dvec3(0.1, 0.2, 1)}) {
        const Camera cam = camera_looking(forward);
        clear();
        ASSERT_FALSE(aerial::gl::draw_sky_box(gl(), *texture, cam.view).has_value());
        ASSERT_EQ(gl().GetError(), static_cast<GLenum>(GL_NO_ERROR));
        const std::vector<std::uint8_t> image = ctx_->read_rgba8();
        for (int row = 0; row < kSize; ++row) {
            for (int x = 0; x < kSize; ++x) {
                const glm::dvec3 cpu =
                    aerial::sample_cubemap_rgba8(faces_, kCubemap, pixel_direction(cam, x, row));
                const std::size_t k = (std::size_t(row) * kSize + std::size_t(x)) * 4;
                for (int c = 0; c < 3; ++c) {
                    const int d = int(std::lround(std::abs(image[k + std::size_t(c)] - cpu[c])));
                    if (d > worst) {
                        worst = d;
                        std::printf("pixel (%d, %d) channel %d: GL %d CPU %.2f\n", x, row, c,
                                    image[k + std::size_t(c)], cpu[c]);
                    }
                }
            }
        }
    }
    std::printf("sky box vs CPU sampler: max %d steps on %s\n", worst,
                aerial_test::context_label(*ctx_).c_str());
    EXPECT_LE(worst, 1);
}

TEST_F(SkyGl, SunSpriteBrightensTheSunAndLeavesTheRestOfTheSky) {
    if (!aerial::gl::cube_maps_supported(gl())) GTEST_SKIP() << "no cube maps";
    auto texture = aerial::gl::SkyCubemapTexture::create(gl(), faces_, kCubemap);
    ASSERT_TRUE(texture.ok());
    aerial::SunSpriteOptions o;
    o.size = 32;
    o.half_width_rad = 0.2;
    o.sun_radius_rad = 0.02;  // large enough to cover pixels at this resolution
    auto sprite = aerial::make_sun_sprite(*sky_, kExposure, aerial::ToneCurve::exponential, o);
    ASSERT_TRUE(sprite.ok()) << sprite.error().message;
    auto sun = aerial::gl::SunSpriteTexture::create(gl(), *sprite);
    ASSERT_TRUE(sun.ok()) << sun.error().message;
    const Camera cam = camera_looking(sky_->view.sun_dir);
    clear();
    ASSERT_FALSE(aerial::gl::draw_sky_box(gl(), *texture, cam.view).has_value());
    const std::vector<std::uint8_t> sky_only = ctx_->read_rgba8();
    ASSERT_FALSE(aerial::gl::draw_sun_sprite(gl(), *sun, cam.view, sky_->view.sun_dir).has_value());
    const std::vector<std::uint8_t> with_sun = ctx_->read_rgba8();
    const std::size_t centre = (std::size_t(kSize / 2) * kSize + kSize / 2) * 4;
    EXPECT_EQ(with_sun[centre], 255) << "the disc at the view centre";
    const std::size_t corner = 0;
    EXPECT_EQ(with_sun[corner], sky_only[corner]) << "outside the sprite the sky is untouched";
    for (std::size_t k = 0; k < with_sun.size(); ++k) {
        ASSERT_GE(with_sun[k], sky_only[k]) << "the sprite only adds light";
    }
}

// The moon's disc: its lit side where the sprite says, on the observer's left for a bright
// limb angle of pi / 2; only light added.
TEST_F(SkyGl, MoonSpriteShowsItsPhaseFacingTheEye) {
    auto moon_image = aerial::make_moon_sprite(90.0 * aerial::kPi / 180.0, 0.5 * aerial::kPi, 32);
    ASSERT_TRUE(moon_image.ok());
    aerial::SunSprite sprite{moon_image->size, 0.3, moon_image->rgba};  // large: many pixels
    auto texture = aerial::gl::SunSpriteTexture::create(gl(), sprite);
    ASSERT_TRUE(texture.ok()) << texture.error().message;
    const glm::dvec3 moon = glm::normalize(glm::dvec3(1.0, 0.0, 0.5));
    const Camera cam = camera_looking(moon);
    clear();
    ASSERT_FALSE(
        aerial::gl::draw_moon_sprite(gl(), *texture, cam.view, moon, {0, 0, 1}, glm::vec3(1.0f))
            .has_value());
    const std::vector<std::uint8_t> image = ctx_->read_rgba8();
    double left = 0.0, right = 0.0;
    for (int row = 0; row < kSize; ++row)
        for (int x = 0; x < kSize; ++x)
            (x < kSize / 2 ? left : right) += image[(std::size_t(row) * kSize + x) * 4];
    EXPECT_GT(left, 20.0 * (right + 1.0)) << "the lit half on the left";
    EXPECT_EQ(
        aerial::gl::draw_moon_sprite(gl(), *texture, cam.view, moon, moon, glm::vec3(1.0f))->field,
        "up");
}

// Stars: each drawn where its direction projects, brighter stars brighter; nothing else.
TEST_F(SkyGl, StarsAreDrawnWhereTheyStand) {
    auto glow_image = aerial::make_star_glow(16);
    ASSERT_TRUE(glow_image.ok());
    auto glow = aerial::gl::SunSpriteTexture::create(gl(), *glow_image);
    ASSERT_TRUE(glow.ok());
    const Camera cam = camera_looking({0.0, 1.0, 0.0});  // north, on the horizon
    // Two stars: pixel (16, 32) and (48, 32) directions, bright and faint, 2 pixels wide.
    const double pixel = 2.0 / kSize;  // tangent per pixel at the centre
    std::vector<aerial::StarAppearance> stars(2);
    stars[0].direction = pixel_direction(cam, 16, 32);
    stars[0].brightness = 1.0f;
    stars[0].half_width_rad = float(2.0 * pixel);
    stars[1].direction = pixel_direction(cam, 48, 32);
    stars[1].brightness = 0.3f;
    stars[1].half_width_rad = float(2.0 * pixel);
    clear();
    ASSERT_FALSE(aerial::gl::draw_stars(gl(), *glow, cam.view, stars).has_value());
    const std::vector<std::uint8_t> image = ctx_->read_rgba8();
    const auto at = [&](int x, int row) { return int(image[(std::size_t(row) * kSize + x) * 4]); };
    EXPECT_GT(at(16, 32), 200);
    EXPECT_GT(at(48, 32), 40);
    EXPECT_LT(at(48, 32), at(16, 32));
    EXPECT_EQ(at(32, 10), 0) << "the sky between the stars is untouched";
}

TEST_F(SkyGl, DrawsAndUploadsLeaveTheGlStateAsTheyFoundIt) {
    if (!aerial::gl::cube_maps_supported(gl())) GTEST_SKIP() << "no cube maps";
    // An engine's state: culling, depth test, a bound and enabled 2D texture, texgen, odd
    // matrices and blend function, modulate.
    const auto& g = gl();
    g.Enable(GL_CULL_FACE);
    g.Enable(GL_DEPTH_TEST);
    g.Enable(GL_TEXTURE_2D);
    g.Enable(GL_TEXTURE_GEN_S);
    g.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    g.MatrixMode(GL_PROJECTION);
    const float projection[16] = {2, 0, 0, 0, 0, 3, 0, 0, 0, 0, -1, -1, 0, 0, -1, 0};
    g.LoadMatrixf(projection);
    g.MatrixMode(GL_MODELVIEW);
    const float modelview[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1};
    g.LoadMatrixf(modelview);
    g.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    g.TexCoord2f(0.25f, 0.75f);
    const auto before = aerial::gl::capture_state(g);
    auto texture = aerial::gl::SkyCubemapTexture::create(g, faces_, kCubemap);
    ASSERT_TRUE(texture.ok());
    auto sprite = aerial::make_sun_sprite(*sky_, kExposure, aerial::ToneCurve::exponential);
    ASSERT_TRUE(sprite.ok());
    auto sun = aerial::gl::SunSpriteTexture::create(g, *sprite);
    ASSERT_TRUE(sun.ok());
    const Camera cam = camera_looking({1, 0.3, 0.2});
    ASSERT_FALSE(aerial::gl::draw_sky_box(g, *texture, cam.view).has_value());
    ASSERT_FALSE(aerial::gl::draw_sun_sprite(g, *sun, cam.view, sky_->view.sun_dir).has_value());
    g.Color4f(0.1f, 0.2f, 0.3f, 0.4f);
    const auto with_colour = aerial::gl::capture_state(g);
    ASSERT_FALSE(aerial::gl::draw_moon_sprite(g, *sun, cam.view, sky_->view.sun_dir, {0, 0, 1},
                                              glm::vec3(0.5f))
                     .has_value());
    aerial::StarAppearance star;
    star.direction = {0.0, 0.6, 0.8};
    star.brightness = 0.7f;
    star.half_width_rad = 0.01f;
    ASSERT_FALSE(aerial::gl::draw_stars(g, *sun, cam.view, {star}).has_value());
    const auto after_night =
        aerial::gl::state_differences(with_colour, aerial::gl::capture_state(g));
    EXPECT_TRUE(after_night.empty()) << after_night.front();
    g.Color4f(1.0f, 1.0f, 1.0f, 1.0f);
    ASSERT_FALSE(texture.value().update(faces_, kCubemap).has_value());
    const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(g));
    EXPECT_TRUE(changed.empty()) << changed.front();
    EXPECT_EQ(g.GetError(), static_cast<GLenum>(GL_NO_ERROR));
    // The current matrices give the same view back (translation dropped).
    const auto from_gl = aerial::gl::sky_box_view_from_current_matrices(g);
    EXPECT_EQ(from_gl.projection[5], 3.0f);
    EXPECT_EQ(from_gl.view_rotation[12], 0.0f);
}

TEST_F(SkyGl, RejectsBadInputNamingTheField) {
    if (!aerial::gl::cube_maps_supported(gl())) GTEST_SKIP() << "no cube maps";
    auto short_faces = faces_;
    short_faces[3].resize(10);
    EXPECT_EQ(aerial::gl::SkyCubemapTexture::create(gl(), short_faces, kCubemap).error().field,
              "faces");
    EXPECT_EQ(aerial::gl::SkyCubemapTexture::create(gl(), faces_, 0).error().field, "size");
    auto texture = aerial::gl::SkyCubemapTexture::create(gl(), faces_, kCubemap);
    ASSERT_TRUE(texture.ok());
    aerial::gl::SkyBoxView ortho;
    ortho.projection = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1};
    auto e = aerial::gl::draw_sky_box(gl(), *texture, ortho);
    ASSERT_TRUE(e.has_value());
    EXPECT_EQ(e->field, "projection");
    aerial::SunSprite bad;
    bad.size = 4;
    bad.half_width_rad = 0.1;
    EXPECT_EQ(aerial::gl::SunSpriteTexture::create(gl(), bad).error().field, "sprite");
}

}  // namespace
