// GL state hygiene and bad data with a context.
//
// State hygiene per path: an engine's unusual state (far from GL's defaults, so a "reset to
// default" shows up as a difference) is set up, each path of the module draws, and the whole
// snapshot of aerial/gl_state.hpp must be unchanged: cpu secondary colour, combiner and two
// passes, the ARB 2002 and height programs, the sky box and sun sprite, and the scene renderer
// (cpu with the dome and the cubemap sky, arb).
// Bad data: no current context, paths and programs the context lacks or rejects, scene meshes
// with non-finite, empty, degenerate, non-manifold and 1e7 m geometry: a clear error naming what
// is wrong (or a valid frame), the engine's state restored, and the renderer's caches intact.
#include <algorithm>
#include <array>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "aerial/aerial.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/headless.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/scene_sky.hpp"
#include "aerial/sky_gl.hpp"
#include "gl_test_context.hpp"
#include "scene_test_support.hpp"

namespace {

using aerial::gl::Path;
using namespace aerial::scene;

constexpr int kWidth = 96, kHeight = 64;

// Entry points the engine sets state with that the module's Api does not carry.
using PolygonOffsetFn = void (*)(GLfloat, GLfloat);
using EnumFn = void (*)(GLenum);
using EnumEnumFn = void (*)(GLenum, GLenum);
using AlphaFuncFn = void (*)(GLenum, GLclampf);
using Normal3fFn = void (*)(GLfloat, GLfloat, GLfloat);
using TexGeniFn = void (*)(GLenum, GLenum, GLint);
using StencilFuncFn = void (*)(GLenum, GLint, GLuint);

struct SmallWorld;

class StateHygiene : public aerial_test::SceneDrawingTest<kWidth, kHeight> {
  protected:
    void TearDown() override {
        if (!ctx_) return;
        if (!textures_.empty()) {
            gl().DeleteTextures(GLsizei(textures_.size()), textures_.data());
        }
        if (engine_program_ != 0) gl().DeletePrograms(1, &engine_program_);
    }

    template <typename Fn>
    Fn proc(const char* name) {
        void* p = ctx_->loader()(ctx_->loader_user(), name);
        EXPECT_NE(p, nullptr) << name;
        return reinterpret_cast<Fn>(p);
    }

    /// An engine in the middle of its frame: every piece of state the module may touch, and
    /// more, set away from GL's defaults.
    void set_unusual_engine_state() {
        const aerial::gl::Api& g = gl();
        const aerial::gl::Caps& caps = g.caps;
        g.Viewport(3, 2, kWidth - 7, kHeight - 5);
        g.Enable(GL_SCISSOR_TEST);
        g.Scissor(1, 1, kWidth - 2, kHeight - 2);
        g.Enable(GL_FOG);
        g.Fogi(GL_FOG_MODE, GL_EXP2);
        g.Fogf(GL_FOG_DENSITY, 0.25f);
        g.Fogf(GL_FOG_START, 3.0f);
        g.Fogf(GL_FOG_END, 70.0f);
        const GLfloat fog[4] = {0.3f, 0.4f, 0.5f, 0.6f};
        g.Fogfv(GL_FOG_COLOR, fog);
        g.Enable(GL_BLEND);
        if (g.BlendFuncSeparate) {
            g.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ZERO);
        } else {
            g.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        }
        if (g.BlendEquation) g.BlendEquation(GL_FUNC_REVERSE_SUBTRACT);
        g.Enable(GL_LIGHTING);
        g.Enable(GL_NORMALIZE);
        g.Enable(GL_COLOR_MATERIAL);
        g.ColorMaterial(GL_FRONT, GL_DIFFUSE);
        const GLfloat ambient[4] = {0.1f, 0.2f, 0.3f, 0.9f};
        g.Materialfv(GL_BACK, GL_AMBIENT, ambient);
        g.Enable(GL_DEPTH_TEST);
        g.DepthFunc(GL_GREATER);
        g.DepthMask(GL_FALSE);
        g.ColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_TRUE);
        g.Enable(GL_ALPHA_TEST);
        proc<AlphaFuncFn>("glAlphaFunc")(GL_GEQUAL, 0.25f);
        g.Enable(GL_CULL_FACE);
        proc<EnumFn>("glCullFace")(GL_FRONT);
        proc<EnumFn>("glFrontFace")(GL_CW);
        g.Enable(GL_POLYGON_OFFSET_FILL);
        proc<PolygonOffsetFn>("glPolygonOffset")(1.5f, 2.0f);
        proc<EnumEnumFn>("glPolygonMode")(GL_BACK, GL_LINE);
        g.Enable(GL_STENCIL_TEST);
        proc<StencilFuncFn>("glStencilFunc")(GL_ALWAYS, 1, 0xffu);
        g.ShadeModel(GL_FLAT);
        g.Color4f(0.9f, 0.8f, 0.7f, 0.6f);
        if (g.SecondaryColor3f) g.SecondaryColor3f(0.25f, 0.5f, 0.75f);
        proc<Normal3fFn>("glNormal3f")(0.0f, 0.6f, 0.8f);
        g.PixelStorei(GL_UNPACK_ALIGNMENT, 2);
        g.PixelStorei(GL_UNPACK_ROW_LENGTH, 5);

