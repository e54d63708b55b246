// The fixed-function paths (aerial::gl::draw_with_colours) on a headless context: each path
// against the others on a textured mesh shaded by aerial::shade_into, two passes against one,
// why the second pass needs black fog, every path leaving the GL state as it found it
// (aerial/gl_state.hpp), and path selection with and without the extensions.
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/gl_state_saver.hpp"
#include "aerial/headless.hpp"
#include "gl_test_context.hpp"

namespace {

using aerial::gl::Api;
using aerial::gl::ApplyOptions;
using aerial::gl::Path;
using aerial::headless::Context;

constexpr int kSize = 64;    // pixels, square
constexpr int kGrid = 12;    // vertices per side of the mesh
constexpr int kTexels = 16;  // texture size, square

// A terrain-like mesh in front of the eye: screen positions for GL, world positions (metres)
// for the model, texture coordinates, and F_ex / L_in from aerial::shade_into.
struct Scene {
    std::vector<float> screen;  // x, y, z in NDC (identity matrices), z from -0.9 to -0.1
    std::vector<float> world;   // x, y, z metres
    std::vector<float> texcoords;
    std::vector<unsigned short> indices;
    std::vector<std::uint8_t> fex, lin;
    std::vector<std::uint8_t> texels;
};

Scene make_scene(const std::string& preset, double sun_elevation_deg) {
    Scene s;
    for (int j = 0; j < kGrid; ++j) {
        for (int i = 0; i < kGrid; ++i) {
            const float u = float(i) / float(kGrid - 1), v = float(j) / float(kGrid - 1);
            s.screen.insert(s.screen.end(), {-0.95f + 1.9f * u, -0.95f + 1.9f * v,
                                             -0.9f + 0.8f * v + 0.03f * std::sin(7.0f * u)});
            s.world.insert(s.world.end(),
                           {-8000.0f + 16000.0f * u, 300.0f + 30000.0f * v * v,
                            20.0f + 400.0f * std::sin(3.0f * u) * std::sin(2.0f * v)});
            s.texcoords.insert(s.texcoords.end(), {1.7f * u, 1.3f * v});
        }
    }
    for (int j = 0; j + 1 < kGrid; ++j) {
        for (int i = 0; i + 1 < kGrid; ++i) {
            const auto a = static_cast<unsigned short>(j * kGrid + i);
            const auto b = static_cast<unsigned short>(a + 1);
            const auto c = static_cast<unsigned short>(a + kGrid);
            const auto d = static_cast<unsigned short>(c + 1);
            s.indices.insert(s.indices.end(), {a, b, d, a, d, c});
        }
    }
    for (int t = 0; t < kTexels * kTexels; ++t) {
        const int x = t % kTexels, y = t / kTexels;
        s.texels.insert(s.texels.end(),
                        {static_cast<std::uint8_t>(60 + (x * 37 + y * 11) % 190),
                         static_cast<std::uint8_t>(80 + (x * 13 + y * 29) % 170),
                         static_cast<std::uint8_t>(40 + (x * 7 + y * 23) % 210), 255});
    }

    auto atmosphere = aerial::atmosphere_preset(preset);
    EXPECT_TRUE(atmosphere.ok()) << preset;
    aerial::View view;
    view.eye = {0.0, 0.0, 150.0};
    const double e = sun_elevation_deg * aerial::kPi / 180.0;
    view.sun_dir = glm::normalize(glm::dvec3(0.3 * std::cos(e), std::cos(e), std::sin(e)));
    auto frame = aerial::prepare_frame<float>(*atmosphere, view, aerial::Model::hoffman_preetham);
    EXPECT_TRUE(frame.ok());
    const std::size_t n = s.world.size() / 3;
    // The primary colour is F_ex × 0.75 (a lit colour, as lit_rgba8 gives), and the exposure
    // keeps 0.75 F_ex + L_in <= 0.98 at every vertex (and the brightest L_in <= 0.9): where the
    // sum passes 1, GL clamps it at different stages in the different paths (colour sum, texture
    // combiner, framebuffer), which fog then shows; that is not what these tests measure.
    constexpr float kPrimaryScale = 0.75f;
    std::vector<float> fex_rgb(3 * n), lin_rgb(3 * n);
    aerial::BatchOutputs raw;
    raw.extinction_rgb = fex_rgb.data();
    raw.in_scattering_rgb = lin_rgb.data();
    EXPECT_TRUE(aerial::shade_into(*frame, aerial::Positions::aos(s.world.data(), n), raw).ok());
    float brightest = 1e-6f, exposure = 1e30f;
    for (std::size_t i = 0; i < 3 * n; ++i) {
        brightest = std::max(brightest, lin_rgb[i]);
        if (lin_rgb[i] > 0.0f) {
            exposure = std::min(exposure, (0.98f - kPrimaryScale * fex_rgb[i]) / lin_rgb[i]);
        }
    }
    exposure = std::min(exposure, 0.9f / brightest);
    s.fex.resize(4 * n);
    s.lin.resize(4 * n);
    aerial::BatchOutputs out;
    out.in_scattering_rgba8 = s.lin.data();
    aerial::BatchSettings settings;
    settings.display.exposure = exposure;
    EXPECT_TRUE(
        aerial::shade_into(*frame, aerial::Positions::aos(s.world.data(), n), out, settings).ok());
    for (std::size_t v = 0; v < n; ++v) {
        for (std::size_t c = 0; c < 3; ++c) {
            s.fex[4 * v + c] = aerial::to_unorm8(kPrimaryScale * fex_rgb[3 * v + c]);
        }
        s.fex[4 * v + 3] = 255;
    }
    return s;
}

enum class Fog { off, on };

// The engine: its texture on unit 0, its arrays, depth test, optional fog with its own colour.
class Engine {
  public:
    explicit Engine(const Api& gl, const Scene& scene) : gl_(gl), scene_(scene) {
        gl_.GenTextures(1, &texture_);
        gl_.BindTexture(GL_TEXTURE_2D, texture_);
        gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kTexels, kTexels, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                       scene_.texels.data());
    }
    ~Engine() { gl_.DeleteTextures(1, &texture_); }

