// The integration guide's examples (docs/examples/*.c, included in docs/integration.md) run as
// an engine would run them, on a headless context: each draws the haze, leaves the GL state as
// it found it, and the GL 1.1 two-pass example and the ARB program agree within 2 LSB.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
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

namespace {

struct Example {
    const char* name;
    int (*init)(aerial_gl_load_function, void*);
    int (*frame)(const engine_camera*, engine_mesh*, size_t);
    void (*shutdown)();
};

/// Runs one example for one frame on a fresh context with a white texture bound (the engine's),
/// and returns the image.
std::vector<std::uint8_t> run(const Example& example) {
    auto ctx = aerial::headless::Context::create({aerial::headless::Platform::osmesa, kSize, kSize});
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
    EXPECT_EQ(example.frame(&camera, &grid.mesh, 1), 1)
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
    const Example gl11{"gl11_two_pass", gl11_init, gl11_frame, gl11_shutdown};
    const Example gl14{"gl14_secondary_color", gl14_init, gl14_frame, gl14_shutdown};
    const Example arb{"arb_vertex_program", arb_init, arb_frame, arb_shutdown};
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

}  // namespace
