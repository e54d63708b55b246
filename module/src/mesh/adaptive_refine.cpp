// Refinement of AdaptiveMesh: Rivara's longest-edge propagation path (LEPP) from the worst face,
// each step a bisection of both faces of an edge (TriMesh::split(EdgeHandle, VertexHandle)), so
// the mesh stays conforming; the new vertex is the edge midpoint projected onto the surface
// (then moved within its one-ring with settings.relocate, adaptive_relocate.cpp).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "adaptive_internal.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {

double min_angle(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r) {
    auto angle = [](const glm::dvec3& apex, const glm::dvec3& u, const glm::dvec3& v) {
        const glm::dvec3 a = u - apex, b = v - apex;
        return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    };
    return std::min({angle(p, q, r), angle(q, r, p), angle(r, p, q)});
}

OpenMesh::EdgeHandle AdaptiveMesh::longest_edge(OpenMesh::FaceHandle f) const {
    // A total order (length, then handle) so that LEPP paths strictly ascend and end.
    OpenMesh::EdgeHandle best;
    double best_length = -1.0;
    for (auto h : mesh_.fh_range(f)) {
        const auto e = mesh_.edge_handle(h);
        const double length = mesh_.calc_edge_sqr_length(e);
        if (length > best_length || (length == best_length && e.idx() < best.idx())) {
            best = e;
            best_length = length;
        }
    }
    return best;
}

OpenMesh::EdgeHandle AdaptiveMesh::colour_edge(OpenMesh::FaceHandle f) {
    // The edge with the largest midpoint error whose bisection keeps both faces' halves at
    // least colour_edge_min_angle_deg in every angle; ties and no candidate: the longest edge.
    const double bound = double(settings_.colour_edge_min_angle_deg) * kPi / 180.0;
    const OpenMesh::EdgeHandle longest = longest_edge(f);
    OpenMesh::EdgeHandle best;
    float best_error = -1.0f;
    for (auto h : mesh_.fh_range(f)) {
        const auto e = mesh_.edge_handle(h);
        if (edge_locked(e) || !(mesh_.calc_edge_sqr_length(e) > 0.0)) continue;
        const auto va = mesh_.from_vertex_handle(h), vb = mesh_.to_vertex_handle(h);
        const glm::dvec3 a = to_glm(mesh_.point(va)), b = to_glm(mesh_.point(vb));
        const glm::dvec3 m = surface_.project(0.5 * (a + b));
        bool shaped = true;
        for (auto side : {h, mesh_.opposite_halfedge_handle(h)}) {
            if (mesh_.is_boundary(side)) continue;
            const glm::dvec3 apex =
                to_glm(mesh_.point(mesh_.to_vertex_handle(mesh_.next_halfedge_handle(side))));
            if (min_angle(a, m, apex) < bound || min_angle(m, b, apex) < bound) shaped = false;
        }
        if (!shaped) continue;
        const float error = edge_midpoint_error(*frame_, settings_.colour, a, b, vertex_colour(va),
                                                vertex_colour(vb));
        if (error > best_error || (error == best_error && e == longest)) {
            best = e;
            best_error = error;
        }
    }
    return best.is_valid() ? best : longest;
}

bool AdaptiveMesh::splittable(OpenMesh::FaceHandle f) const {
    // A face whose longest edge is locked stays: bisecting its other edges would only make
    // slivers along the locked edge without reducing the error there.
    const auto e = longest_edge(f);
    return e.is_valid() && !edge_locked(e) && mesh_.calc_edge_sqr_length(e) > 0.0;
}

