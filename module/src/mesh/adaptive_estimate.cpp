// The colour estimates of AdaptiveMesh and when they are stale: the vertices' displayed colours,
// each face's colour error stamped with the eye and sun it was computed for, the index of those
// stamps (faces grouped by update, so that only the ones that can be stale are visited), and the
// first step of an update, which re-estimates the stale faces and queues those above the target.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "adaptive_internal.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {
namespace {

// True when a value computed with (stamp_eye, stamp_sun) for something at `position` is out of
// date for the frame: the eye moved by more than `fraction` of the distance, or the sun turned.
bool stale(const glm::vec3& stamp_eye, const glm::vec3& stamp_sun, const glm::dvec3& position,
           const Frame<float>& frame, const AdaptiveSettings& settings) {
    if (std::isnan(stamp_eye.x)) return true;
    const glm::dvec3 eye = frame.view.eye;
    const double moved = glm::length(eye - glm::dvec3(stamp_eye));
    if (moved > settings.eye_move_fraction * glm::length(position - eye)) return true;
    const double c = std::clamp(glm::dot(frame.view.sun_dir, glm::dvec3(stamp_sun)), -1.0, 1.0);
    return std::acos(c) > settings.sun_turn_rad;
}

}  // namespace

glm::vec3 AdaptiveMesh::vertex_colour(OpenMesh::VertexHandle v) {
    const glm::dvec3 p = to_glm(mesh_.point(v));
    if (stale(mesh_.property(colour_eye_, v).v, mesh_.property(colour_sun_, v).v, p, *frame_,
              settings_)) {
        mesh_.property(colour_, v).v = display_colour(*frame_, settings_.colour, p);
        mesh_.property(colour_eye_, v).v = glm::vec3(frame_->view.eye);
        mesh_.property(colour_sun_, v).v = glm::vec3(frame_->view.sun_dir);
    }
    return mesh_.property(colour_, v).v;
}

int AdaptiveMesh::sample_multiple() const {
    // Relocation moves vertices to where its score (colour_error's samples: the edge midpoints
    // and the centroid on small faces) is small, which can be where the rest of the face is not:
    // estimated with those samples, a refined dome's dense error rose from 1.59 to 2.26 steps.
    // Estimating with twice the samples per edge (a grid containing colour_error's) sends those
    // faces back to refinement: 1.31 steps.
    return settings_.relocate ? 2 : 1;
}

bool AdaptiveMesh::edge_locked(OpenMesh::EdgeHandle e) const {
    return settings_.lock_boundary && mesh_.is_boundary(e);
}

float AdaptiveMesh::estimate(OpenMesh::FaceHandle f) {
    glm::dvec3 p[3];
    glm::vec3 c[3];
    bool skip[3];
    int k = 0;
    for (auto h : mesh_.fh_range(f)) {  // halfedge k runs from vertex k to vertex k + 1
        const auto v = mesh_.from_vertex_handle(h);
        p[k] = to_glm(mesh_.point(v));
        c[k] = vertex_colour(v);
        skip[k] = edge_locked(mesh_.edge_handle(h));
        ++k;
    }
    const float e = colour_error_skipping(*frame_, settings_.colour, p, c, skip, sample_multiple());
    stamp(f, e);
    return e;
}

