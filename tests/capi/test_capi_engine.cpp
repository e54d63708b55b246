// What an engine with its own vertex layout, scene graph and sky needs from the C interface,
// without GL: colour formats written straight into interleaved vertices, model-space positions
// with a model matrix, dome colours that follow the view direction, cubemap faces, the sun
// sprite's parameters and the automatic exposure.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/aerial.h"
#include "aerial/sky.hpp"
#include "aerial/sun.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;

/// An engine vertex as Irrlicht's video::S3DVertex lays it out: position, normal, colour, uv.
struct EngineVertex {
    float pos[3];
    float normal[3];
    std::uint32_t colour;
    float uv[2];
};

class EngineContext : public ::testing::Test {
  protected:
    void SetUp() override {
        ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &ctx_), AERIAL_OK);
        view_ = aerial_view{};
        view_.eye[2] = 500.0;
        const double e = 20.0 * kPi / 180.0;
        view_.sun_dir[0] = std::cos(e);
        view_.sun_dir[2] = std::sin(e);
        ASSERT_EQ(aerial_context_set_view(ctx_, &view_), AERIAL_OK);
    }
    void TearDown() override { aerial_context_destroy(ctx_); }

    aerial_context* ctx_ = nullptr;
    aerial_view view_{};
};

std::vector<EngineVertex> terrain_vertices() {
    std::vector<EngineVertex> v;
    for (int i = 0; i < 97; ++i) {
        const float t = float(i) / 96.0f;
        v.push_back({{-8000.0f + 16000.0f * t, 3000.0f * std::sin(7.0f * t), 200.0f * t},
                     {0, 0, 1},
                     0xDEADBEEFu,
                     {t, t}});
    }
    return v;
}

TEST_F(EngineContext, ColourFormatsWriteStraightIntoInterleavedVertices) {
    std::vector<EngineVertex> vertices = terrain_vertices();
    const std::size_t n = vertices.size();
    aerial_positions positions{};
    positions.x = vertices[0].pos;
    positions.count = n;
    positions.stride_bytes = sizeof(EngineVertex);
    std::vector<std::uint8_t> rgba(4 * n);
    aerial_outputs out{};
    out.extinction_rgba8 = rgba.data();
    ASSERT_EQ(aerial_shade(ctx_, &positions, &out, nullptr, nullptr), AERIAL_OK);

    for (aerial_colour_format format : {AERIAL_COLOUR_BGRA8, AERIAL_COLOUR_ARGB32}) {
        std::vector<EngineVertex> copy = vertices;
        aerial_outputs o{};
        o.extinction_rgba8 = reinterpret_cast<unsigned char*>(&copy[0].colour);
        o.extinction_rgba8_stride = sizeof(EngineVertex);
        o.colour_format = format;
        ASSERT_EQ(aerial_shade(ctx_, &positions, &o, nullptr, nullptr), AERIAL_OK)
            << aerial_last_error_message();
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint8_t* c = &rgba[4 * i];
            if (format == AERIAL_COLOUR_ARGB32) {
                const std::uint32_t want = std::uint32_t(c[3]) << 24 | std::uint32_t(c[0]) << 16 |
                                           std::uint32_t(c[1]) << 8 | c[2];
                ASSERT_EQ(copy[i].colour, want) << "vertex " << i;
            } else {
                std::uint8_t bytes[4];
                std::memcpy(bytes, &copy[i].colour, 4);
                ASSERT_EQ(bytes[0], c[2]);
                ASSERT_EQ(bytes[1], c[1]);
                ASSERT_EQ(bytes[2], c[0]);
                ASSERT_EQ(bytes[3], c[3]);
            }
            // The rest of the engine's vertex is untouched.
            ASSERT_EQ(copy[i].uv[0], vertices[i].uv[0]);
            ASSERT_EQ(copy[i].normal[2], 1.0f);
        }
    }
    aerial_outputs bad{};
    bad.extinction_rgba8 = rgba.data();
    bad.colour_format = aerial_colour_format(7);
    EXPECT_EQ(aerial_shade(ctx_, &positions, &bad, nullptr, nullptr),
              AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "outputs.colour_format");
}

