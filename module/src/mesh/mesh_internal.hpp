// Helpers shared by the mesh sources and aerial::validation's dense_error (not installed).
#pragma once

#include <cmath>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/mesh.hpp"

namespace aerial::mesh {

inline glm::dvec3 to_glm(const Mesh::Point& p) { return {p[0], p[1], p[2]}; }
inline Mesh::Point to_point(const glm::dvec3& p) { return {p.x, p.y, p.z}; }
inline bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The largest channel difference of two displayed colours, in 8-bit steps.
float channel_error_lsb(const glm::vec3& a, const glm::vec3& b);

/// Angle (rad) the longest edge of the triangle p subtends from the eye, bounded by the nearest
/// vertex's distance.
double angular_size(const Frame<float>& frame, const glm::dvec3 (&p)[3]);

/// Calls visit(a, b, c) at the barycentric points (i, j, k) / n of a triangle, without the
/// corners and without the points on the edges flagged in `skip_edge`.
template <class Visit>
void visit_grid(int n, const bool (&skip_edge)[3], Visit&& visit) {
    // Barycentric points (i, j, k) / n without the corners; edge e runs from vertex e to e + 1,
    // so a point on it has a zero weight for vertex (e + 2) % 3.
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; i + j <= n; ++j) {
            const int k = n - i - j;
            if (i == n || j == n || k == n) continue;
            const int w[3] = {i, j, k};
            bool skip = false;
            for (int e = 0; e < 3; ++e) skip = skip || (skip_edge[e] && w[(e + 2) % 3] == 0);
            if (!skip) visit(double(i) / n, double(j) / n, double(k) / n);
        }
    }
}

/// colour_error with the midpoints of the edges flagged in `skip_edge` left out (edge i runs from
/// vertex i to vertex i + 1): the adaptive mesh does not count locked edges it cannot split.
/// `sample_multiple` times the samples per edge colour_error takes (a grid that contains its
/// samples).
float colour_error_skipping(const Frame<float>& frame, const ColourOptions& options,
                            const glm::dvec3 (&p)[3], const glm::vec3 (&c)[3],
                            const bool (&skip_edge)[3], int sample_multiple = 1);

/// The error at the midpoint of the edge a-b alone (the same sample colour_error takes there).
float edge_midpoint_error(const Frame<float>& frame, const ColourOptions& options,
                          const glm::dvec3& a, const glm::dvec3& b, const glm::vec3& ca,
                          const glm::vec3& cb);

}  // namespace aerial::mesh

namespace aerial::mesh {

/// New index of each old vertex and face after compact_keeping_order (-1: it was deleted).
struct CompactMaps {
    std::vector<int> vertex, face;
};

/// Removes the deleted vertices, edges and faces like Mesh::garbage_collection(), but the live
/// elements of each kind keep their relative order (old index i < j gives new index i' < j').
CompactMaps compact_keeping_order(Mesh& mesh);

}  // namespace aerial::mesh
