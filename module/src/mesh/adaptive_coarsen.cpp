// Coarsening of AdaptiveMesh and its morphing. A split is undone by collapsing its vertex into
// one end of the split edge, which restores the two parent faces exactly, and only when the
// vertex's one-ring is still the one it was born with and the parents are back below
// split_lsb / merge_ratio. With settings.morph_updates a new vertex blends in over that many
// updates and a vertex fades out before its split is undone (morph_into).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <queue>
#include <type_traits>
#include <vector>

#include "adaptive_internal.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {

bool AdaptiveMesh::undo_allowed(std::size_t index, UpdateStats& stats, float& error_c,
                                float& error_d) {
    const Split s = splits_[index];
    if (!s.vertex.is_valid() || mesh_.status(s.vertex).deleted() || s.ring_lost) return false;
    const float merge_lsb = settings_.split_lsb / settings_.merge_ratio;
    // The ring must be the one the vertex was born with.
    std::size_t expected = 2 + (s.c.is_valid() ? 1 : 0) + (s.d.is_valid() ? 1 : 0);
    std::size_t count = 0;
    for (auto w : mesh_.vv_range(s.vertex)) {
        if (w != s.a && w != s.b && w != s.c && w != s.d) return false;
        ++count;
    }
    if (count != expected) return false;
    // Cheap test first: the children's last estimates.
    for (auto f : mesh_.vf_range(s.vertex))
        if (mesh_.property(error_, f) > merge_lsb || std::isnan(mesh_.property(error_eye_, f).v.x))
            return false;
    // The parents' errors now.
    auto parent_error = [&](OpenMesh::VertexHandle apex) {
        const OpenMesh::VertexHandle vs[3] = {s.a, s.b, apex};
        glm::dvec3 p[3];
        glm::vec3 c[3];
        bool skip[3];
        for (int k = 0; k < 3; ++k) {
            p[k] = to_glm(mesh_.point(vs[k]));
            c[k] = vertex_colour(vs[k]);
        }
        skip[0] = false;  // a-b was split, so it is not locked
        for (int k = 1; k < 3; ++k) {
            const auto h = mesh_.find_halfedge(vs[k], vs[(k + 1) % 3]);
            skip[k] = h.is_valid() && edge_locked(mesh_.edge_handle(h));
        }
        ++stats.faces_estimated;
        return colour_error_skipping(*frame_, settings_.colour, p, c, skip, sample_multiple());
    };
    error_c = s.c.is_valid() ? parent_error(s.c) : 0.0f;
    error_d = s.d.is_valid() ? parent_error(s.d) : 0.0f;
    if (error_c > merge_lsb || error_d > merge_lsb) return false;
    const auto h = mesh_.find_halfedge(s.vertex, s.a);
    return h.is_valid() && mesh_.is_collapse_ok(h);
}

float AdaptiveMesh::record_weight(const Split& s) const {
    const double n = settings_.morph_updates;
    if (n <= 0.0) return 1.0f;
    const double w = s.fade_start >= 0.0 ? s.fade_weight - (updates_ - s.fade_start) / n
                                         : (updates_ - s.born) / n;
    return float(std::clamp(w, 0.0, 1.0));
}

bool AdaptiveMesh::try_undo(std::size_t index, UpdateStats& stats) {
    Split& record = splits_[index];
    if (!record.vertex.is_valid() || mesh_.status(record.vertex).deleted()) return false;
    float error_c = 0.0f, error_d = 0.0f;
    const bool allowed = undo_allowed(index, stats, error_c, error_d);
    if (settings_.morph_updates > 0) {
        const float w = record_weight(record);
        if (!allowed) {
            // Needed again: blend back in from where the fade-out got to.
            if (record.fade_start >= 0.0) {
                record.fade_start = -1.0;
                record.born = updates_ - double(w) * settings_.morph_updates;
            }
            return false;
        }
        if (record.fade_start < 0.0) {
            record.fade_start = updates_;
            record.fade_weight = w;
            fading_.push_back(int(index));
        }
        if (record_weight(record) > 0.0f) return false;
    } else if (!allowed) {
        return false;
    }
    const Split s = record;
    mesh_.collapse(mesh_.find_halfedge(s.vertex, s.a));
    const auto ab = mesh_.find_halfedge(s.a, s.b);
    for (auto hh : {ab, mesh_.opposite_halfedge_handle(ab)}) {
        const auto f = mesh_.face_handle(hh);
        if (!f.is_valid()) continue;
        const auto apex = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(hh));
        stamp(f, apex == s.c ? error_c : error_d);
    }
    splits_[index].vertex = OpenMesh::VertexHandle();
    ++stats.merges;
    --live_vertices_;
    live_faces_ -= s.c.is_valid() && s.d.is_valid() ? 2 : 1;
    return true;
}