    void set_up(Fog fog, bool textured = true) {
        gl_.Viewport(0, 0, kSize, kSize);
        gl_.MatrixMode(GL_PROJECTION);
        gl_.LoadIdentity();
        gl_.MatrixMode(GL_MODELVIEW);
        gl_.LoadIdentity();
        gl_.ClearColor(0.1f, 0.2f, 0.3f, 1.0f);
        gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        gl_.Enable(GL_DEPTH_TEST);
        gl_.DepthFunc(GL_LESS);
        if (gl_.ActiveTexture) gl_.ActiveTexture(GL_TEXTURE0);
        if (gl_.ClientActiveTexture) gl_.ClientActiveTexture(GL_TEXTURE0);
        gl_.BindTexture(GL_TEXTURE_2D, texture_);
        (textured ? gl_.Enable : gl_.Disable)(GL_TEXTURE_2D);
        gl_.EnableClientState(GL_VERTEX_ARRAY);
        gl_.VertexPointer(3, GL_FLOAT, 0, scene_.screen.data());
        gl_.EnableClientState(GL_TEXTURE_COORD_ARRAY);
        gl_.TexCoordPointer(2, GL_FLOAT, 0, scene_.texcoords.data());
        if (fog == Fog::on) {
            // Linear fog over the mesh's depth: f from 0.95 (near) to 0.5 (far), a warm colour.
            static constexpr GLfloat kFogColour[4] = {0.9f, 0.55f, 0.3f, 1.0f};
            gl_.Enable(GL_FOG);
            gl_.Fogi(GL_FOG_MODE, GL_LINEAR);
            gl_.Fogf(GL_FOG_START, -0.9f);
            gl_.Fogf(GL_FOG_END, 1.9f);
            gl_.Fogfv(GL_FOG_COLOR, kFogColour);
        } else {
            gl_.Disable(GL_FOG);
        }
    }

    void draw() const {
        gl_.DrawElements(GL_TRIANGLES, static_cast<GLsizei>(scene_.indices.size()),
                         GL_UNSIGNED_SHORT, scene_.indices.data());
    }

    GLuint texture() const { return texture_; }

    aerial::gl::VertexColours colours() const {
        aerial::gl::VertexColours c;
        c.primary = scene_.fex.data();
        c.secondary = scene_.lin.data();
        c.vertex_count = scene_.fex.size() / 4;
        return c;
    }

  private:
    const Api& gl_;
    const Scene& scene_;
    GLuint texture_ = 0;
};

class FixedFunction : public aerial_test::DrawingTest<kSize, kSize> {
  protected:
    // Renders the scene along `path`; fails the test if the path cannot run here.
    std::vector<std::uint8_t> render(const Scene& scene, Path path, Fog fog, bool textured = true,
                                     aerial::gl::CombinerTexture* combiner = nullptr) {
        Engine engine(gl(), scene);
        engine.set_up(fog, textured);
        ApplyOptions options;
        options.path = path;
        options.textured = textured;
        options.combiner = combiner;
        auto stats =
            aerial::gl::draw_with_colours(gl(), options, engine.colours(), [&] { engine.draw(); });
        EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
        if (stats.ok()) {
            EXPECT_EQ(stats->passes, path == Path::two_pass ? 2 : 1);
            EXPECT_EQ(stats->path, path);
        }
        EXPECT_EQ(gl().GetError(), static_cast<GLenum>(GL_NO_ERROR)) << aerial::gl::path_name(path);
        return ctx_->read_rgba8();
    }

    bool offers(Path path) const { return aerial::gl::choose_path(gl().caps, path).ok(); }

    /// For each path the context offers: the image render() gives of `scene` with `fog`, then an
    /// engine set up for it again, handed with the image to `variation(path, engine, expected)`,
    /// which changes the engine's setup, draws along `path` and compares. Stops at the first
    /// fatal failure.
    template <typename Variation>
    void each_path_against_its_plain_image(const Scene& scene, Fog fog, Variation&& variation) {
        for (Path path : {Path::secondary_color, Path::combiner, Path::two_pass}) {
            if (!offers(path)) continue;
            const auto expected = render(scene, path, fog);
            Engine engine(gl(), scene);
            engine.set_up(fog);
            variation(path, engine, expected);
            if (HasFatalFailure()) return;
        }
    }
};