TEST_F(EngineContext, ModelSpacePositionsWithAModelMatrixShadeAsTheirWorldPositions) {
    // A node rotated 90 degrees about z and moved: world = R p + t.
    const float m[16] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 2500, -700, 120, 1};
    const std::vector<EngineVertex> local = terrain_vertices();
    std::vector<float> world;
    for (const EngineVertex& v : local) {
        const double x = v.pos[0], y = v.pos[1], z = v.pos[2];
        world.insert(world.end(), {float(-y + 2500.0), float(x - 700.0), float(z + 120.0)});
    }
    const std::size_t n = local.size();
    std::vector<std::uint8_t> want(4 * n), got(4 * n), want_lin(4 * n), got_lin(4 * n);
    aerial_positions pw{};
    pw.x = world.data();
    pw.count = n;
    aerial_outputs ow{};
    ow.extinction_rgba8 = want.data();
    ow.in_scattering_rgba8 = want_lin.data();
    aerial_batch_settings settings{};
    settings.display.exposure = 8.0f;
    ASSERT_EQ(aerial_shade(ctx_, &pw, &ow, &settings, nullptr), AERIAL_OK);
    aerial_positions pm{};
    pm.x = local[0].pos;
    pm.count = n;
    pm.stride_bytes = sizeof(EngineVertex);
    pm.model_matrix = m;
    aerial_outputs om{};
    om.extinction_rgba8 = got.data();
    om.in_scattering_rgba8 = got_lin.data();
    ASSERT_EQ(aerial_shade(ctx_, &pm, &om, &settings, nullptr), AERIAL_OK)
        << aerial_last_error_message();
    EXPECT_EQ(got, want);
    EXPECT_EQ(got_lin, want_lin);

    float projective[16];
    std::memcpy(projective, m, sizeof m);
    projective[3] = 0.5f;
    pm.model_matrix = projective;
    EXPECT_EQ(aerial_shade(ctx_, &pm, &om, &settings, nullptr), AERIAL_ERROR_INVALID_BATCH);
    EXPECT_STREQ(aerial_last_error_field(), "positions.model_matrix");
    projective[3] = 0.0f;
    projective[13] = NAN;
    EXPECT_EQ(aerial_shade(ctx_, &pm, &om, &settings, nullptr), AERIAL_ERROR_INVALID_BATCH);
    EXPECT_NE(std::string(aerial_last_error_message()).find("element 13 = nan"), std::string::npos)
        << aerial_last_error_message();
}

TEST_F(EngineContext, SplitBatchesAndSeparateArraysTakeTheMatrixAndTheFormatToo) {
    // Large enough to be split over two threads; x, y, z as separate arrays; the float path
    // (an rgb output) and the one-pass RGBA8 path.
    const std::size_t n = 70000;
    std::vector<float> x(n), y(n), z(n), wx(n), wy(n), wz(n);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = float(i % 400) * 40.0f - 8000.0f;
        y[i] = float(i / 400) * 90.0f - 8000.0f;
        z[i] = float((i * 7) % 600);
        wx[i] = float(double(x[i]) * 2.0 + 10.0);
        wy[i] = float(double(y[i]) * 2.0 - 20.0);
        wz[i] = float(double(z[i]) * 2.0 + 30.0);
    }
    const float scale2[16] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 10, -20, 30, 1};
    aerial_batch_settings settings{};
    settings.threads = 2;
    settings.min_vertices_per_thread = 1000;
    for (bool with_float : {false, true}) {
        std::vector<std::uint8_t> want(4 * n), got(4 * n);
        std::vector<float> rgb(3 * n);
        aerial_positions world{};
        world.x = wx.data(), world.y = wy.data(), world.z = wz.data(), world.count = n;
        aerial_outputs ow{};
        ow.in_scattering_rgba8 = want.data();
        ow.colour_format = AERIAL_COLOUR_BGRA8;
        if (with_float) ow.in_scattering_rgb = rgb.data();
        ASSERT_EQ(aerial_shade(ctx_, &world, &ow, &settings, nullptr), AERIAL_OK);
        aerial_positions model{};
        model.x = x.data(), model.y = y.data(), model.z = z.data(), model.count = n;
        model.model_matrix = scale2;
        aerial_outputs om = ow;
        om.in_scattering_rgba8 = got.data();
        aerial_batch_stats stats{};
        ASSERT_EQ(aerial_shade(ctx_, &model, &om, &settings, &stats), AERIAL_OK);
        EXPECT_EQ(stats.threads_used, 2u);
        EXPECT_EQ(got, want) << (with_float ? "float path" : "one-pass path");
    }
}

class EngineSky : public EngineContext {
  protected:
    void SetUp() override {
        EngineContext::SetUp();
        ASSERT_EQ(aerial_sky_create(nullptr, &sky_), AERIAL_OK);
        ASSERT_EQ(aerial_sky_set_frame(sky_, ctx_), AERIAL_OK) << aerial_last_error_message();
    }
    void TearDown() override {
        aerial_sky_destroy(sky_);
        EngineContext::TearDown();
    }
    /// Dome colours of the given directions at `radius` around `centre` (engine units).
    std::vector<std::uint8_t> dome(const std::vector<std::array<double, 3>>& dirs, double radius,
                                   const double centre[3], aerial_colour_format format) {
        std::vector<float> xyz;
        for (const auto& d : dirs) {
            for (int k = 0; k < 3; ++k) xyz.push_back(float(centre[k] + radius * d[k]));
        }
        aerial_positions p{};
        p.x = xyz.data();
        p.count = dirs.size();
        aerial_display display{8.0f, AERIAL_TONE_CLAMP};
        aerial_sky_colours out{};
        std::vector<std::uint8_t> codes(4 * dirs.size());
        out.rgba8 = codes.data();
        out.format = format;
        EXPECT_EQ(aerial_sky_shade_dome(sky_, &p, centre, &display, &out), AERIAL_OK)
            << aerial_last_error_message();
        return codes;
    }
    aerial_sky* sky_ = nullptr;
};

