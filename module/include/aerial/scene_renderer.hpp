// aerial/scene_renderer.hpp — draws an aerial::scene graph into the engine's GL context with
// F_ex and L_in applied per vertex, and models no more than the frame needs.
//
// How to use this:
//   1. Once per context: `auto renderer = aerial::scene::SceneRenderer::create(api, options);`
//      (options.backend cpu or arb, options.path for the cpu backend's fixed-function path).
//   2. Per frame: fill a FrameSettings (atmosphere, sun, display, the model that sets the
//      accuracy, the update policy; at night the moon as a second light) and a Camera, then
//      `auto report = renderer->render(*root, camera, settings);` — it clears nothing (the
//      engine clears), draws sky, sun and every visible node, and restores the GL state it
//      touched (enables, depth mask, texture bindings and env modes of units 0 and 1, client
//      arrays, matrices with glPushMatrix/glPopMatrix).
//   3. Read the FrameReport: what was culled, skipped, reused and shaded, with which model.
//   4. Optional: `set_sky_drawer(...)` / `set_sun_drawer(...)` replace the built-in sky dome
//      (per-vertex, hoffman-preetham, about 1000 vertices) and sun disc, e.g. by a cube map.
//
// The update policy (FrameSettings::policy, on by default), per visible node:
//   - skipped: when the largest optical depth between the eye and the node's bounding box
//     changes no 8-bit output by 0.5 step or more (bounded from the coefficients at the lowest
//     altitude of the box, the farthest corner and the largest phase values), the node is drawn
//     with F_ex = 1 and L_in = 0 and nothing is computed;
//   - cached (cpu backend): when aerial::ShadingCache says eye and sun moved too little to change
//     any output by 0.5 step since the node was shaded (aerial/cache.hpp), its colours are reused;
//   - otherwise the cheapest model meeting FrameSettings::error_target_lsb is chosen: the
//     hoffman-preetham and FrameSettings::model outputs are compared on up to 33 sample vertices
//     of the node (its box corners and evenly spaced vertices), and the 2002 model is taken when
//     they agree within the target.
// With the policy off, every visible node is shaded with FrameSettings::model every frame.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "aerial/arb_program.hpp"
#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/error.hpp"
#include "aerial/gl.hpp"
#include "aerial/scattering.hpp"
#include "aerial/scene.hpp"