        // Matrices: an extra modelview level, odd projection, texture matrix on unit 0, the
        // matrix mode left at GL_TEXTURE.
        g.MatrixMode(GL_PROJECTION);
        const GLfloat projection[16] = {2, 0, 0, 0, 0, 3, 0, 0, 0, 0, -1.1f, -1, 0, 0, -2, 0};
        g.LoadMatrixf(projection);
        g.MatrixMode(GL_MODELVIEW);
        g.PushMatrix();
        const GLfloat modelview[16] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1};
        g.LoadMatrixf(modelview);

        // Textures: a 2D texture on units 0 and 1 with odd env modes, texgen, a texture matrix.
        const int units = caps.multitexture ? std::min(2, caps.max_texture_units) : 1;
        textures_.resize(std::size_t(units));
        g.GenTextures(GLsizei(units), textures_.data());
        const std::array<std::uint8_t, 16> texels{200, 100, 50, 255, 10, 20, 30, 255,
                                                  40,  50,  60, 255, 70, 80, 90, 255};
        for (int u = 0; u < units; ++u) {
            if (caps.multitexture) {
                g.ActiveTexture(GLenum(GL_TEXTURE0 + u));
                g.ClientActiveTexture(GLenum(GL_TEXTURE0 + u));
            }
            g.BindTexture(GL_TEXTURE_2D, textures_[std::size_t(u)]);
            g.PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
            g.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 2, 2, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                         texels.data());
            g.PixelStorei(GL_UNPACK_ROW_LENGTH, 5);
            g.Enable(GL_TEXTURE_2D);
            g.TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, u == 0 ? GL_DECAL : GL_BLEND);
            const GLfloat env[4] = {0.1f, 0.9f, 0.2f, 0.8f};
            g.TexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, env);
            proc<TexGeniFn>("glTexGeni")(GL_S, GL_TEXTURE_GEN_MODE, GL_EYE_LINEAR);
            g.Enable(GL_TEXTURE_GEN_S);
            g.TexCoord4f(0.25f, 0.75f, 0.5f, 2.0f);
            g.EnableClientState(GL_TEXTURE_COORD_ARRAY);
            g.TexCoordPointer(3, GL_FLOAT, 24, engine_floats_.data() + u);
        }
        g.MatrixMode(GL_TEXTURE);
        const GLfloat texture_matrix[16] = {1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0.5f, 0, 0, 1};
        g.LoadMatrixf(texture_matrix);  // the last unit's texture matrix
        // The engine leaves the last unit active for the server and unit 0 for the client.
        if (caps.multitexture) g.ClientActiveTexture(GL_TEXTURE0);

        // Client arrays: the vertex array on, colour and secondary colour pointed but off.
        g.EnableClientState(GL_VERTEX_ARRAY);
        g.VertexPointer(4, GL_FLOAT, 32, engine_floats_.data());
        g.ColorPointer(3, GL_FLOAT, 20, engine_floats_.data() + 1);
        g.EnableClientState(GL_NORMAL_ARRAY);
        g.NormalPointer(GL_FLOAT, 12, engine_floats_.data() + 2);
        if (g.SecondaryColorPointer) {
            g.SecondaryColorPointer(3, GL_FLOAT, 16, engine_floats_.data() + 3);
        }

        // The engine's own ARB program bound (and disabled: it is between its draws), with env
        // and local parameters the module must leave alone.
        if (caps.vertex_program) {
            const char* text = "!!ARBvp1.0\nMOV result.position, vertex.position;\nEND\n";
            g.GenPrograms(1, &engine_program_);
            g.BindProgram(GL_VERTEX_PROGRAM_ARB, engine_program_);
            g.ProgramString(GL_VERTEX_PROGRAM_ARB, GL_PROGRAM_FORMAT_ASCII_ARB,
                            GLsizei(std::char_traits<char>::length(text)), text);
            for (GLuint i = 0; i < 96; ++i) {
                const GLfloat v[4] = {float(i), -float(i), 0.5f, 2.0f};
                g.ProgramEnvParameter4fv(GL_VERTEX_PROGRAM_ARB, i, v);
                const GLfloat w[4] = {-float(i), 0.25f, float(i), 3.0f};
                g.ProgramLocalParameter4fv(GL_VERTEX_PROGRAM_ARB, i, w);
            }
        }
        ASSERT_EQ(g.GetError(), GLenum(GL_NO_ERROR)) << "setting up the engine's state";
    }

    /// Expects `what` to have left every piece of captured state as it found it.
    template <typename Fn>
    void expect_restored(const char* what, Fn&& fn) {
        SCOPED_TRACE(what);
        const auto before = aerial::gl::capture_state(gl());
        ASSERT_GT(before.entries.size(), 60u);  // 84 on GL 1.1, several hundred on 4.5
        fn();
        const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
        std::string list;
        for (const std::string& line : changed) list += "\n  " + line;
        EXPECT_TRUE(changed.empty()) << what << " changed:" << list;
        EXPECT_EQ(gl().GetError(), GLenum(GL_NO_ERROR)) << what;
    }

    /// Where the bad-data tests start: the engine's unusual state, a cpu renderer (renderer_)
    /// and `first`, its frame of `world` drawn onto a frame cleared as an engine clears it
    /// (clear_frame). Call it through ASSERT_NO_FATAL_FAILURE.
    void draw_first_frame(const SmallWorld& world, std::vector<std::uint8_t>& first);

    std::vector<GLuint> textures_;
    GLuint engine_program_ = 0;
    std::array<float, 64> engine_floats_{};
    std::optional<SceneRenderer> renderer_;
};