TEST_F(FixedFunction, PathsAgreeWithin1LsbOnATexturedMesh) {
    // Every pair of the paths the context offers, the combiner with its default 16³ identity
    // texture. The minimal 2³ texture is measured too and reported, not asserted (see
    // aerial::gl::CombinerTexture for why it is not the default).
    struct Variant {
        std::string name;
        Path path;
        int combiner_size;
        bool asserted;
    };
    std::vector<Variant> variants;
    if (offers(Path::secondary_color)) {
        variants.push_back({"secondary-color", Path::secondary_color, 0, true});
    }
    if (offers(Path::combiner)) {
        variants.push_back({"combiner", Path::combiner, 16, true});
        variants.push_back({"combiner (2x2x2)", Path::combiner, 2, false});
    }
    variants.push_back({"two-pass", Path::two_pass, 0, true});
    if (variants.size() < 2) GTEST_SKIP() << "only two passes on GL " << gl().caps.version;
    std::vector<std::optional<aerial::gl::CombinerTexture>> textures(variants.size());
    for (std::size_t v = 0; v < variants.size(); ++v) {
        if (variants[v].combiner_size == 0) continue;
        auto t = aerial::gl::CombinerTexture::create(gl(), variants[v].combiner_size);
        ASSERT_TRUE(t.ok()) << t.error().message;
        textures[v].emplace(std::move(t).value());
    }
    const std::size_t n = variants.size();
    std::vector<int> worst(n * n, 0);
    std::vector<std::size_t> over1(n * n, 0), differ(n * n, 0);
    int renderings = 0;
    for (const char* preset : {"earth", "hazy", "foggy"}) {
        for (double sun : {5.0, 40.0}) {
            const Scene scene = make_scene(preset, sun);
            for (Fog fog : {Fog::off, Fog::on}) {
                for (bool textured : {true, false}) {
                    const std::string where = std::string(preset) + " sun " + std::to_string(sun) +
                                              (fog == Fog::on ? " fog" : "") +
                                              (textured ? " textured" : " untextured");
                    std::vector<std::vector<std::uint8_t>> images;
                    for (std::size_t v = 0; v < n; ++v) {
                        images.push_back(render(scene, variants[v].path, fog, textured,
                                                textures[v] ? &*textures[v] : nullptr));
                    }
                    ++renderings;
                    for (std::size_t a = 0; a < n; ++a) {
                        for (std::size_t b = a + 1; b < n; ++b) {
                            const auto d = aerial_test::compare_rgb(images[a], images[b]);
                            worst[a * n + b] = std::max(worst[a * n + b], d.max_lsb);
                            over1[a * n + b] += d.over1;
                            differ[a * n + b] += d.differ;
                            if (!variants[a].asserted || !variants[b].asserted) continue;
                            EXPECT_LE(d.max_lsb, 1)
                                << where << ": " << variants[a].name << " "
                                << aerial_test::pixel_text(images[a], d.pixel) << " vs "
                                << variants[b].name << " "
                                << aerial_test::pixel_text(images[b], d.pixel) << " at pixel "
                                << d.pixel << " (" << d.over1 << " pixels over 1 LSB)";
                        }
                    }
                }
            }
        }
    }
    for (std::size_t a = 0; a < n; ++a) {
        for (std::size_t b = a + 1; b < n; ++b) {
            std::printf(
                "[ info     ] %s: max |%s - %s| = %d LSB (of %d pixels, %zu differ, %zu "
                "by more than 1 LSB)\n",
                aerial_test::context_label(*ctx_).c_str(), variants[a].name.c_str(),
                variants[b].name.c_str(), worst[a * n + b], renderings * kSize * kSize,
                differ[a * n + b], over1[a * n + b]);
        }
    }
}

TEST_F(FixedFunction, EachPathGivesTextureTimesExtinctionPlusInScattering) {
    // Absolute, not only path against path: 8 × 8 flat quads, each with one F_ex and L_in from
    // shade_into at its own world position on all four vertices, under a one-texel texture, so
    // every pixel of a quad must be T × F_ex + L_in (8-bit: T F / 255 rounded, plus L, clamped).
    constexpr int kQuads = 8;
    auto atmosphere = aerial::atmosphere_preset("hazy");
    ASSERT_TRUE(atmosphere.ok());
    aerial::View view;
    view.eye = {0.0, 0.0, 200.0};
    view.sun_dir = glm::normalize(glm::dvec3(0.0, 0.8, 0.6));
    auto frame = aerial::prepare_frame<float>(*atmosphere, view, aerial::Model::hoffman_preetham);
    ASSERT_TRUE(frame.ok());
    std::vector<float> world;
    for (int q = 0; q < kQuads * kQuads; ++q) {
        const float d = 100.0f * std::pow(1.12f, float(q));  // 100 m .. 140 km
        const float a = 0.37f * float(q);
        world.insert(world.end(), {d * std::cos(a), d * std::sin(a), 50.0f + 3.0f * float(q)});
    }
    const std::size_t n = world.size() / 3;
    std::vector<std::uint8_t> fex(4 * n), lin(4 * n);
    aerial::BatchOutputs out;
    out.extinction_rgba8 = fex.data();
    out.in_scattering_rgba8 = lin.data();
    aerial::BatchSettings settings;
    settings.display.exposure = 12.0f;
    ASSERT_TRUE(
        aerial::shade_into(*frame, aerial::Positions::aos(world.data(), n), out, settings).ok());
    // Four vertices a quad, all with the quad's colours.
    std::vector<float> screen, texcoords;
    std::vector<std::uint8_t> quad_fex, quad_lin;
    for (int q = 0; q < kQuads * kQuads; ++q) {
        const float x0 = -1.0f + 2.0f * float(q % kQuads) / kQuads;
        const float y0 = -1.0f + 2.0f * float(q / kQuads) / kQuads;
        const float step = 2.0f / kQuads;
        for (const auto& corner : {std::array<float, 2>{0, 0}, std::array<float, 2>{1, 0},
                                   std::array<float, 2>{1, 1}, std::array<float, 2>{0, 1}}) {
            screen.insert(screen.end(), {x0 + step * corner[0], y0 + step * corner[1], 0.0f});
            texcoords.insert(texcoords.end(), {0.5f, 0.5f});
            const auto qi = static_cast<std::size_t>(q);
            quad_fex.insert(quad_fex.end(), &fex[4 * qi], &fex[4 * qi] + 4);
            quad_lin.insert(quad_lin.end(), &lin[4 * qi], &lin[4 * qi] + 4);
        }
    }
    const std::uint8_t texel[4] = {210, 160, 90, 255};
    GLuint texture = 0;
    gl().GenTextures(1, &texture);
    gl().BindTexture(GL_TEXTURE_2D, texture);
    gl().TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl().TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl().TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, texel);
    gl().Enable(GL_TEXTURE_2D);
    gl().Enable(GL_DEPTH_TEST);
    gl().Viewport(0, 0, kSize, kSize);
    gl().EnableClientState(GL_VERTEX_ARRAY);
    gl().VertexPointer(3, GL_FLOAT, 0, screen.data());
    gl().EnableClientState(GL_TEXTURE_COORD_ARRAY);
    gl().TexCoordPointer(2, GL_FLOAT, 0, texcoords.data());
    aerial::gl::VertexColours colours;
    colours.primary = quad_fex.data();
    colours.secondary = quad_lin.data();
    colours.vertex_count = quad_fex.size() / 4;
    for (Path path : {Path::secondary_color, Path::combiner, Path::two_pass}) {
        if (!offers(path)) continue;
        gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        ApplyOptions options;
        options.path = path;
        auto stats = aerial::gl::draw_with_colours(gl(), options, colours, [&] {
            gl().DrawArrays(GL_QUADS, 0, static_cast<GLsizei>(colours.vertex_count));
        });
        ASSERT_TRUE(stats.ok()) << stats.error().message;
        const auto image = ctx_->read_rgba8();
        int worst = 0;
        std::string where;
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                const int q = (y * kQuads / kSize) * kQuads + x * kQuads / kSize;
                const std::size_t p = 4 * static_cast<std::size_t>((kSize - 1 - y) * kSize + x);
                for (std::size_t c = 0; c < 3; ++c) {
                    const int f = fex[4 * static_cast<std::size_t>(q) + c];
                    const int l = lin[4 * static_cast<std::size_t>(q) + c];
                    const int expected = std::min(255, (texel[c] * f + 127) / 255 + l);
                    const int d = std::abs(int(image[p + c]) - expected);
                    if (d > worst) {
                        worst = d;
                        where = "quad " + std::to_string(q) + " channel " + std::to_string(c) +
                                ": got " + std::to_string(image[p + c]) + ", expected " +
                                std::to_string(expected) + " (T " + std::to_string(texel[c]) +
                                ", F_ex " + std::to_string(f) + ", L_in " + std::to_string(l) + ")";
                    }
                }
            }
        }
        EXPECT_LE(worst, 1) << aerial::gl::path_name(path) << " " << where;
    }
    gl().DisableClientState(GL_VERTEX_ARRAY);
    gl().DisableClientState(GL_TEXTURE_COORD_ARRAY);
    gl().DeleteTextures(1, &texture);
}

