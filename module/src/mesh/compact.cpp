// Garbage collection that keeps the order of what it keeps.
//
// OpenMesh's garbage_collection() fills each hole with the last live element, so the live
// elements change their relative order. AdaptiveMesh breaks ties by handle (the longest edge of a
// face, the worst face of its heap) and appends every new element, so with an order-preserving
// compaction every comparison it makes afterwards comes out as without one: a compacted mesh
// evolves exactly like one that never compacts. Only public ArrayKernel calls are used: the
// properties (positions, status, normals, the caller's) move with copy_all_properties, and the
// connectivity is written back through the set_* calls.
#include <cstddef>
#include <vector>

#include "mesh_internal.hpp"

namespace aerial::mesh {
namespace {

/// New index of every element (-1: deleted), in order; returns the number kept.
template <typename Handle, typename IsDeleted>
int number_live(std::size_t n, IsDeleted is_deleted, std::vector<int>& out) {
    out.assign(n, -1);
    int kept = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (!is_deleted(Handle(int(i)))) out[i] = kept++;
    return kept;
}

}  // namespace

CompactMaps compact_keeping_order(Mesh& mesh) {
    CompactMaps maps;
    std::vector<int> edge;
    const int nv = number_live<OpenMesh::VertexHandle>(
        mesh.n_vertices(), [&](auto h) { return mesh.status(h).deleted(); }, maps.vertex);
    const int ne = number_live<OpenMesh::EdgeHandle>(
        mesh.n_edges(), [&](auto h) { return mesh.status(h).deleted(); }, edge);
    const int nf = number_live<OpenMesh::FaceHandle>(
        mesh.n_faces(), [&](auto h) { return mesh.status(h).deleted(); }, maps.face);

    auto vertex = [&](OpenMesh::VertexHandle v) {
        return v.is_valid() ? OpenMesh::VertexHandle(maps.vertex[std::size_t(v.idx())]) : v;
    };
    auto halfedge = [&](OpenMesh::HalfedgeHandle h) {
        if (!h.is_valid()) return h;
        const int e = edge[std::size_t(h.idx() / 2)];
        return e < 0 ? OpenMesh::HalfedgeHandle() : OpenMesh::HalfedgeHandle(2 * e + (h.idx() & 1));
    };
    auto face = [&](OpenMesh::FaceHandle f) {
        return f.is_valid() ? OpenMesh::FaceHandle(maps.face[std::size_t(f.idx())]) : f;
    };

    // The connectivity of the live elements, in the new numbering.
    struct Links {
        OpenMesh::VertexHandle to;
        OpenMesh::HalfedgeHandle next;
        OpenMesh::FaceHandle face;
    };
    std::vector<OpenMesh::HalfedgeHandle> vertex_out(static_cast<std::size_t>(nv));
    std::vector<OpenMesh::HalfedgeHandle> face_halfedge(static_cast<std::size_t>(nf));
    std::vector<Links> links(2 * std::size_t(ne));
    for (std::size_t i = 0; i < maps.vertex.size(); ++i)
        if (maps.vertex[i] >= 0)
            vertex_out[std::size_t(maps.vertex[i])] =
                halfedge(mesh.halfedge_handle(OpenMesh::VertexHandle(int(i))));
    for (std::size_t i = 0; i < edge.size(); ++i) {
        if (edge[i] < 0) continue;
        for (int side = 0; side < 2; ++side) {
            const OpenMesh::HalfedgeHandle h(int(2 * i) + side);
            links[2 * std::size_t(edge[i]) + std::size_t(side)] = {
                vertex(mesh.to_vertex_handle(h)), halfedge(mesh.next_halfedge_handle(h)),
                face(mesh.face_handle(h))};
        }
    }
    for (std::size_t i = 0; i < maps.face.size(); ++i)
        if (maps.face[i] >= 0)
            face_halfedge[std::size_t(maps.face[i])] =
                halfedge(mesh.halfedge_handle(OpenMesh::FaceHandle(int(i))));

    // Properties: each live element moves down to its new slot, in increasing order, so the slot
    // it lands on holds a deleted element or one that has already moved.
    for (std::size_t i = 0; i < maps.vertex.size(); ++i)
        if (maps.vertex[i] >= 0 && maps.vertex[i] != int(i))
            mesh.copy_all_properties(OpenMesh::VertexHandle(int(i)),
                                     OpenMesh::VertexHandle(maps.vertex[i]), true);
    for (std::size_t i = 0; i < edge.size(); ++i) {
        if (edge[i] < 0 || edge[i] == int(i)) continue;
        mesh.copy_all_properties(OpenMesh::EdgeHandle(int(i)), OpenMesh::EdgeHandle(edge[i]), true);
        for (int side = 0; side < 2; ++side)
            mesh.copy_all_properties(OpenMesh::HalfedgeHandle(int(2 * i) + side),
                                     OpenMesh::HalfedgeHandle(2 * edge[i] + side), true);
    }
    for (std::size_t i = 0; i < maps.face.size(); ++i)
        if (maps.face[i] >= 0 && maps.face[i] != int(i))
            mesh.copy_all_properties(OpenMesh::FaceHandle(int(i)),
                                     OpenMesh::FaceHandle(maps.face[i]), true);

    mesh.resize(std::size_t(nv), std::size_t(ne), std::size_t(nf));
    for (int i = 0; i < nv; ++i)
        mesh.set_halfedge_handle(OpenMesh::VertexHandle(i), vertex_out[std::size_t(i)]);
    for (int i = 0; i < 2 * ne; ++i) {
        const OpenMesh::HalfedgeHandle h(i);
        const Links& l = links[std::size_t(i)];
        mesh.set_vertex_handle(h, l.to);
        mesh.set_face_handle(h, l.face);
        mesh.set_next_halfedge_handle(h, l.next);  // sets next's previous too
    }
    for (int i = 0; i < nf; ++i)
        mesh.set_halfedge_handle(OpenMesh::FaceHandle(i), face_halfedge[std::size_t(i)]);
    return maps;
}

}  // namespace aerial::mesh