void AdaptiveMesh::stamp(OpenMesh::FaceHandle f, float error) {
    const glm::dvec3 eye = frame_->view.eye;
    const glm::dvec3 centroid = to_glm(mesh_.calc_face_centroid(f));
    const double radius = settings_.eye_move_fraction * glm::length(centroid - eye);
    mesh_.property(error_, f) = error;
    mesh_.property(error_eye_, f).v = glm::vec3(eye);
    mesh_.property(error_sun_, f).v = glm::vec3(frame_->view.sun_dir);
    mesh_.property(error_radius_sq_, f) = float(radius * radius);
    for (auto v : mesh_.fv_range(f)) touched_.push_back(v);
    if (error <= settings_.split_lsb) estimated_max_ = std::max(estimated_max_, error);
    if (recording_) {
        const std::size_t i = std::size_t(f.idx());
        if (face_group_.size() <= i) {
            face_group_.resize(i + 1, 0);
            in_above_.resize(i + 1, 0);
        }
        face_group_[i] = groups_.back().id;
        groups_.back().faces.push_back({mesh_.property(error_radius_sq_, f), f.idx()});
        if (error > settings_.split_lsb) {
            if (!in_above_[i]) {
                in_above_[i] = 1;
                above_.push_back(f.idx());
            }
        } else {
            below_.push_back({error, f.idx()});
            std::push_heap(below_.begin(), below_.end());
        }
    }
}

void AdaptiveMesh::rebuild_index() {
    // Groups faces by the exact eye and sun of their last estimate.
    groups_.clear();
    above_.clear();
    below_.clear();
    face_group_.assign(mesh_.n_faces(), 0);
    in_above_.assign(mesh_.n_faces(), 0);
    std::map<std::array<std::uint32_t, 6>, std::size_t> by_stamp;
    for (auto f : mesh_.faces()) {
        const glm::vec3 eye = mesh_.property(error_eye_, f).v;
        const glm::vec3 sun = mesh_.property(error_sun_, f).v;
        if (std::isnan(eye.x)) {  // not estimated yet: the full sweep handles it
            index_valid_ = false;
            groups_.clear();
            return;
        }
        std::array<std::uint32_t, 6> key;
        std::memcpy(key.data(), &eye, sizeof eye);
        std::memcpy(key.data() + 3, &sun, sizeof sun);
        auto [it, added] = by_stamp.emplace(key, groups_.size());
        if (added) {
            StampGroup g;
            g.id = next_group_++;
            g.eye = eye;
            g.sun = sun;
            groups_.push_back(std::move(g));
        }
        StampGroup& g = groups_[it->second];
        g.faces.push_back({mesh_.property(error_radius_sq_, f), f.idx()});
        face_group_[std::size_t(f.idx())] = g.id;
        const float e = mesh_.property(error_, f);
        if (e > settings_.split_lsb) {
            in_above_[std::size_t(f.idx())] = 1;
            above_.push_back(f.idx());
        } else {
            below_.push_back({e, f.idx()});
        }
    }
    std::make_heap(below_.begin(), below_.end());
    for (StampGroup& g : groups_) std::sort(g.faces.begin(), g.faces.end());
    index_valid_ = true;
}

bool AdaptiveMesh::sweep_indexed(UpdateStats& stats, const std::function<bool()>& out_of_time) {
    // Exactly the faces face_stale() accepts: in a group every face has the same stamp eye and
    // sun, so `moved` and the sun's cosine are the same floats face_stale() computes.
    const glm::vec3 eye(frame_->view.eye), sun(frame_->view.sun_dir);
    const float cos_turn = float(std::cos(settings_.sun_turn_rad));
    const std::size_t n_groups = groups_.size() - 1;  // the last one is this update's
    bool finished = true;
    std::size_t visited = 0;
    for (std::size_t g = 0; g < n_groups && finished; ++g) {
        StampGroup& group = groups_[g];
        const glm::vec3 moved = eye - group.eye;
        const float d2 = glm::dot(moved, moved);
        const bool turned = glm::dot(sun, group.sun) < cos_turn;
        std::size_t i = group.head;
        for (; i < group.faces.size() && (turned || d2 > group.faces[i].first); ++i) {
            // Under a time slice: stop between entries; the group's head keeps the place.
            if ((++visited & 255) == 0 && out_of_time()) {
                finished = false;
                break;
            }
            const OpenMesh::FaceHandle f(group.faces[i].second);
            // Entries of faces stamped again since (later, or later in the same update with
            // another radius after a split changed them) are dead.
            if (face_group_[std::size_t(f.idx())] != group.id || mesh_.status(f).deleted() ||
                mesh_.property(error_radius_sq_, f) != group.faces[i].first)
                continue;
            estimate(f);
            ++stats.faces_estimated;
        }
        group.head = i;
    }
    std::size_t kept = 0;
    for (std::size_t g = 0; g < groups_.size(); ++g)
        if (g == groups_.size() - 1 || groups_[g].head < groups_[g].faces.size()) {
            if (kept != g) groups_[kept] = std::move(groups_[g]);
            ++kept;
        }
    groups_.resize(kept);
    return finished;
}

