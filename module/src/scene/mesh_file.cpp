// Mesh files through OpenMesh (OBJ, OFF, PLY): triangulated, with normals and texcoords.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "aerial/scene.hpp"

namespace aerial::scene {
namespace {

struct FileTraits : OpenMesh::DefaultTraits {
    VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::TexCoord2D);
    FaceAttributes(OpenMesh::Attributes::Normal);
};
using FileMesh = OpenMesh::TriMesh_ArrayKernelT<FileTraits>;

std::string lower_extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

}  // namespace

Result<MeshData> load_mesh_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext != "obj" && ext != "off" && ext != "ply") {
        return Error{path,
                     path + ": unknown mesh format '." + ext + "' (expected .obj, .off or .ply)"};
    }
    if (!std::ifstream(path).good()) {
        return Error{path, path + ": cannot open the file (missing or unreadable)"};
    }
    FileMesh mesh;
    mesh.request_vertex_normals();
    mesh.request_vertex_texcoords2D();
    mesh.request_face_normals();
    OpenMesh::IO::Options options;
    options += OpenMesh::IO::Options::VertexNormal;
    options += OpenMesh::IO::Options::VertexTexCoord;
    // OpenMesh reports parse errors on its own error stream; the Result says what failed.
    omerr().disable();
    const bool read = OpenMesh::IO::read_mesh(mesh, path, options);
    omerr().enable();
    if (!read) return Error{path, path + ": OpenMesh could not read it as ." + ext};
    if (mesh.n_faces() == 0) return Error{path, path + ": the file has no faces"};
    if (!options.check(OpenMesh::IO::Options::VertexNormal)) {
        mesh.update_face_normals();
        mesh.update_vertex_normals();
    }
    const bool has_texcoords = options.check(OpenMesh::IO::Options::VertexTexCoord);

    MeshData out;
    out.positions.reserve(mesh.n_vertices() * 3);
    out.normals.reserve(mesh.n_vertices() * 3);
    for (const auto vh : mesh.vertices()) {
        const auto p = mesh.point(vh);
        auto n = mesh.normal(vh);
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (length > 0.0f && std::isfinite(length)) {
            n /= length;
        } else {
            n = FileMesh::Normal(0.0f, 0.0f, 1.0f);  // isolated vertex: any unit vector
        }
        out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
        out.normals.insert(out.normals.end(), {n[0], n[1], n[2]});
        if (has_texcoords) {
            const auto t = mesh.texcoord2D(vh);
            out.texcoords.insert(out.texcoords.end(), {t[0], t[1]});
        }
    }
    out.indices.reserve(mesh.n_faces() * 3);
    for (const auto fh : mesh.faces()) {
        for (const auto vh : mesh.fv_range(fh)) out.indices.push_back(std::uint32_t(vh.idx()));
    }
    if (auto e = validate(out)) return Error{path, path + ": " + e->message};
    return out;
}

}  // namespace aerial::scene
