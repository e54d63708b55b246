// Internal: the GL-free half of a frame of the scene renderer. Per frame the inputs are checked
// and prepared once (prepare_frame_inputs); per visible node plan_node decides how it is coloured
// (skipped: scattering below half a step; cached: the colours still hold; or the cheapest model
// that meets the error target) and the colours of skipped nodes are made here. renderer.cpp
// shades and draws what this decides. Unit-testable without a GL context.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <glm/mat4x4.hpp>

#include "aerial/cache.hpp"
#include "aerial/scattering.hpp"
#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"
#include "validated_meshes.hpp"

namespace aerial::scene::detail {

/// What the renderer keeps per mesh node between frames.
struct NodeState {
    std::shared_ptr<const MeshData> mesh;  ///< the mesh the arrays below were made from
    glm::dmat4 world{0.0};
    std::vector<float> positions;  ///< world space
    std::vector<float> normals;    ///< world space, unit
    MeshBounds bounds;
    std::vector<std::uint8_t> primary, secondary;  ///< RGBA8 colours (cpu backend)
    bool has_colours = false;
    Model model = Model::height;  ///< what the colours (or the arb choice) were computed with
    bool has_choice = false;      ///< arb backend: a method chosen and its cache valid
    ShadingCache cache;
    /// The colours of a skipped node were made for these (lighting only).
    bool skip_colours = false;
    glm::dvec3 skip_sun{0.0};
    glm::vec3 skip_light{-1.0f};
    glm::dvec3 skip_moon{0.0};  ///< the second light's direction times its E (0: none)
    std::uint64_t last_frame = 0;
    /// Adaptive nodes: the arrays of the refined mesh (drawn instead of Node::mesh) and the
    /// vertex count they were made for.
    std::shared_ptr<const MeshData> adaptive_data;
    std::size_t adaptive_vertices = 0;
};

/// The sky ambient of the last estimate and what it was made for (frame_ambient).
struct SkyAmbientCache {
    bool valid = false;
    Atmosphere atmosphere;
    glm::dvec3 sun_dir{0.0};
    glm::dvec3 up{0.0};
    glm::vec3 ambient{0.0f};
};

/// The second light of a frame shaded with both (lights.hpp): the moon's one-light settings
/// and what they give.
struct SecondLight {
    const FrameSettings* settings = nullptr;  ///< sun_dir the moon's, E_sun0 times its fraction
    Frame<float> model;                       ///< settings->model
    Frame<double> bound;                      ///< the same in double, for the skip bound
    glm::vec3 ambient{0.0f};                  ///< its skylight (0 with a given ambient)
};

/// What a frame's decisions depend on, checked and prepared once per frame.
struct FrameInputs {
    const FrameSettings* settings = nullptr;
    Backend backend = Backend::cpu;
    View view;
    Frame<float> hoffman_preetham;             ///< the 2002 model (the policy's cheaper choice)
    Frame<float> model;                        ///< settings.model
    Frame<double> bound;                       ///< settings.model in double, for the skip bound
    glm::vec3 ambient{0.0f};                   ///< the frame's ambient light (frame_ambient)
    std::map<Model, PreparedShadingKey> keys;  ///< cache keys per model, prepared on first use
    /// Frames with both lights: the moon's (settings above are then the sun's). Such frames
    /// take no cached colours and no 2002-model choice.
    std::optional<SecondLight> second;

    const Frame<float>& frame_for(Model m) const {
        return m == Model::hoffman_preetham ? hoffman_preetham : model;
    }
};

/// The public function the errors of a frame are attributed to.
inline constexpr const char* kRender = "scene::SceneRenderer::render";

/// Checks the frame's scene (its meshes once: `validated`), camera and settings against the
/// backend and prepares its frames; the errors are render()'s (kRender).
Result<FrameInputs> prepare_frame_inputs(const Node& root, const Camera& camera,
                                         const FrameSettings& settings, Backend backend,
                                         ValidatedMeshes& validated);

/// settings.ambient, or (when negative) the sky's irradiance at sea level (aerial::sky_ambient,
/// whatever settings.model), estimated again only when the sun turned by more than a quarter of
/// a degree or the atmosphere or up axis changed.
glm::vec3 frame_ambient(SkyAmbientCache& cache, const FrameSettings& settings);

/// Prepares the frame's shading keys of both models the policy chooses between, so that
/// plan_node only reads `f` (nodes are planned on several threads).
void prepare_shading_keys(FrameInputs& f);

/// Adds the node counts of `part` (what one node's shading counted) to `total`.
void add_counts(FrameReport& total, const FrameReport& part);

/// How a visible node is coloured this frame.
struct NodePlan {
    Method method = Method::height;
    Model model = Model::height;  ///< the model of the colours (or of the arb program)
    bool lit = false;             ///< terrain: albedo, sun and ambient light in the primary colour
};

/// Decides for one visible node (in this order): skipped, when no output of the node can change
/// by half a step with scattering (policy on); cached, when the node's colours (cpu) or choice
/// (arb) still hold within half a step (policy on); otherwise the 2002 model where it differs
/// from settings.model by at most error_target_lsb over the node's samples (policy on), else
/// settings.model. Records a new choice in `st` (model, cache, has_choice). Nodes may be planned
/// on several threads at once once prepare_shading_keys(frame) ran.
NodePlan plan_node(FrameInputs& frame, NodeState& st, const Node& node);

/// The colours of a skipped node: lighting only (albedo, sun at the eye, ambient) for terrain,
/// white otherwise; no L_in. Made again only when the sun or the ambient changed; forgets the
/// node's scattering colours and cache.
void skipped_colours(const FrameInputs& frame, NodeState& st, bool lit, const glm::vec3& albedo);

/// max(N.L, 0) of vertex i of the node's world-space normals towards `light_dir` (1 without
/// normals).
float vertex_cosine(const NodeState& st, std::size_t i, const glm::dvec3& light_dir);

/// The Method of shading with `model`.
Method method_of(Model model);

/// World-space arrays and bounds of a node, rebuilt when its mesh or world transform changed.
void update_geometry(NodeState& st, const Node& node, const glm::dmat4& world);

/// Whether the graph holds a node of this kind.
bool has_kind(const Node& root, NodeKind kind);

}  // namespace aerial::scene::detail