TEST_F(FixedFunction, TextureOnAnotherUnitGivesTheSameImage) {
    // The engine's texture on unit 1 (unit 0 off): ApplyOptions::texture_unit = 1, and the
    // combiner path then uses unit 2.
    if (gl().caps.max_texture_units < 3) GTEST_SKIP() << "fewer than 3 texture units";
    const Scene scene = make_scene("earth", 20.0);
    each_path_against_its_plain_image(
        scene, Fog::on,
        [&](Path path, const Engine& engine, const std::vector<std::uint8_t>& expected) {
            gl().Disable(GL_TEXTURE_2D);
            gl().DisableClientState(GL_TEXTURE_COORD_ARRAY);
            gl().ActiveTexture(GL_TEXTURE1);
            gl().BindTexture(GL_TEXTURE_2D, engine.texture());
            gl().Enable(GL_TEXTURE_2D);
            gl().ClientActiveTexture(GL_TEXTURE1);
            gl().EnableClientState(GL_TEXTURE_COORD_ARRAY);
            gl().TexCoordPointer(2, GL_FLOAT, 0, scene.texcoords.data());
            const auto before = aerial::gl::capture_state(gl());
            ApplyOptions options;
            options.path = path;
            options.texture_unit = 1;
            auto stats = aerial::gl::draw_with_colours(gl(), options, engine.colours(),
                                                       [&] { engine.draw(); });
            ASSERT_TRUE(stats.ok()) << stats.error().message;
            EXPECT_TRUE(
                aerial::gl::state_differences(before, aerial::gl::capture_state(gl())).empty());
            const auto d = aerial_test::compare_rgb(expected, ctx_->read_rgba8());
            EXPECT_EQ(d.max_lsb, 0) << aerial::gl::path_name(path) << " on unit 1";
            gl().Disable(GL_TEXTURE_2D);
            gl().DisableClientState(GL_TEXTURE_COORD_ARRAY);
            gl().ActiveTexture(GL_TEXTURE0);
            gl().ClientActiveTexture(GL_TEXTURE0);
        });
}