std::vector<std::array<double, 3>> dome_directions() {
    std::vector<std::array<double, 3>> dirs;
    for (int r = 0; r <= 6; ++r) {
        const double e = (r * 15.0) * kPi / 180.0;
        for (int s = 0; s < 8; ++s) {
            const double a = s * kPi / 4.0;
            dirs.push_back({std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)});
        }
    }
    return dirs;
}

TEST_F(EngineSky, DomeColoursFollowTheViewDirectionWhateverTheDomeRadius) {
    const auto dirs = dome_directions();
    const double eye[3] = {view_.eye[0], view_.eye[1], view_.eye[2]};
    const auto small = dome(dirs, 50.0, eye, AERIAL_COLOUR_RGBA8);
    EXPECT_EQ(dome(dirs, 100e3, eye, AERIAL_COLOUR_RGBA8), small);
    EXPECT_EQ(dome(dirs, 1000e3, eye, AERIAL_COLOUR_RGBA8), small);
    // The same as the C++ sky (aerial::scene's dome: dome_height for the height model).
    aerial::View view;
    view.eye = {eye[0], eye[1], eye[2]};
    view.sun_dir = {view_.sun_dir[0], view_.sun_dir[1], view_.sun_dir[2]};
    auto sky = aerial::prepare_sky(aerial::Atmosphere{}, view, aerial::SkyMethod::dome_height);
    ASSERT_TRUE(sky.ok());
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        const glm::dvec3 l = aerial::sky_radiance(*sky, {dirs[i][0], dirs[i][1], dirs[i][2]});
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(small[4 * i + std::size_t(c)],
                      aerial::to_unorm8(aerial::display_value({8.0f}, float(l[c]))))
                << "direction " << i;
        }
    }
    // Blue overhead, brighter towards the horizon: the sky, not grey.
    const std::size_t zenith = dirs.size() - 1;
    EXPECT_GT(small[4 * zenith + 2], small[4 * zenith]);
}

TEST_F(EngineSky, BelowTheHorizonADomeVertexShowsTheHorizon) {
    const double eye[3] = {view_.eye[0], view_.eye[1], view_.eye[2]};
    const double e = -10.0 * kPi / 180.0;
    const auto below = dome({{std::cos(e), 0.0, std::sin(e)}}, 1000.0, eye, AERIAL_COLOUR_RGBA8);
    const auto horizon = dome({{1.0, 0.0, 0.0}}, 1000.0, eye, AERIAL_COLOUR_RGBA8);
    EXPECT_EQ(below, horizon);
    const auto bgra = dome({{1.0, 0.0, 0.0}}, 1000.0, eye, AERIAL_COLOUR_BGRA8);
    EXPECT_EQ(bgra[0], horizon[2]);
    EXPECT_EQ(bgra[2], horizon[0]);
}

TEST_F(EngineSky, CubemapFacesSayWhenTheyChanged) {
    const int size = 8;
    std::vector<std::uint8_t> rgba(6 * size * size * 4), bgra(rgba.size());
    aerial_display display{8.0f, AERIAL_TONE_CLAMP};
    int changed = -1;
    ASSERT_EQ(aerial_sky_cubemap(sky_, size, AERIAL_COLOUR_RGBA8, &display, rgba.data(),
                                 rgba.size(), &changed),
              AERIAL_OK)
        << aerial_last_error_message();
    EXPECT_EQ(changed, 1);
    ASSERT_EQ(aerial_sky_cubemap(sky_, size, AERIAL_COLOUR_RGBA8, &display, rgba.data(),
                                 rgba.size(), &changed),
              AERIAL_OK);
    EXPECT_EQ(changed, 0);
    ASSERT_EQ(aerial_sky_cubemap(sky_, size, AERIAL_COLOUR_BGRA8, &display, bgra.data(),
                                 bgra.size(), &changed),
              AERIAL_OK);
    EXPECT_EQ(changed, 1);
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
        ASSERT_EQ(bgra[i], rgba[i + 2]);
        ASSERT_EQ(bgra[i + 2], rgba[i]);
    }
    // The +Z face (index 4) looks up: brighter than black.
    EXPECT_GT(rgba[4 * size * size * 4 + 2], 0);
    EXPECT_EQ(
        aerial_sky_cubemap(sky_, size, AERIAL_COLOUR_RGBA8, &display, rgba.data(), 100, &changed),
        AERIAL_ERROR_BUFFER_TOO_SMALL);
    EXPECT_STREQ(aerial_last_error_field(), "capacity_bytes");
}