namespace aerial::scene {

/// Who computes F_ex and L_in.
enum class Backend {
    cpu,  ///< aerial::shade_into into RGBA8 arrays, drawn by aerial::gl::draw_with_colours
    arb,  ///< the generated ARB vertex programs (hoffman-preetham and height) on the GPU
    /// No scattering: every node drawn with F_ex = 1 and L_in = 0 (the texture alone; terrain
    /// keeps its sun and sky lighting), along the cpu backend's fixed-function path. What a
    /// frame looks like without the library, and the base of aerial::validation's per-pixel
    /// reference and fog baseline.
    none,
};
/// "cpu", "arb", "none".
const char* backend_name(Backend backend);
Result<Backend> parse_backend(std::string_view name);

struct RendererOptions {
    Backend backend = Backend::cpu;
    gl::Path path = gl::Path::automatic;  ///< cpu and none backends: the fixed-function path
};

/// A pinhole camera, engine units.
struct Camera {
    glm::dvec3 eye{0.0, 0.0, 100.0};
    glm::dvec3 target{0.0, 1000.0, 100.0};  ///< a point looked at, != eye
    glm::dvec3 up{0.0, 0.0, 1.0};           ///< not parallel to target - eye
    double fov_y_rad = 0.9;                 ///< vertical field of view, (0, pi)
    double aspect = 16.0 / 9.0;             ///< width / height of the viewport, > 0
    double near_units = 1.0;                ///< > 0
    double far_units = 30000.0;             ///< > near_units
};

/// The frame's second light: the moon (aerial/night.hpp gives both values for a date and
/// place: moon_direction_enu, moonlight_fraction). The models run for it as for the sun, along
/// `dir` with the atmosphere's E_sun0 times `fraction`; the frame is the sum of both lights.
struct Moonlight {
    glm::dvec3 dir{0.0, 0.0, 1.0};  ///< towards the moon, world (finite, non-zero; normalised)
    /// Its illuminance outside the atmosphere as a fraction of the sun's, [0, 1e-3]
    /// (moonlight_fraction: 2.4e-6 for a full moon at its mean distance).
    double fraction = 0.0;
};

/// Which lights a frame was shaded with (FrameReport::lights).
enum class Lights {
    sun,   ///< the sun alone (no moon, or its light below half a step)
    moon,  ///< the moon alone (the sun's light below half a step: night)
    both,  ///< both: every shaded node computed for each light and summed
};
/// "sun", "moon", "both".
const char* lights_name(Lights lights);

/// Everything a frame's shading depends on besides the camera.
struct FrameSettings {
    Atmosphere atmosphere;
    glm::dvec3 sun_dir{0.0, 0.0, 1.0};  ///< unit, towards the sun
    glm::dvec3 up{0.0, 0.0, 1.0};       ///< world up, unit
    double meters_per_unit = 1.0;
    Display display;
    /// The model that sets the accuracy: nodes are shaded with it, or with hoffman-preetham
    /// where the policy measures that the two agree within error_target_lsb. The arb backend
    /// has programs for hoffman-preetham and height only.
    Model model = Model::height;
    bool policy = true;             ///< the update policy above; false: shade everything
    double error_target_lsb = 2.0;  ///< largest accepted 8-bit difference to `model`, >= 0
    /// Terrain lighting: sky irradiance added to the sun's (linear RGB; with a moon, both
    /// lights' skylight); negative (default): aerial::sky_ambient at sea level for each light.
    glm::vec3 ambient{-1.0f};
    /// The moon as a second light; none by default. A light is left out of a frame when the
    /// policy is on and its largest output, exposure x (E at the eye + 4 x its sky ambient),
    /// is below half a step (the sun at night, the moon by day): such frames cost one light.
    /// Frames with both lights shade each shaded node twice (cpu: summed before the display;
    /// arb: a second, additive pass of the program with the moon's parameters, exact with the
    /// clamp curve the programs have) and take no cached colours and no 2002-model choice.
    std::optional<Moonlight> moon;
};

/// What the renderer did with a node.
enum class Method {
    culled,            ///< outside the view frustum: not drawn
    skipped,           ///< scattering negligible (< 0.5 step): drawn with F_ex = 1, L_in = 0
    cached,            ///< colours of an earlier frame reused (cpu backend)
    hoffman_preetham,  ///< shaded with the 2002 model
    height,            ///< shaded with the height model
    reference,         ///< shaded with the reference model (cpu backend)
    unshaded,          ///< the none backend: drawn with F_ex = 1, L_in = 0
};
/// "culled", "skipped", "cached", "hoffman-preetham", "height", "reference", "unshaded".
const char* method_name(Method method);

struct NodeReport {
    std::string name;
    Method method = Method::culled;
    std::size_t vertices = 0;
};

/// What one frame did.
struct FrameReport {
    std::vector<NodeReport> nodes;    ///< every mesh and terrain node, in traversal order
    std::size_t vertices_shaded = 0;  ///< vertices whose F_ex and L_in were computed (cpu or GPU)
    std::size_t vertices_drawn = 0;   ///< vertices of drawn nodes (sky and sun excluded)
    std::size_t culled = 0;           ///< nodes
    std::size_t skipped = 0;          ///< nodes
    std::size_t cache_hits = 0;       ///< nodes
    std::size_t shaded_hoffman_preetham = 0;  ///< nodes
    std::size_t shaded_height = 0;            ///< nodes
    std::size_t shaded_reference = 0;         ///< nodes
    double milliseconds = 0.0;  ///< CPU time of render() (GL work is queued, not waited for)
    /// The module's own CPU work within it: the update policy's decisions and the shading (no
    /// GL calls, no sky).
    double shading_milliseconds = 0.0;
    gl::Path path = gl::Path::automatic;  ///< the fixed-function path of the cpu backend
    glm::vec3 ambient{0.0f};              ///< the sky irradiance used for terrain (all lights)
    Lights lights = Lights::sun;          ///< the lights the frame was shaded with
    /// The method of most shaded vertices this frame ("hoffman-preetham", "height", ...), or
    /// "cached" / "skipped" / "unshaded" / "none" when nothing was shaded.
    std::string main_method() const;
};

/// What a sky or sun drawer gets. The projection matrix is loaded and the modelview matrix
/// holds the camera's view (world to eye); depth test and depth writes are off, texturing is
/// off on units 0 and 1, the vertex array is enabled. Draw into it; leave any other state as
/// found.
struct SkyDrawContext {
    const gl::Api* api = nullptr;
    const FrameSettings* settings = nullptr;
    const Camera* camera = nullptr;
    /// Prepared for this frame's eye and the first of `lights` (the moon's on a night without
    /// the sun), with the 2002 model and with FrameSettings::model.
    const Frame<float>* hoffman_preetham = nullptr;
    const Frame<float>* model = nullptr;
    /// The frame's lights, each as the settings of a one-light frame (the moon's: sun_dir the
    /// moon's direction, E_sun0 times its fraction): sky drawers draw the sum of their skies.
    /// The sun's is `settings` itself; the sun drawer draws the sun of `settings`.
    std::vector<const FrameSettings*> lights;
    /// The renderer's fixed-function path (and combiner texture), for
    /// aerial::gl::draw_with_colours: sky colours can be drawn as L_in on a black primary.
    const gl::ApplyOptions* apply = nullptr;
};
using SkyDrawer = std::function<void(const SkyDrawContext&)>;

/// The built-in sky: the core sky of aerial/sky.hpp as a per-vertex dome around the eye, the
/// directions of make_sky_dome_mesh(kSkyDomeRings, kSkyDomeSegments) (the dome aerial-sky-table
/// measures) coloured by shade_sky_dome, then FrameSettings::display, drawn as L_in at half the
/// far distance. With FrameSettings::model `hoffman-preetham` (or `reference`, too slow for a sky
/// every frame) the method is SkyMethod::dome_hp, the 2002 talk's dome; with `height` it is
/// SkyMethod::dome_height, the height model to the top of the atmosphere. The dome_hp virtual
/// dome is fitted again only when the atmosphere changes or the eye's altitude moves by more
/// than 25 m. A skirt ring 10° below the horizon repeats the horizon's colours, so that no gap
/// shows where no terrain covers the horizon.
SkyDrawer default_sky_drawer();
/// The built-in sun: a flat disc of `angular_radius_rad` (default 3 times the real 0.27°, to be
/// seen at low resolution) coloured by the sun's transmittance T from space to the eye:
/// 1 - exp(-4 T / max(T)) per channel, white at noon, yellow to orange near the horizon.
SkyDrawer default_sun_drawer(double angular_radius_rad = 0.0141);

class SceneRenderer {
  public:
    /// Needs a current context with `api` loaded from it (the renderer keeps a pointer to it).
    /// Errors: a forced path the context lacks (cpu), GL_ARB_vertex_program missing (arb).
    static Result<SceneRenderer> create(const gl::Api& api, const RendererOptions& options = {});