/// The triangle the path and program tests draw: world positions 2 to 3 km in front of the eye.
constexpr std::array<float, 9> kTriangle{-500, 2000, 0, 500, 2000, 0, 0, 3000, 300};

/// The engine's draw of kTriangle, in immediate mode.
void draw_triangle(const aerial::gl::Api& g) {
    g.Begin(GL_TRIANGLES);
    for (std::size_t v = 0; v < 3; ++v) {
        g.Vertex3f(kTriangle[3 * v], kTriangle[3 * v + 1], kTriangle[3 * v + 2]);
    }
    g.End();
}

/// Shaded colours of kTriangle's vertices in a hazy view: real F_ex and L_in.
struct Colours {
    std::vector<std::uint8_t> fex, lin;
};

Colours shaded_triangle() {
    Colours c;
    auto atmosphere = aerial::atmosphere_preset("hazy");
    aerial::View view;
    view.eye = {0, 0, 50};
    view.sun_dir = glm::normalize(glm::dvec3(0.2, 0.9, 0.3));
    auto frame = aerial::prepare_frame<float>(*atmosphere, view, aerial::Model::height);
    c.fex.resize(12);
    c.lin.resize(12);
    aerial::BatchOutputs outputs;
    outputs.extinction_rgba8 = c.fex.data();
    outputs.in_scattering_rgba8 = c.lin.data();
    aerial::BatchSettings settings;
    settings.display.exposure = 8.0f;
    auto stats =
        aerial::shade_into(*frame, aerial::Positions::aos(kTriangle.data(), 3), outputs, settings);
    EXPECT_TRUE(stats) << stats.error().message;
    return c;
}

