// aerial/osg.hpp — OpenSceneGraph adapter (target `aerial::osg`, built when OpenSceneGraph is
// found): an update callback that gives every osg::Geometry below a node F_ex and L_in per
// vertex, each frame, from a camera and the sun.
//
// How to use this:
//   1. `aerial::osg_adapter::Settings s;` — atmosphere, sun_dir, model, display; `backend` cpu
//      (colour arrays filled by aerial::shade_into) or arb (the module's ARB vertex program).
//   2. `auto cb = aerial::osg_adapter::ScatteringCallback::create(s, camera);` checks the
//      settings (the error names the field) and, for arb, generates the program.
//   3. `node->setUpdateCallback(cb.value().get());` — each update traversal it reads the eye from
//      the camera's view matrix and, below `node`:
//        cpu: fills each Geometry's colour array (F_ex, RGBA8, it modulates the texture) and
//             secondary-colour array (L_in after the display, RGB8, it is added), marks them
//             dirty and sets the Geometry's data variance to DYNAMIC;
//        arb: puts an osg::VertexProgram with the generated text on the node's StateSet and sets
//             its program.local parameters.
//      The node's StateSet gets GL_COLOR_SUM on, GL_LIGHTING off (the colours carry the light)
//      and a MODULATE texture environment on units 0 .. texture_units-1. Everything goes through
//      OSG state: the adapter makes no GL call, and OSG restores these modes after the node.
//   4. `cb->last_error()` says why the last update did nothing (also logged with OSG_WARN once).
//
// Frames and units: OSG's world is Z-up, the module's default `up` too, so Settings::up = +Z
// fits an ordinary OSG scene; a Y-up scene sets up = (0, 1, 0). Positions are OSG world units;
// `meters_per_unit` converts them (a scene in kilometres sets 1000). Both backends take each
// Geometry's local-to-world matrix (its first parental path) as a model matrix, with no copy of
// its vertices: the cpu backend through Positions::model_matrix, the arb backend through the
// program's model-matrix parameters (ArbProgramOptions::model_matrix; a Geometry below a
// transform gets its own osg::VertexProgram with the same text and its matrix). The camera's view
// matrix is read in the update traversal: a camera manipulator updates it after the scene's update
// callbacks, so the colours lag it by one frame; set the view matrix before Viewer::frame() (or
// call update_now()) to avoid the lag.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <osg/Camera>
#include <osg/Geometry>
#include <osg/Matrixd>
#include <osg/Node>
#include <osg/NodeCallback>
#include <osg/Referenced>
#include <osg/VertexProgram>
#include <osg/observer_ptr>
#include <osg/ref_ptr>

#include "aerial/arb_program.hpp"
#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"

namespace aerial::osg_adapter {

/// Who computes F_ex and L_in.
enum class Backend {
    cpu,  ///< aerial::shade_into into the Geometry's colour and secondary-colour arrays
    arb,  ///< the generated ARB vertex program (hoffman-preetham or height) on the GPU
};
/// "cpu" or "arb".
const char* backend_name(Backend backend);
/// The inverse of backend_name; the error names the field "backend".
Result<Backend> parse_backend(std::string_view name);

struct Settings {
    Backend backend = Backend::cpu;
    Atmosphere atmosphere;              ///< default: the `earth` preset
    glm::dvec3 sun_dir{0.0, 0.0, 1.0};  ///< unit, towards the sun, world frame
    glm::dvec3 up{0.0, 0.0, 1.0};       ///< unit world up; +Z is OSG's convention
    double meters_per_unit = 1.0;       ///< OSG world units to metres, > 0
    /// hoffman-preetham or height on both backends; reference on cpu only.
    Model model = Model::hoffman_preetham;
    /// The arb backend takes the clamp curve only (GL clamps the secondary colour).
    Display display;
    Kernel kernel = Kernel::simd;  ///< cpu backend
    unsigned threads = 1;          ///< cpu backend: shade_into worker threads (0: all)
    /// Texture units whose environment is set to MODULATE (cpu) or whose coordinates the program
    /// passes through (arb), 0 .. kArbMaxTexcoordUnits.
    int texture_units = 1;
    /// arb backend: the driver's limits choose the height program's fidelity (pass
    /// aerial::gl::native_arb_limits for the most accurate program the driver takes; the
    /// defaults are the spec minimums).
    ArbLimits arb_limits;
};

/// The first bad field of the settings ("atmosphere.mie_g", "sun_dir", "model", ...).
std::optional<Error> validate(const Settings& settings);

/// What the last update did.
struct UpdateReport {
    std::size_t geometries = 0;        ///< Geometry drawables found below the node
    std::size_t vertices = 0;          ///< vertices shaded (cpu) or below the program (arb)
    std::size_t invalid_vertices = 0;  ///< cpu: not positions (BatchStats::invalid_vertices)
};

class ScatteringCallback : public ::osg::NodeCallback {
  public:
    /// Validates the settings; for arb, generates the program (errors name the field).
    static Result<::osg::ref_ptr<ScatteringCallback>> create(const Settings& settings,
                                                             ::osg::Camera* camera);

    /// Replaces the settings (validated as create() does); the next update uses them.
    std::optional<Error> set_settings(const Settings& settings);
    const Settings& settings() const { return settings_; }
    void set_camera(::osg::Camera* camera) { camera_ = camera; }

    /// The update: shades `node`'s subtree for the camera's current eye, then traverses.
    void operator()(::osg::Node* node, ::osg::NodeVisitor* nv) override;

    /// The same work outside a traversal, with an explicit eye (world units); for tools and for
    /// applications that move the camera after the update traversal.
    std::optional<Error> update_now(::osg::Node& node, const glm::dvec3& eye);

    /// The ARB program text in use (empty on the cpu backend).
    const std::string& program_text() const { return program_.text; }
    const UpdateReport& last_report() const { return report_; }
    /// Why the last update did nothing, or nullopt when it succeeded.
    const std::optional<Error>& last_error() const { return error_; }

  protected:
    ~ScatteringCallback() override = default;

  private:
    ScatteringCallback() = default;
    std::optional<Error> update(::osg::Node& node, const ::osg::Matrixd& parent_to_world,
                                const glm::dvec3& eye);
    void prepare_state(::osg::Node& node);
    /// A Geometry below a transform on the arb backend, its program and its model matrix rows.
    struct Transformed {
        ::osg::observer_ptr<::osg::Geometry> geometry;
        ::osg::ref_ptr<::osg::VertexProgram> program;
        std::array<std::array<float, 4>, 3> rows{};
        bool seen = false;  ///< found in this update
    };
    /// arb: the entry of a Geometry below a transform, its own program (same text, its own
    /// program.local model matrix) put on its StateSet when first seen.
    Transformed& transformed(::osg::Geometry& geometry);
    /// Takes the per-Geometry programs off their StateSets (new settings, or the cpu backend).
    void remove_transformed_programs();

    Settings settings_;
    ArbProgram program_;
    ::osg::ref_ptr<::osg::VertexProgram> vertex_program_;     ///< arb: holds program_.text
    ::osg::ref_ptr<::osg::VertexProgram> installed_program_;  ///< the one put on the StateSet
    ::osg::observer_ptr<::osg::Camera> camera_;
    UpdateReport report_;
    std::optional<Error> error_;
    bool warned_ = false;
    std::vector<std::uint8_t> secondary_;  ///< scratch: RGBA8 L_in before the RGB8 copy
    std::vector<Transformed> transformed_;
};

}  // namespace aerial::osg_adapter
