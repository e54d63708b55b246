// AdaptiveMesh: colour-error-driven longest-edge bisection (Rivara's LEPP) with undo records for
// coarsening. This file holds the settings, the construction and update() as its steps; the steps
// are in adaptive_estimate.cpp (re-estimate and queue), adaptive_refine.cpp (split, with
// adaptive_relocate.cpp) and adaptive_coarsen.cpp (undo and morphing).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "adaptive_internal.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {

namespace {

using aerial::detail::invalid;
using aerial::detail::number;

}  // namespace

std::optional<Error> validate(const AdaptiveSettings& settings) {
    constexpr const char* kFunction = "mesh::validate";
    if (auto e = validate(settings.colour)) return aerial::detail::from(kFunction, *e);
    if (!(settings.split_lsb > 0.0f) || !std::isfinite(settings.split_lsb))
        return invalid(kFunction, "split_lsb", "a finite value > 0", number(settings.split_lsb));
    if (settings.colour.quantized_vertices && !(settings.split_lsb > 0.5f)) {
        return invalid(kFunction, "split_lsb",
                       "> 0.5 with colour.quantized_vertices (8-bit vertex colours are off by up "
                       "to half a step)",
                       number(settings.split_lsb));
    }
    if (!(settings.merge_ratio >= 1.0f) || !std::isfinite(settings.merge_ratio))
        return invalid(kFunction, "merge_ratio", "a finite value >= 1",
                       number(settings.merge_ratio));
    if (settings.max_vertices < 3)
        return invalid(kFunction, "max_vertices", ">= 3", number(settings.max_vertices));
    if (!(settings.time_slice_ms >= 0.0) || !std::isfinite(settings.time_slice_ms)) {
        return invalid(kFunction, "time_slice_ms", "a finite value >= 0",
                       number(settings.time_slice_ms));
    }
    if (!(settings.eye_move_fraction >= 0.0)) {
        return invalid(kFunction, "eye_move_fraction", "a value >= 0",
                       number(settings.eye_move_fraction));
    }
    if (!(settings.sun_turn_rad >= 0.0))
        return invalid(kFunction, "sun_turn_rad", "a value >= 0", number(settings.sun_turn_rad));
    if (settings.morph_updates < 0 || settings.morph_updates > 1000)
        return invalid(kFunction, "morph_updates", "0 .. 1000", number(settings.morph_updates));
    if (!(settings.compact_garbage_ratio >= 0.0f) ||
        !std::isfinite(settings.compact_garbage_ratio)) {
        return invalid(kFunction, "compact_garbage_ratio", "a finite value >= 0",
                       number(settings.compact_garbage_ratio));
    }
    if (!(settings.colour_edge_min_angle_deg >= 0.0f &&
          settings.colour_edge_min_angle_deg <= 60.0f)) {
        return invalid(kFunction, "colour_edge_min_angle_deg", "a value in [0, 60]",
                       number(settings.colour_edge_min_angle_deg));
    }
    if (!(settings.relocate_min_angle_deg >= 0.0f && settings.relocate_min_angle_deg <= 60.0f)) {
        return invalid(kFunction, "relocate_min_angle_deg", "a value in [0, 60]",
                       number(settings.relocate_min_angle_deg));
    }
    return std::nullopt;
}

Result<AdaptiveMesh> AdaptiveMesh::create(Mesh base, Surface surface, AdaptiveSettings settings) {
    constexpr const char* kFunction = "mesh::AdaptiveMesh::create";
    if (auto e = validate(settings)) return aerial::detail::from(kFunction, *e);
    if (auto e = validate_mesh(base, "base")) return aerial::detail::from(kFunction, *e);
    if (surface.kind == Surface::Kind::sphere &&
        (!(surface.radius_m > 0.0) || !std::isfinite(surface.radius_m) ||
         !finite(surface.centre))) {
        return invalid(kFunction, "surface", "a sphere of finite centre and radius > 0",
                       "centre " + aerial::detail::vector(surface.centre) + ", radius " +
                           number(surface.radius_m));
    }
    if (surface.kind == Surface::Kind::heightfield && !surface.height_m) {
        return invalid(kFunction, "surface", "a heightfield with a height function", "one without");
    }
    AdaptiveMesh m;
    m.mesh_ = std::move(base);
    m.mesh_.garbage_collection();
    m.surface_ = std::move(surface);
    m.settings_ = settings;
    m.base_vertices_ = m.mesh_.n_vertices();
    m.mesh_.add_property(m.colour_);
    m.mesh_.add_property(m.colour_eye_);
    m.mesh_.add_property(m.colour_sun_);
    m.mesh_.add_property(m.error_);
    m.mesh_.add_property(m.error_eye_);
    m.mesh_.add_property(m.error_sun_);
    m.mesh_.add_property(m.error_radius_sq_);
    m.mesh_.add_property(m.record_);
    for (auto v : m.mesh_.vertices()) m.mesh_.property(m.record_, v) = -1;
    m.live_vertices_ = m.mesh_.n_vertices();
    m.live_faces_ = m.mesh_.n_faces();
    m.invalidate();
    return m;
}

void AdaptiveMesh::invalidate() {
    index_valid_ = false;
    for (auto v : mesh_.vertices()) mesh_.property(colour_eye_, v).v = glm::vec3(kNaN);
    for (auto f : mesh_.faces()) {
        mesh_.property(error_eye_, f).v = glm::vec3(kNaN);
        mesh_.property(error_, f) = 0.0f;
    }
}