TEST_F(StateHygiene, TheSnapshotSeesTheEnginesUnusualState) {
    // Were a piece of state not read, the tests below could not see it change.
    set_unusual_engine_state();
    const auto s = aerial::gl::capture_state(gl());
    const auto expect = [&](const char* name, const char* value) {
        const std::string* v = s.find(name);
        ASSERT_NE(v, nullptr) << name << " is not in the snapshot";
        EXPECT_EQ(*v, value) << name;
    };
    expect("GL_FOG_MODE", "GL_EXP2");
    expect("GL_FOG_DENSITY", "0.25");
    expect("GL_POLYGON_OFFSET_FILL", "GL_TRUE");
    expect("GL_POLYGON_OFFSET_FACTOR", "1.5");
    expect("GL_POLYGON_OFFSET_UNITS", "2");
    expect("GL_POLYGON_MODE", "GL_FILL GL_LINE");
    expect("GL_CULL_FACE_MODE", "GL_FRONT");
    expect("GL_FRONT_FACE", "GL_CW");
    expect("GL_ALPHA_TEST_FUNC", "GL_GEQUAL");
    expect("GL_MATRIX_MODE", "GL_TEXTURE");
    expect("GL_MODELVIEW_STACK_DEPTH", "2");
    expect("GL_VIEWPORT", "3 2 89 59");
    expect("GL_CURRENT_NORMAL", "0 0.600000024 0.800000012");
    expect("unit 0 GL_TEXTURE_GEN_S", "GL_TRUE");
    expect("unit 0 GL_TEXTURE_ENV_MODE", "GL_DECAL");
    if (gl().caps.vertex_program) {
        expect("program.env[5]", "5 -5 0.5 2");
        expect("program.local[7]", "-7 0.25 7 3");
    }
}

TEST_F(StateHygiene, EveryFixedFunctionPathRestoresTheEnginesState) {
    set_unusual_engine_state();
    const Colours c = shaded_triangle();
    auto combiner = aerial::gl::CombinerTexture::create(gl());
    int drawn = 0;
    for (Path path : {Path::secondary_color, Path::combiner, Path::two_pass}) {
        if (!aerial::gl::choose_path(gl().caps, path)) continue;
        for (bool textured : {true, false}) {
            const std::string what =
                std::string(aerial::gl::path_name(path)) + (textured ? " textured" : " untextured");
            expect_restored(what.c_str(), [&] {
                aerial::gl::ApplyOptions options;
                options.path = path;
                options.textured = textured;
                options.combiner = combiner ? &combiner.value() : nullptr;
                aerial::gl::VertexColours colours;
                colours.primary = c.fex.data();
                colours.secondary = c.lin.data();
                colours.vertex_count = 3;
                auto stats = aerial::gl::draw_with_colours(gl(), options, colours,
                                                           [&] { draw_triangle(gl()); });
                ASSERT_TRUE(stats) << stats.error().message;
                ++drawn;
            });
        }
    }
    EXPECT_GE(drawn, 2) << "two passes are always available";
}

TEST_F(StateHygiene, ArbProgramsRestoreTheEnginesStateAndParameters) {
    if (!gl().caps.vertex_program) GTEST_SKIP() << "no GL_ARB_vertex_program here";
    set_unusual_engine_state();
    auto atmosphere = aerial::atmosphere_preset("earth");
    for (aerial::Model model : {aerial::Model::hoffman_preetham, aerial::Model::height}) {
        const std::string what = "ARB program " + std::string(aerial::model_name(model));
        expect_restored(what.c_str(), [&] {
            aerial::ArbProgramOptions options;
            options.model = model;
            auto generated = aerial::generate_arb_program(options);
            ASSERT_TRUE(generated) << generated.error().message;
            auto program = aerial::gl::ArbVertexProgram::create(gl(), *generated);
            ASSERT_TRUE(program) << program.error().message;
            auto frame = aerial::prepare_frame<float>(*atmosphere, aerial::View{}, model);
            auto params = aerial::arb_program_parameters(*frame, aerial::Display{}, options);
            ASSERT_TRUE(params) << params.error().message;
            ASSERT_FALSE(program->set_parameters(*params).has_value());
            for (bool textured : {true, false}) {
                aerial::gl::ApplyOptions apply;
                apply.textured = textured;
                auto stats = program->draw([&] { draw_triangle(gl()); }, apply);
                ASSERT_TRUE(stats) << stats.error().message;
            }
        });
    }
}