    SceneRenderer(SceneRenderer&&) noexcept;
    SceneRenderer& operator=(SceneRenderer&&) noexcept;
    ~SceneRenderer();

    /// Draws one frame. Errors (nothing drawn): an invalid graph, camera or settings (the field
    /// is named), a model without a program on the arb backend.
    Result<FrameReport> render(const Node& root, const Camera& camera,
                               const FrameSettings& settings);

    void set_sky_drawer(SkyDrawer drawer);  ///< null: no sky
    void set_sun_drawer(SkyDrawer drawer);  ///< null: no sun
    /// The sun drawer in use (to chain it, as scene::night_sky_drawer does).
    const SkyDrawer& sun_drawer() const;

    /// Forgets every cached colour and GL texture (call after the context lost its objects).
    void clear_caches();

    const RendererOptions& options() const;
    /// arb backend: the program generated for `model` (hoffman-preetham or height; the height
    /// fidelity is the highest the driver's native limits take). Null otherwise.
    const ArbProgram* arb_program(Model model) const;

  private:
    struct Impl;
    explicit SceneRenderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// The first bad camera field ("camera.fov_y_rad", ...).
std::optional<Error> validate(const Camera& camera);
/// Projection (OpenGL clip space) and view (world to eye) matrices of the camera.
glm::dmat4 projection_matrix(const Camera& camera);
glm::dmat4 view_matrix(const Camera& camera);

}  // namespace aerial::scene