TEST_F(FixedFunction, SecondPassWithTheEnginesFogColourIsVisiblyWrong) {
    // The two-pass path with the second pass fogged towards the engine's colour, as a naive
    // implementation would do it: the fog colour is added twice.
    const Path one_pass = offers(Path::secondary_color) ? Path::secondary_color : Path::combiner;
    if (!offers(one_pass)) GTEST_SKIP() << "no single-pass path to compare with";
    const Scene scene = make_scene("earth", 20.0);
    const auto single = render(scene, one_pass, Fog::on);
    const auto ours = render(scene, Path::two_pass, Fog::on);

    Engine engine(gl(), scene);
    engine.set_up(Fog::on);
    gl().TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    gl().EnableClientState(GL_COLOR_ARRAY);
    gl().ColorPointer(4, GL_UNSIGNED_BYTE, 0, scene.fex.data());
    engine.draw();
    gl().Disable(GL_TEXTURE_2D);
    gl().ColorPointer(4, GL_UNSIGNED_BYTE, 0, scene.lin.data());
    gl().Enable(GL_BLEND);
    gl().BlendFunc(GL_ONE, GL_ONE);
    gl().DepthFunc(GL_EQUAL);
    gl().DepthMask(GL_FALSE);
    engine.draw();
    const auto naive = ctx_->read_rgba8();
    gl().DepthMask(GL_TRUE);
    gl().DepthFunc(GL_LESS);
    gl().Disable(GL_BLEND);
    gl().DisableClientState(GL_COLOR_ARRAY);

    const auto d_ours = aerial_test::compare_rgb(single, ours);
    const auto d_naive = aerial_test::compare_rgb(single, naive);
    std::printf(
        "[ info     ] %s: two-pass vs single pass with fog: %d LSB with black fog in pass "
        "2, %d LSB with the engine's fog colour left on\n",
        aerial_test::context_label(*ctx_).c_str(), d_ours.max_lsb, d_naive.max_lsb);
    EXPECT_LE(d_ours.max_lsb, 1);
    EXPECT_GT(d_naive.max_lsb, 8) << "the fog colour added twice should show";
}

TEST_F(FixedFunction, WithGlLightingOnTheCombinerAndTwoPassesAgree) {
    if (!offers(Path::combiner)) GTEST_SKIP() << "no combiner path";
    // The engine lights its mesh with GL: one directional light, scene ambient, normals that
    // vary over the mesh. F_ex feeds the material through colour tracking.
    using LightFv = void (*)(GLenum, GLenum, const GLfloat*);
    using LightModelFv = void (*)(GLenum, const GLfloat*);
    auto light_fv = reinterpret_cast<LightFv>(ctx_->loader()(ctx_->loader_user(), "glLightfv"));
    auto light_model_fv =
        reinterpret_cast<LightModelFv>(ctx_->loader()(ctx_->loader_user(), "glLightModelfv"));
    ASSERT_TRUE(light_fv && light_model_fv);
    const Scene scene = make_scene("hazy", 30.0);
    std::vector<float> normals;
    for (std::size_t v = 0; v < scene.world.size() / 3; ++v) {
        const glm::vec3 n = glm::normalize(
            glm::vec3(0.6f * std::sin(0.7f * float(v)), 0.4f * std::cos(0.3f * float(v)), 1.0f));
        normals.insert(normals.end(), {n.x, n.y, n.z});
    }
    auto render_lit = [&](ApplyOptions options) {
        Engine engine(gl(), scene);
        engine.set_up(Fog::on);
        static constexpr GLfloat kDirection[4] = {0.3f, 0.5f, 0.8f, 0.0f};
        static constexpr GLfloat kDiffuse[4] = {0.7f, 0.65f, 0.6f, 1.0f};
        static constexpr GLfloat kAmbient[4] = {0.25f, 0.3f, 0.35f, 1.0f};
        light_fv(GL_LIGHT0, GL_POSITION, kDirection);
        light_fv(GL_LIGHT0, GL_DIFFUSE, kDiffuse);
        light_model_fv(GL_LIGHT_MODEL_AMBIENT, kAmbient);
        gl().Enable(GL_LIGHT0);
        gl().Enable(GL_LIGHTING);
        gl().EnableClientState(GL_NORMAL_ARRAY);
        gl().NormalPointer(GL_FLOAT, 0, normals.data());
        const auto before = aerial::gl::capture_state(gl());
        auto stats =
            aerial::gl::draw_with_colours(gl(), options, engine.colours(), [&] { engine.draw(); });
        EXPECT_TRUE(stats.ok()) << (stats.ok() ? "" : stats.error().message);
        const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
        std::string list;
        for (const std::string& line : changed) list += "\n  " + line;
        EXPECT_TRUE(changed.empty()) << aerial::gl::path_name(options.path) << " changed:" << list;
        gl().Disable(GL_LIGHTING);
        gl().DisableClientState(GL_NORMAL_ARRAY);
        return std::make_pair(stats.ok() ? stats->path : Path::automatic, ctx_->read_rgba8());
    };
    ApplyOptions lit;
    lit.fixed_function_lighting = true;
    const auto automatic = render_lit(lit);
    EXPECT_EQ(automatic.first, Path::combiner) << "GL lighting ignores the secondary colour";
    lit.path = Path::two_pass;
    const auto two_pass = render_lit(lit);
    lit.path = Path::combiner;
    const auto combiner = render_lit(lit);
    const auto d = aerial_test::compare_rgb(combiner.second, two_pass.second);
    EXPECT_LE(d.max_lsb, 1) << "combiner " << aerial_test::pixel_text(combiner.second, d.pixel)
                            << " vs two-pass " << aerial_test::pixel_text(two_pass.second, d.pixel);
    // Lighting did something: the same draw with lighting switched off looks different.
    ApplyOptions unlit;
    unlit.path = Path::combiner;
    const auto flat = render_lit(unlit);
    EXPECT_GT(aerial_test::compare_rgb(combiner.second, flat.second).max_lsb, 10);
    std::printf("[ info     ] %s: GL lighting on, max |combiner - two-pass| = %d LSB\n",
                aerial_test::context_label(*ctx_).c_str(), d.max_lsb);

    lit.path = Path::secondary_color;
    int calls = 0;
    Engine engine(gl(), scene);
    auto r = aerial::gl::draw_with_colours(gl(), lit, engine.colours(), [&] { ++calls; });
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "fixed_function_lighting");
    EXPECT_EQ(calls, 0);
}

// ---- State -------------------------------------------------------------------------------------