TEST_F(StateHygiene, SkyBoxAndSunSpriteRestoreTheEnginesState) {
    set_unusual_engine_state();
    aerial::View view;
    view.eye = {0.0, 0.0, 100.0};
    view.sun_dir = glm::normalize(glm::dvec3(0.9, 0.4, 0.2));
    auto sky = aerial::prepare_sky(*aerial::atmosphere_preset("earth"), view,
                                   aerial::SkyMethod::height_chained);
    ASSERT_TRUE(sky) << sky.error().message;
    constexpr int kSize = 8;
    auto cubemap = aerial::compute_sky_cubemap(*sky, kSize);
    ASSERT_TRUE(cubemap) << cubemap.error().message;
    const auto faces = aerial::cubemap_to_rgba8(*cubemap, 8.0, aerial::ToneCurve::exponential);
    auto texture = aerial::gl::SkyCubemapTexture::create(gl(), faces, kSize);
    if (!texture) {
        EXPECT_EQ(texture.error().field, "cube_map") << texture.error().message;
        GTEST_SKIP() << "no cube maps here: " << texture.error().message;
    }
    expect_restored("sky box and sun sprite", [&] {
        auto second = aerial::gl::SkyCubemapTexture::create(gl(), faces, kSize);
        ASSERT_TRUE(second) << second.error().message;
        auto sprite = aerial::make_sun_sprite(*sky, 8.0, aerial::ToneCurve::exponential);
        ASSERT_TRUE(sprite) << sprite.error().message;
        auto sun = aerial::gl::SunSpriteTexture::create(gl(), *sprite);
        ASSERT_TRUE(sun) << sun.error().message;
        const auto box_view = aerial::gl::sky_box_view_from_current_matrices(gl());
        ASSERT_FALSE(aerial::gl::draw_sky_box(gl(), *second, box_view).has_value());
        ASSERT_FALSE(
            aerial::gl::draw_sun_sprite(gl(), *sun, box_view, sky->view.sun_dir).has_value());
        ASSERT_FALSE(second.value().update(faces, kSize).has_value());
        ASSERT_FALSE(sun.value().update(*sprite).has_value());
    });
}

/// A small world: two terrain tiles, a box, the sky dome and the sun.
std::unique_ptr<Node> small_world() {
    auto root = make_group("world");
    root->add(make_sky_dome());
    root->add(make_sun());
    ProceduralTerrain terrain;
    terrain.amplitude = 200;
    for (int i = 0; i < 2; ++i) {
        HeightfieldSpec spec;
        spec.origin_x = -1000.0 + 1000.0 * i;
        spec.origin_y = 0;
        spec.size = 1000;
        spec.resolution = 9;
        auto mesh = heightfield_mesh(
            spec, [&](double x, double y) { return procedural_height(terrain, x, y); });
        root->add(make_terrain_tile("tile " + std::to_string(i),
                                    std::make_shared<MeshData>(std::move(mesh.value())), nullptr,
                                    glm::vec3(0.2f)));
    }
    return root;
}

/// The small world with what its tests draw it with: a camera 800 m before the tiles and 300 m
/// up, hazy air with the sun well above the horizon.
struct SmallWorld {
    std::unique_ptr<Node> root = small_world();
    Camera camera =
        aerial_test::scene_camera({0, -800, 300}, {0, 1000, 0}, double(kWidth) / kHeight);
    FrameSettings settings = aerial_test::hazy_frame({0.3, 0.8, 0.4});
};

TEST_F(StateHygiene, SceneRendererRestoresTheEnginesStateOnEveryBackendAndSky) {
    set_unusual_engine_state();
    SmallWorld world;
    struct Case {
        const char* what;
        Backend backend;
        bool cubemap;
        aerial::Model model;
        bool moon = false;  ///< the sun and the moon both lighting the frame
    };
    for (const Case& k :
         {Case{"renderer cpu dome", Backend::cpu, false, aerial::Model::height},
          Case{"renderer cpu cubemap", Backend::cpu, true, aerial::Model::height},
          Case{"renderer arb hoffman-preetham", Backend::arb, false,
               aerial::Model::hoffman_preetham},
          Case{"renderer arb height cubemap", Backend::arb, true, aerial::Model::height},
          Case{"renderer cpu cubemap, sun and moon", Backend::cpu, true, aerial::Model::height,
               true},
          Case{"renderer arb height, sun and moon (two passes)", Backend::arb, false,
               aerial::Model::height, true}}) {
        if (k.backend == Backend::arb && !gl().caps.vertex_program) continue;
        expect_restored(k.what, [&] {
            RendererOptions options;
            options.backend = k.backend;
            auto renderer = SceneRenderer::create(gl(), options);
            ASSERT_TRUE(renderer) << renderer.error().message;
            if (k.cubemap) {
                auto stats = install_cubemap_sky(renderer.value(), gl());
                if (!stats) {  // GL 1.1: no cube maps, the renderer keeps its dome
                    EXPECT_EQ(stats.error().field, "cube_map") << stats.error().message;
                }
            }
            FrameSettings settings = world.settings;
            settings.model = k.model;
            if (k.moon) {
                settings.moon =
                    aerial::scene::Moonlight{glm::normalize(glm::dvec3(0, -1, 1)), 1e-4};
                settings.policy = false;  // both lights, whatever they add
            }
            for (int frame = 0; frame < 2; ++frame) {  // the second one from the caches
                auto report = renderer.value().render(*world.root, world.camera, settings);
                ASSERT_TRUE(report) << report.error().message;
                if (k.moon) {
                    EXPECT_EQ(report->lights, aerial::scene::Lights::both) << k.what;
                }
            }
        });
    }
}