void AdaptiveMesh::bisect(OpenMesh::EdgeHandle e, UpdateStats& stats) {
    const auto h0 = mesh_.halfedge_handle(e, 0);
    const auto h1 = mesh_.halfedge_handle(e, 1);
    Split record;
    record.a = mesh_.from_vertex_handle(h0);
    record.b = mesh_.to_vertex_handle(h0);
    if (!mesh_.is_boundary(h0)) record.c = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h0));
    if (!mesh_.is_boundary(h1)) record.d = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h1));
    const glm::dvec3 mid = 0.5 * (to_glm(mesh_.point(record.a)) + to_glm(mesh_.point(record.b)));
    record.vertex = mesh_.add_vertex(to_point(surface_.project(mid)));
    mesh_.property(colour_eye_, record.vertex).v = glm::vec3(kNaN);
    mesh_.property(record_, record.vertex) = int(splits_.size());
    record.born = updates_;
    splits_.push_back(record);
    mesh_.split(e, record.vertex);
    ++stats.splits;
    ++live_vertices_;
    live_faces_ += record.c.is_valid() && record.d.is_valid() ? 2 : 1;
    if (settings_.relocate) relocate(record.vertex, stats);
    for (auto f : mesh_.vf_range(record.vertex)) {
        estimate(f);
        ++stats.faces_estimated;
    }
}

void AdaptiveMesh::refine(Pass& pass) {
    // Worst face first, until the target, the vertex budget or 90 % of the time slice.
    auto& queue = pass.queue;
    while (!queue.empty()) {
        const Pass::Entry top = queue.top();
        const OpenMesh::FaceHandle f0(top.face);
        if (mesh_.status(f0).deleted() || mesh_.property(error_, f0) != top.error) {
            queue.pop();
            continue;
        }
        if (live_vertices_ >= settings_.max_vertices ||
            ((++pass.iterations & 15) == 0 && pass.out_of_time(0.9))) {
            pass.stats.complete = false;
            break;
        }
        queue.pop();
        if (!splittable(f0)) {
            pass.unrefined_max = std::max(pass.unrefined_max, top.error);
            continue;
        }
        split_towards(pass, f0);
    }
    for (; !queue.empty(); queue.pop()) {
        const OpenMesh::FaceHandle f(queue.top().face);
        if (!mesh_.status(f).deleted() && mesh_.property(error_, f) == queue.top().error)
            pass.unrefined_max = std::max(pass.unrefined_max, queue.top().error);
    }
}

void AdaptiveMesh::split_towards(Pass& pass, OpenMesh::FaceHandle f0) {
    // Bisects the terminal edges of f0's path until f0's own starting edge is bisected; the new
    // faces above the target join the queue.
    const auto e0 = settings_.colour_edge ? colour_edge(f0) : longest_edge(f0);
    for (bool done = false; !done && live_vertices_ < settings_.max_vertices;) {
        // A path from a shorter edge can come back to f0 and split it: then f0 is estimated
        // again (and queued if still above the target) and this path ends.
        if (mesh_.face_handle(mesh_.halfedge_handle(e0, 0)) != f0 &&
            mesh_.face_handle(mesh_.halfedge_handle(e0, 1)) != f0)
            break;
        const auto e = terminal_edge(f0, e0);
        done = e == e0;
        bisect(e, pass.stats);
        for (auto nf : mesh_.vf_range(OpenMesh::VertexHandle(int(mesh_.n_vertices()) - 1)))
            if (mesh_.property(error_, nf) > settings_.split_lsb)
                pass.queue.push({mesh_.property(error_, nf), nf.idx()});
    }
}

OpenMesh::EdgeHandle AdaptiveMesh::terminal_edge(OpenMesh::FaceHandle f,
                                                 OpenMesh::EdgeHandle e) const {
    // Walks the longest-edge propagation path from edge e of face f: across e to the
    // neighbouring face and on to its longest edge, until that is e again (the terminal edge),
    // the boundary or a locked edge. Lengths ascend strictly along the path (longest_edge's
    // total order), so it ends.
    for (int step = 0; step < 4096; ++step) {
        const auto h = mesh_.halfedge_handle(e, 0);
        const auto across = mesh_.face_handle(h) == f
                                ? mesh_.face_handle(mesh_.halfedge_handle(e, 1))
                                : mesh_.face_handle(h);
        if (!across.is_valid()) break;
        const auto next = longest_edge(across);
        if (!next.is_valid() || next == e || edge_locked(next)) break;
        f = across;
        e = next;
    }
    return e;
}

}  // namespace aerial::mesh
