// aerial-render: renders one frame of a scene file headless (OSMesa or EGL surfaceless) with one
// backend and writes it as a PNG (docs/conventions.md, Interfaces): a command line over
// aerial::validation::render_scene_file, which draws through aerial::scene::SceneRenderer. The
// scene format is aerial/scene_file.hpp's (docs/scene.md).
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "aerial/gl.hpp"
#include "aerial/headless.hpp"
#include "aerial/scene_file.hpp"
#include "aerial/validation/scene_render.hpp"
#include "support/cli.hpp"
#include "support/png.hpp"

namespace {

constexpr const char* kTool = "aerial-render";

constexpr const char* kDescription =
    "Renders one frame of a scene (JSON: camera, sun, atmosphere, model, display, procedural\n"
    "terrain and boxes; see docs/scene.md) headless and writes it as an 8-bit RGB PNG.\n"
    "colour = texture x F_ex + L_in, with L_in through the scene's exposure and tone curve.\n"
    "Backends: cpu (aerial::shade_into per vertex, drawn by the fixed-function path of --path),\n"
    "arb (the ARB vertex program), perpixel (the model per pixel at positions reconstructed from\n"
    "depth: no interpolation error), fog (GL_EXP fog, the 2002 baseline), none (texture only).\n"
    "Prints one line: backend, path, GL, size, milliseconds of the frame and GL_RENDERER.\n"
    "Exit status: 0 on success, 2 on bad input, 1 when GL or the context fails.";

}  // namespace

int main(int argc, char** argv) {
    using namespace aerial;
    CLI::App app{kDescription, kTool};
    std::string scene_path, backend_text, gl_text = "osmesa", size_text = "320x240", out_path,
                                          path_text = "automatic";
    app.add_option("--scene", scene_path, "Scene file (JSON)")->required();
    app.add_option("--backend", backend_text, "cpu, arb, perpixel, fog or none")->required();
    app.add_option("--gl", gl_text, "Headless GL: osmesa (default) or egl");
    app.add_option("--size", size_text, "Image size WxH in pixels (default 320x240)");
    auto* path_opt =
        app.add_option("--path", path_text,
                       "cpu backend: automatic (default), secondary-color, combiner or two-pass");
    app.add_option("--out", out_path, "Output PNG")->required();
    if (auto status = tools::parse_command_line(app, argc, argv, kTool)) return *status;

    validation::RenderOptions options;
    const auto backend = validation::parse_render_backend(backend_text, "--backend");
    if (!backend) return tools::fail(kTool, backend.error().message);
    options.backend = *backend;
    const auto gl = headless::parse_platform(gl_text);
    if (!gl) return tools::fail(kTool, "--gl: expected osmesa or egl, got '" + gl_text + "'");
    const auto size = tools::parse_size(size_text, "--size");
    if (!size) return tools::fail(kTool, size.error().message);
    const auto path = gl::parse_path(path_text);
    if (!path) {
        return tools::fail(kTool,
                           "--path: expected automatic, secondary-color, combiner or two-pass, "
                           "got '" +
                               path_text + "'");
    }
    options.path = *path;
    const auto scene = scene::load_scene_file(scene_path);
    if (!scene) return tools::fail(kTool, "--scene " + scene.error().message);
    if (auto e = validation::check_backend(*scene, options, path_opt->count() > 0)) {
        return tools::fail(kTool, e->message);
    }

    auto context = headless::Context::create({*gl, size->first, size->second});
    if (!context) {
        std::fprintf(stderr, "%s: --gl %s: %s\n", kTool, gl_text.c_str(),
                     context.error().message.c_str());
        return 1;
    }
    const auto image = validation::render_scene_file(*context, *scene, options);
    if (!image) {
        std::fprintf(stderr, "%s: %s\n", kTool, image.error().message.c_str());
        return 1;
    }
    if (auto error = tools::write_png(
            out_path, tools::rgb_from_rgba8(image->width, image->height, image->rgba))) {
        return tools::fail(kTool, "--out " + *error);
    }
    const char* path_name =
        options.backend == validation::RenderBackend::cpu ? gl::path_name(image->path_used) : "-";
    std::printf("backend=%s path=%s gl=%s size=%dx%d ms=%.2f program=%s renderer=\"%s\"\n",
                validation::render_backend_name(options.backend), path_name, gl_text.c_str(),
                image->width, image->height, image->milliseconds, image->program.c_str(),
                context->api().caps.renderer.c_str());
    if (std::fflush(stdout) != 0) return tools::fail(kTool, "cannot write output");
    return 0;
}
