// aerial/validation/scene_render.hpp — one frame of a scene file (aerial/scene_file.hpp) through
// aerial::scene::SceneRenderer, with the two images the library's own backends are measured
// against: the per-pixel reference and plain GL fog. aerial-render, the golden images, aerial-bench
// and aerial-tess render with it.
//
// How to use this:
//   1. Create an aerial::headless::Context of the image size; it is current.
//   2. `auto image = aerial::validation::render_scene_file(context, file, options);` gives the
//      RGBA8 image (top row first) and what the frame took.
//
// Backends (colour = texture × F_ex + L_in, L_in through the file's display, the 8-bit rule of
// aerial/batch.hpp), each a SceneRenderer frame of the file's graph (scene::scene_graph):
//   cpu       scene::Backend::cpu: shade_into per vertex, drawn along options.path
//   arb       scene::Backend::arb: the generated ARB vertex program
//   none      scene::Backend::none: the texture alone (F_ex = 1, L_in = 0)
//   perpixel  the `none` frame, its depth read back, each pixel's world position reconstructed
//             through the inverse view-projection and shaded with shade_into in float, composited
//             on the CPU: the image without interpolation error
//   fog       the `none` frame drawn with GL_FOG, GL_EXP: one density (the green channel's
//             extinction of the model at the eye) and one fog colour (the in-scattering of an
//             infinitely long ray, phase averaged over the sphere, through the display) — the
//             baseline the 2002 talk compared against
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>

#include "aerial/error.hpp"
#include "aerial/gl.hpp"
#include "aerial/headless.hpp"
#include "aerial/scene_file.hpp"

namespace aerial::validation {

enum class RenderBackend { cpu, arb, perpixel, fog, none };

/// "cpu", "arb", "perpixel", "fog", "none".
const char* render_backend_name(RenderBackend backend);
/// The error names `field` and lists the names.
Result<RenderBackend> parse_render_backend(std::string_view name,
                                           std::string_view field = "backend");

struct RenderOptions {
    RenderBackend backend = RenderBackend::cpu;
    gl::Path path = gl::Path::automatic;  ///< cpu, none, perpixel and fog: the fixed-function path
};

struct RenderedImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;            ///< top row first
    double milliseconds = 0.0;                 ///< the frame, glFinish (and the per-pixel shading)
    gl::Path path_used = gl::Path::automatic;  ///< the fixed-function path of the frame
    /// arb backend: the program loaded, "MODEL:INSTRUCTIONS" or, for height, "height:FIDELITY:
    /// INSTRUCTIONS" (the highest fidelity the driver's native limits run); "-" otherwise.
    std::string program = "-";
};

/// Whether the backend can render this scene at all, before any context exists: the ARB program
/// needs a model it has a program for and the clamp tone curve; --path is for the cpu backend
/// only. The error names "--backend" or "--path".
std::optional<Error> check_backend(const scene::SceneFile& file, const RenderOptions& options,
                                   bool path_given);

/// Clears to the file's background and renders one frame. Errors: the backend cannot run this
/// scene or context, or GL failed.
Result<RenderedImage> render_scene_file(const headless::Context& context,
                                        const scene::SceneFile& file, const RenderOptions& options);

/// GL fog parameters of the fog baseline: density per engine unit and the fog colour in [0, 1].
struct FogParameters {
    float density = 0.0f;
    float colour[4] = {0, 0, 0, 1};
};
FogParameters fog_parameters(const Frame<float>& frame, const Display& display);

/// The per-pixel reference after a textured frame (F_ex = 1, L_in = 0) was drawn and read back
/// into `rgba`: positions from the depth buffer, shading with `frame`'s model (shade_into,
/// float), texture × F_ex + display(L_in) with the 8-bit rule; background pixels are left as
/// they are. `projection` and `view` are the matrices the frame was drawn with.
std::optional<Error> shade_per_pixel(const headless::Context& context, const Frame<float>& frame,
                                     const Display& display, const glm::dmat4& projection,
                                     const glm::dmat4& view, std::vector<std::uint8_t>& rgba);

/// The world positions of the covered pixels of a depth buffer (bottom row first, as
/// glReadPixels gives it; depth 1 is background), through the inverse of the float matrices GL
/// was given. `positions` gets x, y, z per covered pixel, `pixels` its index in a top-row-first
/// image (y flipped).
void positions_from_depth(const std::vector<float>& depth, int width, int height,
                          const glm::dmat4& projection, const glm::dmat4& view,
                          std::vector<float>& positions, std::vector<std::size_t>& pixels);

}  // namespace aerial::validation