// Engine state that differs from GL's defaults in everything a path touches, so that a path
// that forgot to restore something shows in the snapshot.
void unusual_engine_state(const Api& gl, const Scene& scene, std::vector<GLuint>& textures) {
    gl.Enable(GL_FOG);
    static constexpr GLfloat kFogColour[4] = {0.25f, 0.5f, 0.75f, 1.0f};
    gl.Fogfv(GL_FOG_COLOR, kFogColour);
    gl.Enable(GL_BLEND);
    gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LEQUAL);
    gl.Enable(GL_LIGHTING);
    gl.ShadeModel(GL_FLAT);
    gl.ColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_TRUE);
    gl.Color4f(0.5f, 0.25f, 0.125f, 0.75f);
    const Api& a = gl;
    textures.resize(4);
    gl.GenTextures(4, textures.data());
    const int units = std::min(a.caps.max_texture_units, 3);
    for (int u = 0; u < units; ++u) {
        if (a.ActiveTexture) a.ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + u));
        gl.BindTexture(GL_TEXTURE_2D, textures[static_cast<std::size_t>(u)]);
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kTexels, kTexels, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                      scene.texels.data());
        gl.Enable(GL_TEXTURE_2D);
        gl.TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, u == 1 ? GL_DECAL : GL_REPLACE);
        if (a.ClientActiveTexture) a.ClientActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + u));
        gl.EnableClientState(GL_TEXTURE_COORD_ARRAY);
        gl.TexCoordPointer(2, GL_FLOAT, 8 + 4 * u, scene.texcoords.data());
    }
    if (a.caps.texture_3d && units > 1) {
        a.ActiveTexture(GL_TEXTURE1);
        gl.BindTexture(GL_TEXTURE_3D, textures[3]);
    }
    if (a.ActiveTexture) a.ActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(units - 1));
    if (a.ClientActiveTexture) a.ClientActiveTexture(GL_TEXTURE0);
    gl.EnableClientState(GL_VERTEX_ARRAY);
    gl.VertexPointer(3, GL_FLOAT, 0, scene.screen.data());
    gl.ColorPointer(3, GL_FLOAT, 12, scene.world.data());  // disabled, but pointed somewhere
}

TEST_F(FixedFunction, EveryPathLeavesTheGlStateAsItFoundIt) {
    const Scene scene = make_scene("earth", 20.0);
    std::vector<GLuint> textures;
    unusual_engine_state(gl(), scene, textures);
    aerial::gl::CombinerTexture* none = nullptr;
    auto combiner = aerial::gl::CombinerTexture::create(gl());
    for (Path path : {Path::secondary_color, Path::combiner, Path::two_pass}) {
        if (!offers(path)) continue;
        for (bool textured : {true, false}) {
            for (aerial::gl::CombinerTexture* c :
                 {none, combiner.ok() ? &combiner.value() : none}) {
                const auto before = aerial::gl::capture_state(gl());
                ASSERT_GT(before.entries.size(), 30u);
                ApplyOptions options;
                options.path = path;
                options.textured = textured;
                options.combiner = c;
                aerial::gl::VertexColours colours;
                colours.primary = scene.fex.data();
                colours.secondary = scene.lin.data();
                colours.vertex_count = scene.fex.size() / 4;
                auto stats = aerial::gl::draw_with_colours(gl(), options, colours, [&] {
                    gl().DrawElements(GL_TRIANGLES, static_cast<GLsizei>(scene.indices.size()),
                                      GL_UNSIGNED_SHORT, scene.indices.data());
                });
                ASSERT_TRUE(stats.ok()) << stats.error().message;
                const auto changed =
                    aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
                std::string list;
                for (const std::string& line : changed) list += "\n  " + line;
                EXPECT_TRUE(changed.empty())
                    << aerial::gl::path_name(path) << (textured ? "" : " untextured")
                    << (c ? " with a CombinerTexture" : "") << " changed:" << list;
                EXPECT_EQ(gl().GetError(), static_cast<GLenum>(GL_NO_ERROR));
            }
        }
    }
    gl().DeleteTextures(static_cast<GLsizei>(textures.size()), textures.data());
}

TEST_F(FixedFunction, WorksWithTheEnginesVertexBufferBound) {
    // An engine whose positions live in a buffer object and which leaves GL_ARRAY_BUFFER bound:
    // the module's colour arrays must still come from client memory, and the binding stays.
    if (!gl().caps.vertex_buffer_object) GTEST_SKIP() << "no vertex buffer objects";
    using GenBuffers = void (*)(GLsizei, GLuint*);
    using DeleteBuffers = void (*)(GLsizei, const GLuint*);
    using BufferData = void (*)(GLenum, GLsizeiptr, const void*, GLenum);
    auto gen = reinterpret_cast<GenBuffers>(ctx_->loader()(ctx_->loader_user(), "glGenBuffers"));
    auto del =
        reinterpret_cast<DeleteBuffers>(ctx_->loader()(ctx_->loader_user(), "glDeleteBuffers"));
    auto data = reinterpret_cast<BufferData>(ctx_->loader()(ctx_->loader_user(), "glBufferData"));
    ASSERT_TRUE(gen && del && data);
    const Scene scene = make_scene("earth", 20.0);
    each_path_against_its_plain_image(
        scene, Fog::off,
        [&](Path path, const Engine& engine, const std::vector<std::uint8_t>& expected) {
            GLuint buffer = 0;
            gen(1, &buffer);
            gl().BindBuffer(GL_ARRAY_BUFFER, buffer);
            data(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(scene.screen.size() * sizeof(float)),
                 scene.screen.data(), GL_STATIC_DRAW);
            gl().VertexPointer(3, GL_FLOAT, 0, nullptr);  // offset 0 in the buffer
            const auto before = aerial::gl::capture_state(gl());
            EXPECT_EQ(*before.find("GL_ARRAY_BUFFER_BINDING"), std::to_string(buffer));
            ApplyOptions options;
            options.path = path;
            auto stats = aerial::gl::draw_with_colours(gl(), options, engine.colours(),
                                                       [&] { engine.draw(); });
            ASSERT_TRUE(stats.ok()) << stats.error().message;
            const auto changed =
                aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
            std::string list;
            for (const std::string& line : changed) list += "\n  " + line;
            EXPECT_TRUE(changed.empty()) << aerial::gl::path_name(path) << " changed:" << list;
            EXPECT_EQ(gl().GetError(), static_cast<GLenum>(GL_NO_ERROR));
            const auto d = aerial_test::compare_rgb(expected, ctx_->read_rgba8());
            EXPECT_EQ(d.max_lsb, 0) << aerial::gl::path_name(path)
                                    << ": the image changed with the positions in a buffer";
            gl().BindBuffer(GL_ARRAY_BUFFER, 0);
            del(1, &buffer);
        });
}