bool AdaptiveMesh::face_stale(OpenMesh::FaceHandle f) const {
    // The eye moved by more than eye_move_fraction of the face's distance at its last estimate,
    // or the sun turned by more than sun_turn_rad.
    const glm::vec3& eye = mesh_.property(error_eye_, f).v;
    if (std::isnan(eye.x)) return true;
    const glm::vec3 moved = glm::vec3(frame_->view.eye) - eye;
    if (glm::dot(moved, moved) > mesh_.property(error_radius_sq_, f)) return true;
    const float c = glm::dot(glm::vec3(frame_->view.sun_dir), mesh_.property(error_sun_, f).v);
    return c < float(std::cos(settings_.sun_turn_rad));
}

void AdaptiveMesh::queue_indexed(Pass& pass) {
    StampGroup g;
    g.id = next_group_++;
    g.eye = glm::vec3(frame_->view.eye);
    g.sun = glm::vec3(frame_->view.sun_dir);
    groups_.push_back(std::move(g));
    const bool swept = sweep_indexed(pass.stats, [&] { return pass.out_of_time(0.5); });
    if (!swept) pass.stats.complete = false;
    // The same queue and maximum queue_sweep builds. When the time slice cut the sweep, faces
    // above the target may still be stale: those are re-estimated first, so that nothing is
    // refined on an old estimate (above_ may grow while we walk it).
    std::size_t kept = 0;
    for (std::size_t n = 0; n < above_.size(); ++n) {
        const int i = above_[n];
        const OpenMesh::FaceHandle f(i);
        if (!swept && !mesh_.status(f).deleted() && face_stale(f)) {
            estimate(f);
            ++pass.stats.faces_estimated;
        }
        const float e = mesh_.property(error_, f);
        if (!mesh_.status(f).deleted() && e > settings_.split_lsb) {
            pass.queue.push({e, i});
            above_[kept++] = i;
        } else {
            in_above_[std::size_t(i)] = 0;
        }
    }
    above_.resize(kept);
    while (!below_.empty()) {
        const auto [e, i] = below_.front();
        const OpenMesh::FaceHandle f(i);
        if (!mesh_.status(f).deleted() && mesh_.property(error_, f) == e) {
            estimated_max_ = std::max(estimated_max_, e);
            break;
        }
        std::pop_heap(below_.begin(), below_.end());
        below_.pop_back();
    }
}

void AdaptiveMesh::queue_sweep(Pass& pass) {
    // Round robin from where the last time-sliced sweep stopped.
    const std::size_t n_faces = mesh_.n_faces();
    std::size_t visited = 0;
    for (; visited < n_faces; ++visited) {
        if ((visited & 255) == 0 && pass.out_of_time(0.5)) {
            pass.stats.complete = false;
            break;
        }
        const OpenMesh::FaceHandle f(int((cursor_ + visited) % n_faces));
        if (mesh_.status(f).deleted()) continue;
        if (face_stale(f)) {
            estimate(f);
            ++pass.stats.faces_estimated;
        }
        const float e = mesh_.property(error_, f);
        if (e > settings_.split_lsb)
            pass.queue.push({e, f.idx()});
        else
            estimated_max_ = std::max(estimated_max_, e);
    }
    cursor_ = n_faces ? (cursor_ + visited) % n_faces : 0;
}

}  // namespace aerial::mesh