// ---- Bad data ---------------------------------------------------------------------------------

using MakeCurrentOsmesaFn = GLboolean (*)(void*, void*, GLenum, GLsizei, GLsizei);
using GetCurrentDisplayFn = void* (*)();
using MakeCurrentEglFn = unsigned (*)(void*, void*, void*, void*);

/// Releases the current context of this thread through the context's own loader; false when
/// the platform does not give the entry point.
bool release_current(const aerial::headless::Context& context) {
    const auto load = context.loader();
    void* user = context.loader_user();
    if (context.platform() == aerial::headless::Platform::osmesa) {
        auto make_current = reinterpret_cast<MakeCurrentOsmesaFn>(load(user, "OSMesaMakeCurrent"));
        return make_current != nullptr && make_current(nullptr, nullptr, 0, 0, 0);
    }
    auto display = reinterpret_cast<GetCurrentDisplayFn>(load(user, "eglGetCurrentDisplay"));
    auto make_current = reinterpret_cast<MakeCurrentEglFn>(load(user, "eglMakeCurrent"));
    return display != nullptr && make_current != nullptr &&
           make_current(display(), nullptr, nullptr, nullptr) != 0;
}

/// Clears colour and depth as an engine starts its frame, whatever its depth write mask: the
/// unusual state has depth writes off, under which glClear leaves the depth buffer undefined.
void clear_frame(const aerial::gl::Api& g) {
    GLboolean depth_writes = GL_TRUE;
    g.GetBooleanv(GL_DEPTH_WRITEMASK, &depth_writes);
    g.DepthMask(GL_TRUE);
    g.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    g.DepthMask(depth_writes);
}

void StateHygiene::draw_first_frame(const SmallWorld& world, std::vector<std::uint8_t>& first) {
    set_unusual_engine_state();
    auto created = SceneRenderer::create(gl());
    ASSERT_TRUE(created) << created.error().message;
    renderer_.emplace(std::move(created.value()));
    clear_frame(gl());
    ASSERT_TRUE(renderer_->render(*world.root, world.camera, world.settings));
    first = ctx_->read_rgba8();
}

