// The integration guide's examples (docs/examples/*.c, included in docs/integration.md) run as
// an engine would run them, on a headless context: each draws the haze, leaves the GL state as
// it found it, and the GL 1.1 two-pass example and the ARB program agree within 2 LSB.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/aerial.h"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/headless.hpp"

extern "C" {
#include "engine.h"

int gl11_init(aerial_gl_load_function load, void* user);
int gl11_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count);
void gl11_shutdown(void);
int gl14_init(aerial_gl_load_function load, void* user);
int gl14_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count);
void gl14_shutdown(void);
int arb_init(aerial_gl_load_function load, void* user);
int arb_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count);
void arb_shutdown(void);
int material_init(aerial_gl_load_function load, void* user);
int material_frame(const engine_camera* camera, engine_mesh* meshes, size_t mesh_count);
void material_shutdown(void);
int one_colour_init(aerial_gl_load_function load, void* user);
int one_colour_frame(const engine_camera* camera, engine_coloured_mesh* meshes, size_t count);
void one_colour_shutdown(void);
int sky_init(void);
int sky_frame(const engine_camera* camera, engine_dome* dome);
void sky_shutdown(void);
}

namespace {

constexpr int kSize = 64;
const aerial::gl::Api* g_api = nullptr;

/// A 17 x 17 grid over [-1, 1]^2 at z = 0, drawn with identity matrices (so world x, y are the
/// normalised device coordinates); one engine unit is 20 km.
struct Grid {
    std::vector<float> xyz, normals, texcoords;
    std::vector<GLuint> indices;
    std::vector<std::uint8_t> primary, secondary;
    engine_mesh mesh{};
};

Grid make_grid() {
    Grid g;
    const int n = 17;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            g.xyz.insert(g.xyz.end(), {-1.0f + 2.0f * float(i) / float(n - 1),
                                       -1.0f + 2.0f * float(j) / float(n - 1), 0.0f});
            g.normals.insert(g.normals.end(), {0.0f, 0.0f, 1.0f});
            g.texcoords.insert(g.texcoords.end(), {0.5f, 0.5f});
        }
    }
    for (int j = 0; j + 1 < n; ++j) {
        for (int i = 0; i + 1 < n; ++i) {
            const GLuint a = GLuint(j * n + i), b = a + 1, c = a + GLuint(n), d = c + 1;
            g.indices.insert(g.indices.end(), {a, b, d, a, d, c});
        }
    }
    g.primary.resize(4 * std::size_t(n * n));
    g.secondary.resize(4 * std::size_t(n * n));
    g.mesh.xyz = g.xyz.data();
    g.mesh.normals = g.normals.data();
    g.mesh.vertex_count = std::size_t(n * n);
    g.mesh.primary = g.primary.data();
    g.mesh.secondary = g.secondary.data();
    return g;
}

Grid* g_grid = nullptr;

}  // namespace

extern "C" void engine_draw_mesh(void* mesh) {
    const auto* m = static_cast<const engine_mesh*>(mesh);
    const aerial::gl::Api& gl = *g_api;
    gl.EnableClientState(GL_VERTEX_ARRAY);
    gl.EnableClientState(GL_TEXTURE_COORD_ARRAY);
    gl.VertexPointer(3, GL_FLOAT, 0, m->xyz);
    gl.TexCoordPointer(2, GL_FLOAT, 0, g_grid->texcoords.data());
    gl.DrawElements(GL_TRIANGLES, GLsizei(g_grid->indices.size()), GL_UNSIGNED_INT,
                    g_grid->indices.data());
    gl.DisableClientState(GL_TEXTURE_COORD_ARRAY);
    gl.DisableClientState(GL_VERTEX_ARRAY);
}

extern "C" unsigned int engine_program_create(const char* text) {
    const aerial::gl::Api& gl = *g_api;
    GLuint id = 0;
    gl.GenPrograms(1, &id);
    gl.BindProgram(GL_VERTEX_PROGRAM_ARB, id);
    gl.ProgramString(GL_VERTEX_PROGRAM_ARB, GL_PROGRAM_FORMAT_ASCII_ARB, GLsizei(std::strlen(text)),
                     text);
    GLint error_at = -1;
    gl.GetIntegerv(GL_PROGRAM_ERROR_POSITION_ARB, &error_at);
    gl.BindProgram(GL_VERTEX_PROGRAM_ARB, 0);
    return error_at == -1 ? id : 0;
}

extern "C" void engine_program_local(unsigned int program, int index, const float vector[4]) {
    const aerial::gl::Api& gl = *g_api;
    gl.BindProgram(GL_VERTEX_PROGRAM_ARB, program);
    gl.ProgramLocalParameter4fv(GL_VERTEX_PROGRAM_ARB, GLuint(index), vector);
    gl.BindProgram(GL_VERTEX_PROGRAM_ARB, 0);
}

