// Relocation of a new vertex of AdaptiveMesh (settings.relocate): a pattern search on the surface,
// within the vertex's one-ring, for where the fewest of its faces are above split_lsb.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "adaptive_internal.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {

void AdaptiveMesh::relocate(OpenMesh::VertexHandle v, UpdateStats& stats) {
    // A pattern search on the surface: from the edge midpoint, try kDirections points at a step
    // around the vertex, move to the best that is better (at most kMoves times a step), halve
    // the step kLevels times. Better means fewer of the vertex's faces above split_lsb (faces that
    // refinement would split next), then a smaller sum of their errors: minimising the largest
    // error alone hardly helps (a face's error far from the vertex does not move with it).
    constexpr int kDirections = 8, kLevels = 3, kMoves = 2;
    constexpr double kFirstStep = 0.25;  // of the distance to the nearest ring vertex
    if (mesh_.is_boundary(v)) return;
    // The vertex's faces, each as its three corners (halfedge k runs from corner k to k + 1),
    // which corner is v, which edges are locked, and the face's normal with v at the midpoint.
    struct RingFace {
        glm::dvec3 p[3];
        glm::vec3 c[3];
        bool skip[3];
        int at = -1;
        glm::dvec3 normal;
    };
    std::vector<RingFace> ring;
    const glm::dvec3 x0 = to_glm(mesh_.point(v));
    for (auto f : mesh_.vf_range(v)) {
        RingFace r;
        int k = 0;
        for (auto h : mesh_.fh_range(f)) {
            const auto w = mesh_.from_vertex_handle(h);
            r.p[k] = to_glm(mesh_.point(w));
            if (w == v)
                r.at = k;
            else
                r.c[k] = vertex_colour(w);
            r.skip[k] = edge_locked(mesh_.edge_handle(h));
            ++k;
        }
        r.normal = glm::cross(r.p[1] - r.p[0], r.p[2] - r.p[0]);
        ring.push_back(r);
    }
    double nearest = std::numeric_limits<double>::infinity();
    for (auto w : mesh_.vv_range(v))
        nearest = std::min(nearest, glm::length(to_glm(mesh_.point(w)) - x0));
    if (ring.empty() || !(nearest > 0.0)) return;
    auto smallest_angle = [&](const glm::dvec3& x) {
        double least = kPi;
        for (RingFace& r : ring) {
            r.p[r.at] = x;
            least = std::min(least, min_angle(r.p[0], r.p[1], r.p[2]));
        }
        return least;
    };
    const double bound =
        std::min(double(settings_.relocate_min_angle_deg) * kPi / 180.0, smallest_angle(x0));
    struct Score {
        int above = std::numeric_limits<int>::max();  // refused positions score worst
        float sum = 0.0f;
        bool operator<(const Score& o) const {
            return above < o.above || (above == o.above && sum < o.sum);
        }
    };
    auto score = [&](const glm::dvec3& x) {
        for (RingFace& r : ring) {
            r.p[r.at] = x;
            if (!(glm::dot(glm::cross(r.p[1] - r.p[0], r.p[2] - r.p[0]), r.normal) > 0.0))
                return Score{};  // turned over
        }
        if (!(smallest_angle(x) >= bound)) return Score{};
        const glm::vec3 colour = display_colour(*frame_, settings_.colour, x);
        Score out;
        out.above = 0;
        for (RingFace& r : ring) {
            r.p[r.at] = x;
            r.c[r.at] = colour;
            const float e = colour_error_skipping(*frame_, settings_.colour, r.p, r.c, r.skip);
            out.above += e > settings_.split_lsb ? 1 : 0;
            out.sum += e;
        }
        return out;
    };
    Score best = score(x0);
    if (best.above == 0) return;  // refinement would split none of the faces
    // The tangent plane: the surface's normal (sphere, heightfield) or the faces' mean normal.
    glm::dvec3 n(0.0);
    if (surface_.kind == Surface::Kind::sphere)
        n = x0 - surface_.centre;
    else if (surface_.kind == Surface::Kind::heightfield)
        n = glm::dvec3(0.0, 0.0, 1.0);
    else
        for (const RingFace& r : ring) n += glm::normalize(r.normal);
    if (!(glm::length(n) > 0.0)) return;
    n = glm::normalize(n);
    const glm::dvec3 along =
        to_glm(mesh_.point(mesh_.to_vertex_handle(mesh_.halfedge_handle(v)))) - x0;
    glm::dvec3 u = along - glm::dot(along, n) * n;
    if (!(glm::length(u) > 0.0)) return;
    u = glm::normalize(u);
    const glm::dvec3 w = glm::cross(n, u);
    glm::dvec3 x = x0;
    double step = kFirstStep * nearest;
    for (int level = 0; level < kLevels; ++level, step *= 0.5) {
        for (int move = 0; move < kMoves; ++move) {
            glm::dvec3 next = x;
            Score next_score = best;
            for (int k = 0; k < kDirections; ++k) {
                const double a = 2.0 * kPi * k / kDirections;
                const glm::dvec3 y =
                    surface_.project(x + step * (std::cos(a) * u + std::sin(a) * w));
                const Score s = score(y);
                if (s < next_score) {
                    next = y;
                    next_score = s;
                }
            }
            if (next == x) break;
            x = next;
            best = next_score;
        }
    }
    if (x == x0) return;
    mesh_.set_point(v, to_point(x));
    mesh_.property(colour_eye_, v).v = glm::vec3(kNaN);
    ++stats.relocated;
}

}  // namespace aerial::mesh