// A driver that reports a value GL rejects when given back (zink: GL_MATRIX_MODE 0 on a fresh
// context), fed to the saver through an Api whose glGetIntegerv lies about the matrix mode and
// the depth function.
void (*real_get_integerv)(GLenum, GLint*) = nullptr;
void lying_get_integerv(GLenum pname, GLint* value) {
    real_get_integerv(pname, value);
    if (pname == GL_MATRIX_MODE || pname == GL_DEPTH_FUNC) *value = 0;
}

TEST_F(FixedFunction, StateSaverNeverRestoresAValueGlRejects) {
    Api lying = gl();
    real_get_integerv = gl().GetIntegerv;
    lying.GetIntegerv = lying_get_integerv;
    while (gl().GetError() != GL_NO_ERROR) {
    }
    std::vector<std::string> rejected;
    {
        aerial::gl::StateSaver saver(lying);
        const GLfloat identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        saver.load_matrix(GL_PROJECTION, identity);
        saver.depth_func(GL_LEQUAL);
        saver.restore();
        rejected = saver.rejected();
    }
    EXPECT_EQ(gl().GetError(), static_cast<GLenum>(GL_NO_ERROR))
        << "restoring what the driver reported raised a GL error";
    ASSERT_EQ(rejected.size(), 2u);
    EXPECT_EQ(rejected[0],
              "GL_MATRIX_MODE: the driver reported 0x0000, which GL does not accept back; "
              "restored as its initial value 0x1700");
    EXPECT_EQ(rejected[1].rfind("GL_DEPTH_FUNC: the driver reported 0x0000", 0), 0u) << rejected[1];
    GLint mode = 0, depth = 0;
    gl().GetIntegerv(GL_MATRIX_MODE, &mode);
    gl().GetIntegerv(GL_DEPTH_FUNC, &depth);
    EXPECT_EQ(mode, GL_MODELVIEW);
    EXPECT_EQ(depth, GL_LESS);
}

TEST_F(FixedFunction, SnapshotNamesWhatChanged) {
    const auto before = aerial::gl::capture_state(gl());
    gl().Enable(GL_BLEND);
    gl().BlendFunc(GL_ONE, GL_ONE);
    const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
    ASSERT_FALSE(changed.empty());
    EXPECT_EQ(changed[0], "GL_BLEND: GL_FALSE -> GL_TRUE");
    bool named_blend_dst = false;
    for (const auto& line : changed) named_blend_dst |= line.find("GL_BLEND_DST") == 0;
    EXPECT_TRUE(named_blend_dst);
    gl().Disable(GL_BLEND);
    gl().BlendFunc(GL_ONE, GL_ZERO);
}

// ---- Errors and path selection ---------------------------------------------------------------

TEST_F(FixedFunction, CombinerTextureTakesOnlySizesWithExactTexels) {
    if (!gl().caps.texture_3d) GTEST_SKIP() << "no 3D textures";
    for (int size : {2, 4, 6, 16, 18}) {
        auto t = aerial::gl::CombinerTexture::create(gl(), size);
        ASSERT_TRUE(t.ok()) << size << ": " << t.error().message;
        aerial::gl::CombinerTexture moved = std::move(t).value();
        EXPECT_EQ(moved.size(), size);
        EXPECT_NE(moved.id(), 0u);
        // L_in codes 0 and 255 land on the first and last texel centres.
        const std::uint8_t lin[8] = {0, 0, 0, 255, 255, 255, 255, 255};
        aerial::gl::VertexColours c;
        c.primary = c.secondary = lin;
        c.vertex_count = 2;
        const float* tc = moved.texcoords_for(c);
        EXPECT_FLOAT_EQ(tc[0], 0.5f / float(size));
        EXPECT_FLOAT_EQ(tc[3], 1.0f - 0.5f / float(size));
    }
    for (int size : {0, 1, 3, 5, 17, 19, 256}) {
        auto t = aerial::gl::CombinerTexture::create(gl(), size);
        ASSERT_FALSE(t.ok()) << size;
        EXPECT_EQ(t.error().field, "size");
    }
    EXPECT_EQ(gl().GetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST_F(FixedFunction, BadInputIsAnErrorAndDrawsNothing) {
    const Scene scene = make_scene("earth", 20.0);
    Engine engine(gl(), scene);
    engine.set_up(Fog::off);
    int calls = 0;
    auto count = [&] { ++calls; };
    aerial::gl::VertexColours colours = engine.colours();
    ApplyOptions options;

    colours.primary = nullptr;
    auto r = aerial::gl::draw_with_colours(gl(), options, colours, count);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "colours.primary");
    colours = engine.colours();
    colours.secondary_stride_bytes = 3;
    r = aerial::gl::draw_with_colours(gl(), options, colours, count);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "colours.secondary_stride_bytes");
    EXPECT_EQ(r.error().message,
              "aerial::gl::draw_with_colours(): colours.secondary_stride_bytes: expected 0 "
              "(packed) or 4 .. 2147483647 bytes, got 3");
    colours = engine.colours();
    options.texture_unit = gl().caps.max_texture_units;
    r = aerial::gl::draw_with_colours(gl(), options, colours, count);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "texture_unit");
    if (offers(Path::combiner)) {
        options.texture_unit = gl().caps.max_texture_units - 1;
        options.path = Path::combiner;
        r = aerial::gl::draw_with_colours(gl(), options, colours, count);
        ASSERT_FALSE(r.ok()) << "the combiner path needs the unit after texture_unit";
        EXPECT_EQ(r.error().field, "texture_unit");
    }
    r = aerial::gl::draw_with_colours(gl(), ApplyOptions{}, colours, {});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "draw");
    EXPECT_EQ(calls, 0);
}

