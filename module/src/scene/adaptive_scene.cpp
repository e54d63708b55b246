// Adaptive meshes in the scene graph (aerial/adaptive_scene.hpp): OpenMesh meshes as MeshData,
// the adaptive nodes, and the renderer's refinement and colour morph of them.
#include "aerial/adaptive_scene.hpp"

#include <cmath>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "adaptive_node.hpp"

namespace aerial::scene {

MeshData mesh_data_from(const mesh::Mesh& m, double texture_repeat, bool normals) {
    MeshData out;
    const std::size_t n = m.n_vertices();
    out.positions.reserve(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& p = m.point(mesh::Mesh::VertexHandle(int(i)));
        out.positions.insert(out.positions.end(), {float(p[0]), float(p[1]), float(p[2])});
        if (texture_repeat > 0.0) {
            out.texcoords.insert(out.texcoords.end(),
                                 {float(p[0] / texture_repeat), float(p[1] / texture_repeat)});
        }
    }
    std::vector<glm::dvec3> sums(normals ? n : 0, glm::dvec3(0.0));
    for (const auto f : m.faces()) {
        if (m.status(f).deleted()) continue;
        std::uint32_t corner[3];
        int k = 0;
        for (const auto v : m.fv_range(f)) corner[k++] = std::uint32_t(v.idx());
        out.indices.insert(out.indices.end(), {corner[0], corner[1], corner[2]});
        if (!normals) continue;
        const auto at = [&](std::uint32_t i) {
            const auto& p = m.point(mesh::Mesh::VertexHandle(int(i)));
            return glm::dvec3(p[0], p[1], p[2]);
        };
        // Twice the area times the unit normal: the area-weighted sum.
        const glm::dvec3 a = at(corner[0]);
        const glm::dvec3 face = glm::cross(at(corner[1]) - a, at(corner[2]) - a);
        for (std::uint32_t i : corner) sums[i] += face;
    }
    for (const glm::dvec3& s : sums) {
        const double length = glm::length(s);
        const glm::dvec3 u = length > 0.0 ? s / length : glm::dvec3(0.0, 0.0, 1.0);
        out.normals.insert(out.normals.end(), {float(u.x), float(u.y), float(u.z)});
    }
    return out;
}

namespace {

std::unique_ptr<Node> adaptive_node(NodeKind kind, std::string name,
                                    std::shared_ptr<mesh::AdaptiveMesh> adaptive,
                                    std::shared_ptr<const Texture> texture, double texture_repeat,
                                    glm::vec3 albedo) {
    auto node = make_group(std::move(name));
    node->kind = kind;
    node->adaptive = std::move(adaptive);
    node->texture = std::move(texture);
    node->texture_repeat = texture_repeat;
    node->albedo = albedo;
    return node;
}

}  // namespace

std::unique_ptr<Node> make_adaptive_mesh(std::string name,
                                         std::shared_ptr<mesh::AdaptiveMesh> adaptive,
                                         std::shared_ptr<const Texture> texture,
                                         double texture_repeat) {
    return adaptive_node(NodeKind::mesh, std::move(name), std::move(adaptive), std::move(texture),
                         texture_repeat, glm::vec3(1.0f));
}

std::unique_ptr<Node> make_adaptive_terrain(std::string name,
                                            std::shared_ptr<mesh::AdaptiveMesh> adaptive,
                                            std::shared_ptr<const Texture> texture,
                                            double texture_repeat, glm::vec3 albedo) {
    return adaptive_node(NodeKind::terrain, std::move(name), std::move(adaptive),
                         std::move(texture), texture_repeat, albedo);
}

namespace detail {

std::optional<Error> refine_adaptive_node(NodeState& st, const Node& node, const glm::dmat4& world,
                                          const Frame<float>& frame) {
    if (world != glm::dmat4(1.0)) {
        return aerial::detail::invalid(
            kRender, node.name,
            "the identity as the world transform (an adaptive node is refined in world "
            "coordinates)",
            "another transform");
    }
    const mesh::UpdateStats stats = node.adaptive->update(frame);
    const bool changed = stats.splits > 0 || stats.merges > 0 || stats.relocated > 0 ||
                         stats.compacted ||
                         st.adaptive_vertices != node.adaptive->mesh().n_vertices();
    if (!st.adaptive_data || changed) {
        st.adaptive_data = std::make_shared<MeshData>(mesh_data_from(
            node.adaptive->mesh(), node.texture_repeat, node.kind == NodeKind::terrain));
        st.adaptive_vertices = node.adaptive->mesh().n_vertices();
    }
    return std::nullopt;
}

void morph_adaptive_colours(NodeState& st, const Node& node) {
    node.adaptive->morph_into(st.primary.data(), 3, 4);
    node.adaptive->morph_into(st.secondary.data(), 3, 4);
}

}  // namespace detail
}  // namespace aerial::scene
