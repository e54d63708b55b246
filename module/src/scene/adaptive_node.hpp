// Internal: the renderer's step for an adaptive node (aerial/adaptive_scene.hpp) before its
// geometry is updated, and after it is shaded.
#pragma once

#include <optional>

#include "aerial/error.hpp"
#include "aerial/scattering.hpp"
#include "frame_plan.hpp"

namespace aerial::scene::detail {

/// Refines the node's AdaptiveMesh for `frame` (the frame's model at the camera) and, when its
/// mesh changed, rebuilds st.adaptive_data (mesh_data_from: texcoords from node.texture_repeat,
/// normals for terrain). Error: a world transform other than the identity.
std::optional<Error> refine_adaptive_node(NodeState& st, const Node& node, const glm::dmat4& world,
                                          const Frame<float>& frame);

/// Morphs the node's fresh RGBA8 colours (st.primary, st.secondary) with its AdaptiveMesh.
void morph_adaptive_colours(NodeState& st, const Node& node);

}  // namespace aerial::scene::detail