TEST_F(FixedFunction, AutomaticChoiceFollowsTheContext) {
    const aerial::gl::Caps& caps = gl().caps;
    auto path = aerial::gl::choose_path(caps, Path::automatic);
    ASSERT_TRUE(path.ok());
    const Path expected = caps.secondary_color                            ? Path::secondary_color
                          : (caps.texture_env_combine && caps.texture_3d) ? Path::combiner
                                                                          : Path::two_pass;
    EXPECT_EQ(*path, expected) << caps.version;
    std::printf(
        "[ info     ] %s, GL %s: automatic path %s (secondary colour %s: GL >= 1.4 %s, "
        "GL_EXT_secondary_color %s)\n",
        aerial_test::context_label(*ctx_).c_str(), caps.version.c_str(),
        aerial::gl::path_name(*path), caps.secondary_color ? "yes" : "no",
        caps.at_least(1, 4) ? "yes" : "no",
        caps.has_extension("GL_EXT_secondary_color") ? "listed" : "not listed");
    // Whatever it chose draws.
    const Scene scene = make_scene("earth", 20.0);
    Engine engine(gl(), scene);
    engine.set_up(Fog::off);
    auto stats = aerial::gl::draw_with_colours(gl(), ApplyOptions{}, engine.colours(),
                                               [&] { engine.draw(); });
    ASSERT_TRUE(stats.ok()) << stats.error().message;
    EXPECT_EQ(stats->path, expected);
    // A forced path the context lacks is an error naming what is missing, and draws nothing.
    if (!caps.secondary_color) {
        ApplyOptions forced;
        forced.path = Path::secondary_color;
        int calls = 0;
        auto r = aerial::gl::draw_with_colours(gl(), forced, engine.colours(), [&] { ++calls; });
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().field, "GL_EXT_secondary_color");
        EXPECT_EQ(calls, 0);
    }
}

aerial::gl::Caps caps_of(int major, int minor, const std::string& extensions) {
    aerial::gl::Caps caps;
    caps.version_major = major;
    caps.version_minor = minor;
    caps.extensions = extensions;
    return caps;
}

TEST(ChoosePath, FollowsVersionThenExtensions) {
    // What load_api derives from version and extension string (see gl_api.cpp).
    aerial::gl::Caps gl11 = caps_of(1, 1, "");
    auto p = aerial::gl::choose_path(gl11, Path::automatic);
    ASSERT_TRUE(p.ok());
    EXPECT_EQ(*p, Path::two_pass);
    for (Path forced : {Path::secondary_color, Path::combiner}) {
        auto r = aerial::gl::choose_path(gl11, forced);
        ASSERT_FALSE(r.ok()) << aerial::gl::path_name(forced);
        EXPECT_EQ(
            r.error().message.rfind("aerial::gl::choose_path(): " + r.error().field + ": ", 0), 0u)
            << r.error().message;
        EXPECT_EQ(r.error().kind, aerial::ErrorKind::not_supported) << r.error().message;
    }
    EXPECT_EQ(aerial::gl::choose_path(gl11, Path::secondary_color).error().field,
              "GL_EXT_secondary_color");
    EXPECT_EQ(aerial::gl::choose_path(gl11, Path::combiner).error().field, "GL_ARB_multitexture");

    aerial::gl::Caps gl13 = caps_of(1, 3, "GL_ARB_multitexture GL_ARB_texture_env_combine");
    gl13.multitexture = gl13.texture_env_combine = gl13.texture_3d = true;
    gl13.max_texture_units = 4;
    EXPECT_EQ(*aerial::gl::choose_path(gl13, Path::automatic), Path::combiner);
    gl13.texture_3d = false;
    EXPECT_EQ(aerial::gl::choose_path(gl13, Path::combiner).error().field, "GL_EXT_texture3D");
    EXPECT_EQ(*aerial::gl::choose_path(gl13, Path::automatic), Path::two_pass);

    aerial::gl::Caps gl14 = gl13;
    gl14.secondary_color = true;  // core in 1.4, whatever the extension string says
    EXPECT_EQ(*aerial::gl::choose_path(gl14, Path::automatic), Path::secondary_color);
    EXPECT_EQ(*aerial::gl::choose_path(gl14, Path::two_pass), Path::two_pass);
}

TEST(ChoosePath, NamesParseBack) {
    for (Path p : {Path::automatic, Path::secondary_color, Path::combiner, Path::two_pass}) {
        auto parsed = aerial::gl::parse_path(aerial::gl::path_name(p));
        ASSERT_TRUE(parsed.has_value()) << aerial::gl::path_name(p);
        EXPECT_EQ(*parsed, p);
    }
    EXPECT_FALSE(aerial::gl::parse_path("secondary_color").has_value());
}

}  // namespace