TEST_F(EngineSky, SunSpriteInfoPlacesTheSprite) {
    aerial_sun_sprite_info info{};
    aerial_display display{8.0f, AERIAL_TONE_CLAMP};
    ASSERT_EQ(
        aerial_sky_sun_sprite(sky_, nullptr, &display, AERIAL_COLOUR_RGBA8, nullptr, 0, &info),
        AERIAL_OK)
        << aerial_last_error_message();
    EXPECT_EQ(info.size, 64);
    EXPECT_NEAR(info.direction[0], view_.sun_dir[0], 1e-12);
    EXPECT_NEAR(info.direction[2], view_.sun_dir[2], 1e-12);
    // At 20 degrees the sun is yellowed: blue is dimmed more than red.
    EXPECT_GT(info.transmittance[0], info.transmittance[2]);
    EXPECT_LE(info.transmittance[0], 1.0f);
    std::vector<std::uint8_t> image(std::size_t(info.size * info.size * 4));
    ASSERT_EQ(aerial_sky_sun_sprite(sky_, nullptr, &display, AERIAL_COLOUR_RGBA8, image.data(),
                                    image.size(), &info),
              AERIAL_OK);
    const std::size_t centre = std::size_t((info.size / 2) * info.size + info.size / 2);
    EXPECT_EQ(image[4 * centre], 255);  // the disc, far beyond display white
    EXPECT_EQ(aerial_sky_sun_sprite(sky_, nullptr, &display, AERIAL_COLOUR_RGBA8, image.data(), 16,
                                    &info),
              AERIAL_ERROR_BUFFER_TOO_SMALL);
}

TEST_F(EngineSky, ASkyNeedsAFrameFirst) {
    aerial_sky* fresh = nullptr;
    ASSERT_EQ(aerial_sky_create(nullptr, &fresh), AERIAL_OK);
    const double up[3] = {0, 0, 1};
    float rgb[3];
    EXPECT_EQ(aerial_sky_radiance(fresh, up, rgb), AERIAL_ERROR_NO_VIEW);
    EXPECT_STREQ(aerial_last_error_field(), "sky");
    aerial_sky_destroy(fresh);
    aerial_sky_options options{};
    options.method = aerial_sky_method(9);
    EXPECT_EQ(aerial_sky_create(&options, &fresh), AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "method");
}

/// The exposure of the grey-card rule, from the C++ pieces as the sample game computes it.
double cpp_exposure(const aerial::Atmosphere& atmosphere, double altitude, double elevation) {
    aerial::SkyAmbientOptions ambient;
    ambient.elevation_steps = 8;
    ambient.azimuth_steps = 16;
    const glm::dvec3 sky = *aerial::sky_ambient(atmosphere, altitude, elevation, ambient);
    return aerial::auto_exposure(
        aerial::sun_irradiance_at_altitude(atmosphere, altitude, elevation), elevation, sky,
        atmosphere.sun_irradiance);
}

TEST_F(EngineContext, AutoExposureIsTheGreyCardRuleForEveryPreset) {
    float earth = 0;
    ASSERT_EQ(aerial_auto_exposure(ctx_, nullptr, &earth), AERIAL_OK)
        << aerial_last_error_message();
    EXPECT_NEAR(earth, cpp_exposure(aerial::Atmosphere{}, 500.0, 20.0 * kPi / 180.0), 1e-4 * earth);
    aerial_atmosphere hazy;
    ASSERT_EQ(aerial_atmosphere_preset("hazy", &hazy), AERIAL_OK);
    ASSERT_EQ(aerial_context_set_atmosphere(ctx_, &hazy), AERIAL_OK);
    ASSERT_EQ(aerial_context_set_view(ctx_, &view_), AERIAL_OK);
    float haze = 0;
    ASSERT_EQ(aerial_auto_exposure(ctx_, nullptr, &haze), AERIAL_OK);
    // Haze dims the sun but brightens the sky: the rule follows the light that reaches the card,
    // not a constant picked for earth.
    EXPECT_NE(haze, earth);
    aerial_exposure_options bad{};
    bad.albedo = 1.5;
    EXPECT_EQ(aerial_auto_exposure(ctx_, &bad, &haze), AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "albedo");
    aerial_exposure_options high{};
    high.use_card_altitude = 1;
    high.card_altitude_m = 3000.0;
    float at_altitude = 0;
    ASSERT_EQ(aerial_auto_exposure(ctx_, &high, &at_altitude), AERIAL_OK);
    EXPECT_LT(at_altitude, haze);  // more sun above the haze: a smaller exposure
}

}  // namespace
