// Renders a scene (render/scene.hpp) with one of aerial-render's backends into the current
// headless context.
//
// How to use this:
//   1. Create an aerial::headless::Context of the image size; it is current.
//   2. `auto image = aerial::render::render_scene(context, scene, options);` gives the RGBA8
//      image (top row first) and what the frame took.
//
// Backends (colour = texture × F_ex + L_in, L_in through scene.display, 8-bit rule of
// aerial/batch.hpp):
//   cpu       aerial::shade_into per vertex → RGBA8 colours → aerial::gl::draw_with_colours
//             along options.path (automatic, secondary-color, combiner, two-pass)
//   arb       aerial::generate_arb_program + aerial::gl::ArbVertexProgram (GPU per vertex)
//   perpixel  the scene drawn textured only, its depth read back, each pixel's world position
//             reconstructed through the inverse view-projection and shaded with shade_into in
//             float, composited on the CPU: the image without interpolation error
//   fog       plain GL_FOG, GL_EXP: one density (the green channel's extinction of the model at
//             the eye) and one fog colour (the in-scattering of an infinitely long ray with the
//             phase functions averaged over the sphere, through scene.display) — the baseline
//             Hoffman & Preetham compared against
//   none      the texture alone
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>

#include "aerial/error.hpp"
#include "aerial/gl.hpp"
#include "aerial/headless.hpp"
#include "render/scene.hpp"

namespace aerial::render {

enum class Backend { cpu, arb, perpixel, fog, none };

/// "cpu", "arb", "perpixel", "fog", "none".
const char* backend_name(Backend backend);
std::optional<Backend> parse_backend(std::string_view name);

struct RenderOptions {
    Backend backend = Backend::cpu;
    gl::Path path = gl::Path::automatic;  ///< cpu backend only
};

struct RenderedImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  ///< top row first
    double milliseconds = 0.0;       ///< shading, drawing, glFinish (and read-back for perpixel)
    gl::Path path_used = gl::Path::automatic;  ///< cpu backend: the path draw_with_colours took
    /// arb backend: the program loaded, "MODEL:INSTRUCTIONS" or, for height, "height:FIDELITY:
    /// INSTRUCTIONS" (the highest fidelity the driver's native limits run); "-" otherwise.
    std::string program = "-";
};

/// Whether the backend can render this scene at all, before any context exists: the ARB program
/// needs a model it has a program for (hoffman-preetham) and the clamp tone curve; --path is for
/// the cpu backend only. The error names "--backend" or "--path".
std::optional<Error> check_backend(const Scene& scene, const RenderOptions& options,
                                   bool path_given);

/// Renders one frame. Errors: the backend cannot run this scene or context (the ARB program
/// needs hoffman-preetham and the clamp tone; a forced path the context lacks), or GL failed.
Result<RenderedImage> render_scene(const headless::Context& context, const Scene& scene,
                                   const RenderOptions& options);

/// GL fog parameters of the fog backend: density per engine unit and the fog colour in [0, 1].
struct FogParameters {
    float density = 0.0f;
    float colour[4] = {0, 0, 0, 1};
};
FogParameters fog_parameters(const Frame<float>& frame, const Display& display);

// ---- Pieces of render_scene, for tools that draw their own meshes with the same rules -------

/// The scene's texture (build_texture) in a GL texture object bound on the active unit, mipmapped,
/// GL_MODULATE, GL_TEXTURE_2D enabled; the destructor disables, unbinds and deletes it.
class BoundTexture {
  public:
    BoundTexture(const gl::Api& api, const Texture& texture);
    BoundTexture(const BoundTexture&) = delete;
    BoundTexture& operator=(const BoundTexture&) = delete;
    ~BoundTexture();

  private:
    const gl::Api& api_;
    unsigned id_ = 0;
};

/// Projection and view of the scene's camera at this aspect ratio.
struct Matrices {
    glm::dmat4 projection;
    glm::dmat4 view;
};
Matrices camera_matrices(const Camera& camera, int width, int height);

/// Draws `mesh` (positions and texture coordinates from client arrays, texture unit 0) with
/// whatever state is set; leaves those two client arrays disabled.
void draw_arrays(const gl::Api& api, const Mesh& mesh);

/// Loads `m` (as float) into the matrix stack `mode` (GL_PROJECTION, GL_MODELVIEW).
void load_matrix(const gl::Api& api, unsigned mode, const glm::dmat4& m);

/// The perpixel backend after the textured frame is drawn and read back into `rgba`: positions
/// from the depth buffer, shading with `frame`'s model (shade_into, float), texture × F_ex +
/// display(L_in) with the 8-bit rule; background pixels are left as they are.
std::optional<Error> shade_per_pixel(const headless::Context& context, const Frame<float>& frame,
                                     const Display& display, const Matrices& matrices,
                                     std::vector<std::uint8_t>& rgba);

/// The world positions of the covered pixels of a depth buffer (bottom row first, as
/// glReadPixels gives it; depth 1 is background), through the inverse of the float matrices GL
/// was given. `positions` gets x, y, z per covered pixel, `pixels` its index in a top-row-first
/// image (y flipped). The perpixel backend and aerial-tess's GL grading use it.
void positions_from_depth(const std::vector<float>& depth, int width, int height,
                          const glm::dmat4& projection, const glm::dmat4& view,
                          std::vector<float>& positions, std::vector<std::size_t>& pixels);

}  // namespace aerial::render
