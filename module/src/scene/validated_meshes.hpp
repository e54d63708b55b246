// Internal: the meshes a SceneRenderer has validated already. Checking every position and index
// of a large world each frame costs milliseconds (4.5 M vertices in the sample's 64 km world);
// a mesh is checked when the renderer first sees it, and again when its address or the address
// or size of any of its arrays changed (a new or resized mesh). Edit a mesh by replacing it: an
// edit in place of the same arrays is not checked again.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <unordered_map>

#include "aerial/scene.hpp"

namespace aerial::scene::detail {

class ValidatedMeshes {
  public:
    bool contains(const MeshData& mesh) const {
        const auto it = seen_.find(&mesh);
        return it != seen_.end() && it->second == identity(mesh);
    }
    void add(const MeshData& mesh) {
        if (seen_.size() >= kMaxMeshes) seen_.clear();  // scenes that churn meshes
        seen_[&mesh] = identity(mesh);
    }

  private:
    static constexpr std::size_t kMaxMeshes = 1 << 20;
    using Identity = std::array<const void*, 8>;
    static Identity identity(const MeshData& m) {
        return {m.positions.data(), reinterpret_cast<const void*>(m.positions.size()),
                m.normals.data(),   reinterpret_cast<const void*>(m.normals.size()),
                m.texcoords.data(), reinterpret_cast<const void*>(m.texcoords.size()),
                m.indices.data(),   reinterpret_cast<const void*>(m.indices.size())};
    }
    std::unordered_map<const MeshData*, Identity> seen_;
};

/// validate(root), skipping the meshes in `memo` and adding those it checked.
std::optional<Error> validate(const Node& root, ValidatedMeshes& memo);

}  // namespace aerial::scene::detail