float AdaptiveMesh::face_error(OpenMesh::FaceHandle face) const {
    return mesh_.property(error_, face);
}

UpdateStats AdaptiveMesh::update(const Frame<float>& frame) {
    Pass pass;
    pass.slice_ms = settings_.time_slice_ms;
    frame_ = &frame;
    updates_ += 1.0;
    touched_.clear();
    estimated_max_ = 0.0f;

    // 1. Re-estimate what the view change made stale (through the index of estimates, or round
    // robin under a time slice) and queue every face above the target.
    const bool indexed = settings_.indexed_sweep && index_valid_;
    recording_ = indexed;
    if (indexed)
        queue_indexed(pass);
    else
        queue_sweep(pass);
    // 2. Refine: worst face first, LEPP bisection until the target, the budget or the slice.
    refine(pass);
    // 3. Coarsen: undo bisections whose parents are back below split / merge_ratio.
    if (settings_.coarsen) coarsen(pass);
    // 4. Keep the index of estimates for the next update, and compact the arrays when due.
    end_index(indexed);
    recording_ = false;
    frame_ = nullptr;
    if (garbage_over_ratio()) {
        compact();
        pass.stats.compacted = true;
    }
    pass.stats.vertices = live_vertices_;
    pass.stats.faces = live_faces_;
    pass.stats.max_error_lsb = std::max(estimated_max_, pass.unrefined_max);
    return pass.stats;
}

void AdaptiveMesh::end_index(bool indexed) {
    if (indexed) {
        std::sort(groups_.back().faces.begin(), groups_.back().faces.end());
        if (below_.size() > 4 * live_faces_ + 1024) rebuild_index();
    } else if (settings_.indexed_sweep) {
        rebuild_index();  // once every face has an estimate (after a complete first sweep)
    }
}

bool AdaptiveMesh::garbage_over_ratio() const {
    const double ratio = settings_.compact_garbage_ratio;
    auto too_much = [ratio](std::size_t stored, std::size_t live) {
        return double(stored - live) > ratio * double(live);
    };
    return ratio > 0.0 &&
           (too_much(mesh_.n_vertices(), live_vertices_) || too_much(mesh_.n_faces(), live_faces_));
}

void AdaptiveMesh::compact() {
    const CompactMaps maps = compact_keeping_order(mesh_);
    auto vertex = [&](OpenMesh::VertexHandle& v) {
        if (!v.is_valid()) return true;
        v = OpenMesh::VertexHandle(maps.vertex[std::size_t(v.idx())]);
        return v.is_valid();
    };
    auto face = [&](int f) { return maps.face[std::size_t(f)]; };

    // Undo records of live vertices, in their order (parents before children, newest last).
    std::vector<int> record(splits_.size(), -1);
    std::vector<Split> live;
    for (std::size_t i = 0; i < splits_.size(); ++i) {
        Split s = splits_[i];
        if (!s.vertex.is_valid() || maps.vertex[std::size_t(s.vertex.idx())] < 0) continue;
        for (OpenMesh::VertexHandle* h : {&s.vertex, &s.a, &s.b, &s.c, &s.d})
            if (!vertex(*h)) s.ring_lost = true;
        record[i] = int(live.size());
        live.push_back(s);
    }
    splits_ = std::move(live);
    for (std::size_t i = 0; i < splits_.size(); ++i)
        mesh_.property(record_, splits_[i].vertex) = int(i);
    std::size_t kept = 0;
    for (const int r : fading_)
        if (record[std::size_t(r)] >= 0) fading_[kept++] = record[std::size_t(r)];
    fading_.resize(kept);
    touched_.clear();

    // The round-robin sweep goes on at the first live face from where it was.
    std::size_t cursor = 0;
    for (std::size_t f = 0; f < cursor_ && f < maps.face.size(); ++f) cursor += face(int(f)) >= 0;
    cursor_ = mesh_.n_faces() ? cursor % mesh_.n_faces() : 0;

    // The index of estimates: entries of deleted faces could never be visited again.
    if (!index_valid_) return;
    for (StampGroup& g : groups_) {
        std::size_t n = 0;
        for (std::size_t i = g.head; i < g.faces.size(); ++i) {
            const int f = face(g.faces[i].second);
            if (f >= 0) g.faces[n++] = {g.faces[i].first, f};
        }
        g.faces.resize(n);
        g.head = 0;
    }
    std::vector<std::uint64_t> face_group(mesh_.n_faces(), 0);
    std::vector<char> in_above(mesh_.n_faces(), 0);
    for (std::size_t i = 0; i < maps.face.size(); ++i) {
        const int f = face(int(i));
        if (f < 0) continue;
        if (i < face_group_.size()) face_group[std::size_t(f)] = face_group_[i];
        if (i < in_above_.size()) in_above[std::size_t(f)] = in_above_[i];
    }
    face_group_ = std::move(face_group);
    in_above_ = std::move(in_above);
    kept = 0;
    for (const int f : above_)
        if (face(f) >= 0) above_[kept++] = face(f);
    above_.resize(kept);
    kept = 0;
    for (const auto& [e, f] : below_)
        if (face(f) >= 0) below_[kept++] = {e, face(f)};
    below_.resize(kept);
    std::make_heap(below_.begin(), below_.end());
}

}  // namespace aerial::mesh
