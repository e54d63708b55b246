// aerial-irrlicht-reference: the Irrlicht example's frame (irrlicht_scene.h) rendered by the
// library's own renderer, aerial::scene::SceneRenderer (backend cpu or arb, headless OSMesa),
// in the Z-up right-handed twin of Irrlicht's Y-up left-handed world: the same terrain grid and
// triangles, camera, sun, exposure (aerial_auto_exposure of the same view) and built-in sky
// dome. A left-handed camera in the mirrored world sees the same image as a right-handed one in
// the twin, so the two PNGs compare pixel for pixel.
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "aerial/aerial.h"
#include "aerial/atmosphere.hpp"
#include "aerial/headless.hpp"
#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/sky.hpp"
#include "irrlicht_scene.h"
#include "support/png.hpp"

namespace {

constexpr const char* kTool = "aerial-irrlicht-reference";

// The Irrlicht program replicates aerial::scene's dome from these numbers.
static_assert(SCENE_DOME_RINGS == aerial::kSkyDomeRings, "irrlicht_scene.h: the dome's rings");
static_assert(SCENE_DOME_SEGMENTS == aerial::kSkyDomeSegments,
              "irrlicht_scene.h: the dome's segments");

int fail(const std::string& message, int code = 1) {
    std::fprintf(stderr, "%s: %s\n", kTool, message.c_str());
    return code;
}

std::shared_ptr<aerial::scene::MeshData> terrain_mesh() {
    auto m = std::make_shared<aerial::scene::MeshData>();
    for (int j = 0; j < SCENE_GRID_N; ++j) {
        for (int i = 0; i < SCENE_GRID_N; ++i) {
            double p[3];
            scene_grid_point(i, j, p);
            m->positions.insert(m->positions.end(), {float(p[0]), float(p[1]), float(p[2])});
            m->texcoords.insert(m->texcoords.end(), {float(p[0] / SCENE_TEXTURE_REPEAT_M),
                                                     float(p[1] / SCENE_TEXTURE_REPEAT_M)});
        }
    }
    for (int j = 0; j + 1 < SCENE_GRID_N; ++j) {
        for (int i = 0; i + 1 < SCENE_GRID_N; ++i) {
            unsigned int cell[6];
            scene_cell_indices(i, j, cell);
            m->indices.insert(m->indices.end(), cell, cell + 6);
        }
    }
    return m;
}

std::shared_ptr<aerial::scene::Texture> albedo_texture() {
    auto t = std::make_shared<aerial::scene::Texture>();
    t->width = t->height = SCENE_TEXTURE_SIDE;
    for (int k = 0; k < SCENE_TEXTURE_SIDE * SCENE_TEXTURE_SIDE; ++k) {
        t->rgb.insert(t->rgb.end(), {SCENE_ALBEDO_R, SCENE_ALBEDO_G, SCENE_ALBEDO_B});
    }
    return t;
}

aerial::scene::Camera camera(int width, int height) {
    aerial::scene::Camera c;
    c.eye = {SCENE_EYE_X, SCENE_EYE_Y, SCENE_EYE_Z};
    c.target = {SCENE_TARGET_X, SCENE_TARGET_Y, SCENE_TARGET_Z};
    c.up = {0.0, 0.0, 1.0};
    c.fov_y_rad = SCENE_FOV_Y_RAD;
    c.aspect = double(width) / double(height);
    c.near_units = SCENE_NEAR_M;
    c.far_units = SCENE_FAR_M;
    return c;
}

/// The exposure the Irrlicht program uses: aerial_auto_exposure of its own (Y-up) view.
bool exposure(float& out, std::string& error) {
    aerial_view view;
    scene_aerial_view(&view);
    aerial_context* ctx = nullptr;
    const bool ok = aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &ctx) == AERIAL_OK &&
                    aerial_context_set_view(ctx, &view) == AERIAL_OK &&
                    aerial_auto_exposure(ctx, nullptr, &out) == AERIAL_OK;
    if (!ok) error = aerial_last_error_message();
    aerial_context_destroy(ctx);
    return ok;
}

aerial::Result<std::vector<std::uint8_t>> render(aerial::headless::Context& ctx,
                                                 aerial::scene::Backend backend, float exposure) {
    aerial::scene::RendererOptions options;
    options.backend = backend;
    auto renderer = aerial::scene::SceneRenderer::create(ctx.api(), options);
    if (!renderer) return renderer.error();
    auto root = aerial::scene::make_group("world");
    root->add(aerial::scene::make_sky_dome());
    root->add(aerial::scene::make_mesh("terrain", terrain_mesh(), albedo_texture()));
    aerial::scene::FrameSettings fs;  // earth, height model
    double sun[3];
    scene_sun_dir(sun);
    fs.sun_dir = {sun[0], sun[1], sun[2]};
    fs.display.exposure = exposure;
    fs.policy = false;  // every node with the height model, as the Irrlicht program
    const auto& api = ctx.api();
    api.Viewport(0, 0, ctx.width(), ctx.height());
    api.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    auto report = renderer.value().render(*root, camera(ctx.width(), ctx.height()), fs);
    if (!report) return report.error();
    api.Finish();
    return ctx.read_rgba8();
}

}  // namespace

int main(int argc, char** argv) {
    std::string out, backend_text = "cpu";
    int width = 320, height = 240;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--out") {
            out = value;
        } else if (flag == "--backend") {
            backend_text = value;
        } else if (flag == "--width" || flag == "--height") {
            (flag == "--width" ? width : height) = std::atoi(value.c_str());
        } else {
            return fail("main(): " + flag +
                            ": expected one of --out, --backend, --width, --height, got an "
                            "unknown option",
                        2);
        }
    }
    if (out.empty() || argc % 2 == 0) {
        return fail("main(): --out: expected a PNG path, got none", 2);
    }
    auto backend = aerial::scene::parse_backend(backend_text);
    if (!backend || *backend == aerial::scene::Backend::none) {
        return fail("main(): --backend: expected one of cpu, arb, got '" + backend_text + "'", 2);
    }
    if (width < 16 || height < 16 || width > 4096 || height > 4096) {
        return fail("main(): --width, --height: expected 16..4096, got " + std::to_string(width) +
                        "x" + std::to_string(height),
                    2);
    }
    float e = 0.0f;
    std::string error;
    if (!exposure(e, error)) return fail(error);
    auto ctx =
        aerial::headless::Context::create({aerial::headless::Platform::osmesa, width, height});
    if (!ctx) return fail(ctx.error().message);
    auto pixels = render(ctx.value(), *backend, e);
    if (!pixels) return fail(pixels.error().message);
    auto image = aerial::tools::rgb_from_rgba8(width, height, pixels.value());
    if (auto w = aerial::tools::write_png(out, image)) return fail(*w);
    std::printf("%s: backend=%s %dx%d exposure=%.9g -> %s\n", kTool, backend_text.c_str(), width,
                height, double(e), out.c_str());
    return 0;
}