extern "C" void engine_program_draw(unsigned int program, engine_mesh* mesh) {
    const aerial::gl::Api& gl = *g_api;
    gl.BindProgram(GL_VERTEX_PROGRAM_ARB, program);
    gl.Enable(GL_VERTEX_PROGRAM_ARB);
    engine_draw_mesh(mesh);
    gl.Disable(GL_VERTEX_PROGRAM_ARB);
    gl.BindProgram(GL_VERTEX_PROGRAM_ARB, 0);
}

extern "C" void engine_draw_coloured(const engine_coloured_mesh* mesh, const unsigned int* colours,
                                     size_t stride) {
    const aerial::gl::Api& gl = *g_api;
    const auto s = GLsizei(sizeof(engine_vertex));
    gl.EnableClientState(GL_VERTEX_ARRAY);
    gl.EnableClientState(GL_TEXTURE_COORD_ARRAY);
    gl.EnableClientState(GL_COLOR_ARRAY);
    gl.VertexPointer(3, GL_FLOAT, s, mesh->vertices[0].xyz);
    gl.TexCoordPointer(2, GL_FLOAT, s, mesh->vertices[0].uv);
    gl.ColorPointer(GL_BGRA, GL_UNSIGNED_BYTE, GLsizei(stride), colours);  // ARGB32 words
    gl.DrawElements(GL_TRIANGLES, GLsizei(g_grid->indices.size()), GL_UNSIGNED_INT,
                    g_grid->indices.data());
    gl.DisableClientState(GL_COLOR_ARRAY);
    gl.DisableClientState(GL_TEXTURE_COORD_ARRAY);
    gl.DisableClientState(GL_VERTEX_ARRAY);
    // The pointers as the engine keeps them between draws (what run() compares against).
    gl.VertexPointer(3, GL_FLOAT, 0, g_grid->xyz.data());
    gl.TexCoordPointer(2, GL_FLOAT, 0, g_grid->texcoords.data());
    gl.ColorPointer(4, GL_FLOAT, 0, nullptr);
}

namespace {
int g_domes_drawn = 0;
}

extern "C" void engine_draw_dome(const engine_dome*) { ++g_domes_drawn; }

namespace {

/// One example: its init, its frame (drawing the grid its way) and its shutdown.
struct Example {
    const char* name;
    int (*init)(aerial_gl_load_function, void*);
    std::function<int(const engine_camera*, Grid&)> frame;
    void (*shutdown)();
};

/// The frame of an example that draws engine_mesh arrays.
std::function<int(const engine_camera*, Grid&)> mesh_frame(int (*frame)(const engine_camera*,
                                                                        engine_mesh*, size_t)) {
    return
        [frame](const engine_camera* camera, Grid& grid) { return frame(camera, &grid.mesh, 1); };
}

/// The one-colour example's frame: the grid as interleaved ARGB32 engine vertices.
int coloured_frame(const engine_camera* camera, Grid& grid) {
    std::vector<engine_vertex> vertices(grid.mesh.vertex_count);
    for (std::size_t v = 0; v < vertices.size(); ++v) {
        vertices[v] = {{grid.xyz[3 * v], grid.xyz[3 * v + 1], grid.xyz[3 * v + 2]},
                       0u,
                       {grid.texcoords[2 * v], grid.texcoords[2 * v + 1]}};
    }
    std::vector<unsigned int> in_scattering(vertices.size());
    engine_coloured_mesh mesh{vertices.data(), vertices.size(), in_scattering.data()};
    return one_colour_frame(camera, &mesh, 1);
}

/// Runs one example for one frame on a fresh context with a white texture bound (the engine's),
/// and returns the image.
std::vector<std::uint8_t> run(const Example& example) {
    auto ctx =
        aerial::headless::Context::create({aerial::headless::Platform::osmesa, kSize, kSize});
    EXPECT_TRUE(ctx.ok()) << ctx.error().message;
    if (!ctx.ok()) return {};
    const aerial::gl::Api& gl = ctx->api();
    g_api = &gl;
    Grid grid = make_grid();
    g_grid = &grid;

    GLuint texture = 0;
    const std::uint8_t white[4] = {255, 255, 255, 255};
    gl.GenTextures(1, &texture);
    gl.BindTexture(GL_TEXTURE_2D, texture);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, white);
    gl.Enable(GL_TEXTURE_2D);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LEQUAL);
    gl.ClearColor(0.2f, 0.1f, 0.3f, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    // The engine's array pointers as its draw leaves them, so that the state comparison below
    // sees only what the module changes.
    gl.VertexPointer(3, GL_FLOAT, 0, grid.xyz.data());
    gl.TexCoordPointer(2, GL_FLOAT, 0, grid.texcoords.data());

    engine_camera camera{{0.0, -1.5, 0.01}, {0.0, 0.6, 0.8}, 20000.0};
    EXPECT_EQ(example.init(ctx->loader(), ctx->loader_user()), 1)
        << example.name << ": " << aerial_last_error_message();
    const auto before = aerial::gl::capture_state(gl);
    EXPECT_EQ(example.frame(&camera, grid), 1)
        << example.name << ": " << aerial_last_error_message();
    const auto changed = aerial::gl::state_differences(before, aerial::gl::capture_state(gl));
    EXPECT_TRUE(changed.empty()) << example.name << " left changed: " << changed.front();
    example.shutdown();
    gl.Finish();
    auto image = ctx->read_rgba8();
    gl.DeleteTextures(1, &texture);
    g_api = nullptr;
    g_grid = nullptr;
    return image;
}