void AdaptiveMesh::coarsen(Pass& pass) {
    // Undoes bisections whose parents are back below split / merge_ratio. Only vertices next to
    // a face estimated in this update can have changed their answer; newest first, and an undo
    // makes the parents' vertices candidates again (cascades).
    continue_fades(pass.stats);
    std::priority_queue<int> candidates;
    std::size_t consumed = 0;
    auto collect = [&] {
        for (; consumed < touched_.size(); ++consumed) {
            const auto v = touched_[consumed];
            if (!mesh_.status(v).deleted() && mesh_.property(record_, v) >= 0)
                candidates.push(mesh_.property(record_, v));
        }
    };
    collect();
    int last = -1;
    while (!candidates.empty()) {
        if ((++pass.iterations & 63) == 0 && pass.out_of_time(1.0)) {
            pass.stats.complete = false;
            break;
        }
        const int r = candidates.top();
        candidates.pop();
        if (r == last) continue;  // duplicates come out together
        last = r;
        if (try_undo(std::size_t(r), pass.stats)) {
            collect();
            last = -1;
        }
    }
}

void AdaptiveMesh::continue_fades(UpdateStats& stats) {
    // Fading vertices go on fading (or come back) whether or not their faces were re-estimated;
    // the last step of a fade removes the vertex (and, like any undo, makes the parents'
    // vertices candidates for coarsen()).
    std::vector<int> fading;
    fading.swap(fading_);
    std::sort(fading.begin(), fading.end(), std::greater<int>());
    fading.erase(std::unique(fading.begin(), fading.end()), fading.end());
    for (const int r : fading) {
        const Split& s = splits_[std::size_t(r)];
        if (!s.vertex.is_valid() || mesh_.status(s.vertex).deleted() || s.fade_start < 0.0)
            continue;
        if (!try_undo(std::size_t(r), stats) && splits_[std::size_t(r)].fade_start >= 0.0)
            fading_.push_back(r);
    }
}

float AdaptiveMesh::morph_weight(OpenMesh::VertexHandle v) const {
    const int r = mesh_.property(record_, v);
    return r < 0 ? 1.0f : record_weight(splits_[std::size_t(r)]);
}

std::pair<OpenMesh::VertexHandle, OpenMesh::VertexHandle> AdaptiveMesh::parents(
    OpenMesh::VertexHandle v) const {
    const int r = mesh_.property(record_, v);
    if (r < 0) return {OpenMesh::VertexHandle(), OpenMesh::VertexHandle()};
    return {splits_[std::size_t(r)].a, splits_[std::size_t(r)].b};
}

template <typename T>
void AdaptiveMesh::morph_values(T* values, std::size_t components, std::size_t stride) const {
    if (settings_.morph_updates <= 0) return;
    // Geomorphing of the detail: a vertex shows its parents' shown mean plus w times its own
    // detail (its value minus its parents' mean). Vertices born together then move on straight
    // lines from the coarse interpolation to their values, 1/morph_updates of the way per update,
    // however deep the chain of bisections. Records are in the order of the splits, so parents
    // come before their children.
    std::vector<float> exact;
    for (const Split& s : splits_) {
        if (!s.vertex.is_valid() || mesh_.status(s.vertex).deleted()) continue;
        const float w = record_weight(s);
        if (w >= 1.0f) continue;
        if (exact.empty()) {
            exact.resize(mesh_.n_vertices() * components);
            for (std::size_t v = 0; v < mesh_.n_vertices(); ++v)
                for (std::size_t k = 0; k < components; ++k)
                    exact[v * components + k] = float(values[v * stride + k]);
        }
        const std::size_t i = std::size_t(s.vertex.idx()), a = std::size_t(s.a.idx()),
                          b = std::size_t(s.b.idx());
        T* out = values + i * stride;
        for (std::size_t k = 0; k < components; ++k) {
            const float shown_parents =
                0.5f * (float(values[a * stride + k]) + float(values[b * stride + k]));
            const float detail = exact[i * components + k] -
                                 0.5f * (exact[a * components + k] + exact[b * components + k]);
            const float v = shown_parents + w * detail;
            if constexpr (std::is_same_v<T, std::uint8_t>)
                out[k] = T(std::clamp(std::lround(v), 0L, 255L));
            else
                out[k] = T(v);
        }
    }
}

void AdaptiveMesh::morph_into(float* values, std::size_t components, std::size_t stride) const {
    morph_values(values, components, stride);
}

void AdaptiveMesh::morph_into(std::uint8_t* values, std::size_t components,
                              std::size_t stride) const {
    morph_values(values, components, stride);
}

}  // namespace aerial::mesh