TEST_F(StateHygiene, NoCurrentContextIsAnErrorNamingTheContextEverywhere) {
    const SmallWorld world;
    std::vector<std::uint8_t> first;
    ASSERT_NO_FATAL_FAILURE(draw_first_frame(world, first));
    const auto before = aerial::gl::capture_state(gl());
    if (!release_current(*ctx_)) GTEST_SKIP() << "cannot release the context here";

    const auto is_context_error = [](const aerial::Error& e) {
        return e.field == "context" &&
               e.message.find("no GL context is current") != std::string::npos;
    };
    auto reloaded = aerial::gl::load_api(ctx_->loader(), ctx_->loader_user());
    ASSERT_FALSE(reloaded);
    EXPECT_EQ(reloaded.error().field, "glGetString") << reloaded.error().message;
    auto created = SceneRenderer::create(gl());
    ASSERT_FALSE(created);
    EXPECT_TRUE(is_context_error(created.error())) << created.error().message;
    auto rendered = renderer_->render(*world.root, world.camera, world.settings);
    ASSERT_FALSE(rendered);
    EXPECT_TRUE(is_context_error(rendered.error())) << rendered.error().message;
    const Colours c = shaded_triangle();
    aerial::gl::VertexColours colours;
    colours.primary = c.fex.data();
    colours.secondary = c.lin.data();
    colours.vertex_count = 3;
    bool called = false;
    auto drawn = aerial::gl::draw_with_colours(gl(), {}, colours, [&] { called = true; });
    ASSERT_FALSE(drawn);
    EXPECT_TRUE(is_context_error(drawn.error())) << drawn.error().message;
    EXPECT_FALSE(called) << "the engine's draw callback must not run without a context";
    auto combiner = aerial::gl::CombinerTexture::create(gl());
    ASSERT_FALSE(combiner);
    EXPECT_TRUE(is_context_error(combiner.error())) << combiner.error().message;
    auto generated = aerial::generate_arb_program(aerial::ArbProgramOptions{});
    ASSERT_TRUE(generated);
    auto program = aerial::gl::ArbVertexProgram::create(gl(), *generated);
    ASSERT_FALSE(program);
    EXPECT_TRUE(is_context_error(program.error())) << program.error().message;
    std::array<std::vector<std::uint8_t>, 6> faces;
    for (auto& f : faces) f.assign(4 * 4 * 4, 128);
    auto cube = aerial::gl::SkyCubemapTexture::create(gl(), faces, 4);
    ASSERT_FALSE(cube);
    EXPECT_TRUE(is_context_error(cube.error())) << cube.error().message;

    ASSERT_FALSE(ctx_->make_current().has_value());
    const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
    std::string list;
    for (const std::string& line : changed) list += "\n  " + line;
    EXPECT_TRUE(changed.empty()) << "calls without a context changed:" << list;
    // Nothing the renderer had is lost: the same frame again, from its caches.
    clear_frame(gl());
    ASSERT_TRUE(renderer_->render(*world.root, world.camera, world.settings));
    const auto second = ctx_->read_rgba8();
    const auto d = aerial_test::compare_rgb(first, second);
    EXPECT_EQ(d.max_lsb, 0) << "the frame after the calls without a context differs at pixel "
                            << d.pixel << ": " << aerial_test::pixel_text(first, d.pixel)
                            << " then " << aerial_test::pixel_text(second, d.pixel) << " ("
                            << d.differ << " pixels differ)";
}

TEST_F(StateHygiene, APathOrProgramTheContextLacksIsAnErrorAndChangesNothing) {
    set_unusual_engine_state();
    const Colours c = shaded_triangle();
    int missing = 0;
    for (Path path : {Path::secondary_color, Path::combiner, Path::two_pass}) {
        const auto chosen = aerial::gl::choose_path(gl().caps, path);
        if (chosen) continue;
        ++missing;
        SCOPED_TRACE(aerial::gl::path_name(path));
        const auto before = aerial::gl::capture_state(gl());
        RendererOptions options;
        options.path = path;
        auto renderer = SceneRenderer::create(gl(), options);
        ASSERT_FALSE(renderer);
        EXPECT_EQ(renderer.error().field, chosen.error().field) << renderer.error().message;
        aerial::gl::ApplyOptions apply;
        apply.path = path;
        aerial::gl::VertexColours colours;
        colours.primary = c.fex.data();
        colours.secondary = c.lin.data();
        colours.vertex_count = 3;
        bool called = false;
        auto drawn = aerial::gl::draw_with_colours(gl(), apply, colours, [&] { called = true; });
        ASSERT_FALSE(drawn);
        EXPECT_EQ(drawn.error().field, chosen.error().field) << drawn.error().message;
        EXPECT_FALSE(called);
        EXPECT_TRUE(aerial::gl::state_differences(before, aerial::gl::capture_state(gl())).empty());
    }
    const auto before = aerial::gl::capture_state(gl());
    if (!gl().caps.vertex_program) {
        ++missing;
        RendererOptions options;
        options.backend = Backend::arb;
        auto renderer = SceneRenderer::create(gl(), options);
        ASSERT_FALSE(renderer);
        EXPECT_EQ(renderer.error().field, "GL_ARB_vertex_program") << renderer.error().message;
    } else {
        // A program the driver rejects: the error names the position, the engine's program
        // stays bound with its parameters.
        aerial::ArbProgram garbage;
        garbage.text = "!!ARBvp1.0\nTEMP t;\nFROB t, vertex.position;\nEND\n";
        garbage.resources.instructions = 1;
        garbage.resources.temporaries = 1;
        auto program = aerial::gl::ArbVertexProgram::create(gl(), garbage);
        ASSERT_FALSE(program);
        EXPECT_NE(program.error().message.find("GL_PROGRAM_ERROR_POSITION_ARB"), std::string::npos)
            << program.error().message;
        EXPECT_EQ(gl().GetError(), GLenum(GL_INVALID_OPERATION)) << "left to the engine";
    }
    const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(gl()));
    EXPECT_TRUE(changed.empty()) << changed.front();
    std::printf("[ info     ] paths or programs missing here: %d\n", missing);
}