int max_difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    int worst = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        if (i % 4 != 3) worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
    }
    return worst;
}

/// The image is covered by the mesh (no clear colour left) and hazier at the top (far) than at
/// the bottom (near): the blue channel of L_in grows with distance while F_ex falls.
void expect_haze(const std::vector<std::uint8_t>& image, const char* name) {
    ASSERT_EQ(image.size(), std::size_t(4 * kSize * kSize)) << name;
    for (std::size_t p = 0; p < image.size() / 4; ++p) {
        const bool clear = image[4 * p] == 51 && image[4 * p + 1] == 26 && image[4 * p + 2] == 77;
        ASSERT_FALSE(clear) << name << ": pixel " << p << " was not drawn";
    }
    const std::size_t top = 4 * (kSize / 2), bottom = 4 * ((kSize - 1) * kSize + kSize / 2);
    EXPECT_NE(image[top + 0] - image[top + 2], image[bottom + 0] - image[bottom + 2])
        << name << ": the colour does not change with distance";
}

TEST(DocsExamples, EachGenerationDrawsTheHazeAndRestoresTheState) {
    const Example gl11{"gl11_two_pass", gl11_init, mesh_frame(gl11_frame), gl11_shutdown};
    const Example gl14{"gl14_secondary_color", gl14_init, mesh_frame(gl14_frame), gl14_shutdown};
    const Example arb{"arb_vertex_program", arb_init, mesh_frame(arb_frame), arb_shutdown};
    const auto a = run(gl11);
    expect_haze(a, gl11.name);
    const auto b = run(gl14);
    expect_haze(b, gl14.name);
    const auto c = run(arb);
    expect_haze(c, arb.name);
    std::printf("GL 1.1 two-pass example vs ARB example: max %d LSB\n", max_difference(a, c));
    // The same model and exposure on the CPU with two passes and on the GPU.
    EXPECT_LE(max_difference(a, c), 2);
    // The lit, hazy example is a different picture.
    EXPECT_GT(max_difference(a, b), 10);
}

TEST(DocsExamples, AMaterialSystemsProgramAndOneColourTwoPassesDrawTheSameHeightModel) {
    const Example material{"material_system", material_init, mesh_frame(material_frame),
                           material_shutdown};
    const Example one_colour{"one_colour", one_colour_init, coloured_frame, one_colour_shutdown};
    const auto a = run(material);
    expect_haze(a, material.name);
    const auto b = run(one_colour);
    expect_haze(b, one_colour.name);
    std::printf("material-system ARB program vs one-colour two passes: max %d LSB\n",
                max_difference(a, b));
    EXPECT_LE(max_difference(a, b), 2);
}

TEST(DocsExamples, TheSkyExampleColoursTheEnginesDomeByDirection) {
    ASSERT_EQ(sky_init(), 1) << aerial_last_error_message();
    const engine_camera camera{{0.0, 0.0, 0.05}, {0.0, 0.6, 0.8}, 1000.0};
    std::vector<std::vector<std::uint8_t>> colours;
    for (double radius : {1.0, 100.0}) {  // 1 km and 100 km around the eye
        std::vector<float> xyz;
        for (int e = 0; e <= 90; e += 15) {
            const double el = e * 3.14159265358979323846 / 180.0;
            xyz.insert(xyz.end(), {float(radius * std::cos(el)), 0.0f,
                                   float(camera.position[2] + radius * std::sin(el))});
        }
        std::vector<std::uint8_t> rgba(4 * xyz.size() / 3);
        engine_dome dome{xyz.data(), xyz.size() / 3, rgba.data()};
        const int drawn = g_domes_drawn;
        ASSERT_EQ(sky_frame(&camera, &dome), 1) << aerial_last_error_message();
        EXPECT_EQ(g_domes_drawn, drawn + 1);
        colours.push_back(rgba);
    }
    sky_shutdown();
    EXPECT_EQ(colours[0], colours[1]);  // the radius does not change the sky
    const std::vector<std::uint8_t>& c = colours[0];
    const std::size_t zenith = c.size() - 4;
    EXPECT_GT(c[zenith + 2], c[zenith]);  // blue overhead
    EXPECT_GT(c[2], 0);                   // not black at the horizon
}

}  // namespace