std::shared_ptr<MeshData> mesh_of(std::vector<float> positions,
                                  std::vector<std::uint32_t> indices) {
    auto mesh = std::make_shared<MeshData>();
    mesh->positions = std::move(positions);
    mesh->indices = std::move(indices);
    return mesh;
}

TEST_F(StateHygiene, BadSceneMeshesAreAnErrorNamingTheNodeAndLoseNothing) {
    const SmallWorld good;
    const Camera& camera = good.camera;
    const FrameSettings& settings = good.settings;
    std::vector<std::uint8_t> first;
    ASSERT_NO_FATAL_FAILURE(draw_first_frame(good, first));

    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (float bad : {nan, inf, -inf}) {
        auto world = small_world();
        world->add(make_mesh("bad box", mesh_of({0, 0, 0, 10, 0, 0, 0, bad, 10}, {0, 1, 2})));
        const auto before = aerial::gl::capture_state(gl());
        auto report = renderer_->render(*world, camera, settings);
        ASSERT_FALSE(report);
        EXPECT_NE(report.error().field.find("bad box"), std::string::npos)
            << report.error().field << ": " << report.error().message;
        EXPECT_NE(report.error().message.find("positions"), std::string::npos)
            << report.error().message;
        EXPECT_TRUE(aerial::gl::state_differences(before, aerial::gl::capture_state(gl())).empty());
    }
    // The renderer's caches are intact: the good world draws as before.
    clear_frame(gl());
    ASSERT_TRUE(renderer_->render(*good.root, camera, settings));
    EXPECT_EQ(aerial_test::compare_rgb(first, ctx_->read_rgba8()).max_lsb, 0);

    // Empty, degenerate and non-manifold meshes, and a mesh 1e7 units away from the origin seen
    // from near it: valid frames, nothing crashes, the state is restored.
    auto odd = small_world();
    odd->add(make_mesh("empty", mesh_of({}, {})));
    odd->add(make_mesh("no triangles", mesh_of({0, 0, 0, 1, 1, 1}, {})));
    // Four triangles on one edge (non-manifold), one of zero area (collinear), one with a
    // repeated vertex, one sliver.
    odd->add(make_mesh("non-manifold and degenerate",
                       mesh_of({0,   100, 0,  0, 100, 50,  40, 120, 20,  -40, 120, 20, 30, 80,  30,
                                -30, 80,  10, 0, 100, 100, 0,  100, 150, 60,  100, 10, 61, 100, 10},
                               {0, 1, 2, 0, 1, 3, 0, 1, 4, 0, 1, 5, 0, 6, 7, 0, 6, 6, 8, 9, 0})));
    const auto before = aerial::gl::capture_state(gl());
    FrameReport odd_report;
    for (int frame = 0; frame < 2; ++frame) {
        clear_frame(gl());
        auto report = renderer_->render(*odd, camera, settings);
        ASSERT_TRUE(report) << report.error().message;
        odd_report = *report;
    }
    EXPECT_GT(odd_report.vertices_drawn, 0u);
    EXPECT_TRUE(aerial::gl::state_differences(before, aerial::gl::capture_state(gl())).empty());

    // 1e7 units: the same tiles moved there, the camera with them.
    const double far_away = 1e7;
    auto moved = small_world();
    moved->transform = glm::translate(glm::dmat4(1.0), glm::dvec3(far_away, -far_away, 0.0));
    Camera far_camera = camera;
    far_camera.eye += glm::dvec3(far_away, -far_away, 0.0);
    far_camera.target += glm::dvec3(far_away, -far_away, 0.0);
    clear_frame(gl());
    auto far_report = renderer_->render(*moved, far_camera, settings);
    ASSERT_TRUE(far_report) << far_report.error().message;
    EXPECT_GT(far_report->vertices_drawn, 0u) << "the moved tiles are in view";
    EXPECT_TRUE(aerial::gl::state_differences(before, aerial::gl::capture_state(gl())).empty());
}

}  // namespace
