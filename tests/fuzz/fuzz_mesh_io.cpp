// libFuzzer target: mesh files read by the module, then the module's work on them. The first
// byte picks the format (OFF, OBJ, PLY), the rest is the file. The bytes go through
// aerial::scene::load_mesh_file (the module's OFF reader; OpenMesh IO behind the module's checks
// for OBJ and PLY; from a file): an
// accepted MeshData passes validate() and is finite. Its triangles then become an
// aerial::mesh::Mesh, checked by validate_mesh; an accepted mesh goes into AdaptiveMesh::create,
// two updates (eye moved in between) and dense_error: every position stays finite and every error
// figure is finite. (Reading straight through OpenMesh::IO would fuzz OpenMesh's reservation of
// whatever counts a header declares: load_mesh_file rejects counts the file cannot hold.)
// Bad meshes must be rejected with an error, never crash.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <OpenMesh/Core/IO/MeshIO.hh>

#include "aerial/mesh.hpp"
#include "aerial/scene.hpp"
#include "aerial/validation/dense_error.hpp"
#include "fuzz_check.hpp"

namespace {

using aerial::fuzz::check;

constexpr const char* kFormats[] = {"off", "obj", "ply"};
// Meshes above this size are valid but slow to refine on every input.
constexpr std::size_t kMaxFaces = 2000;

const aerial::Frame<float>& frame_at(int which) {
    static const auto frames = [] {
        std::vector<aerial::Frame<float>> f;
        aerial::View view;
        view.sun_dir = {0.0, 0.6, 0.8};
        for (const glm::dvec3 eye : {glm::dvec3(0.0, 0.0, 2.0), glm::dvec3(500.0, -300.0, 80.0)}) {
            view.eye = eye;
            f.push_back(aerial::prepare_frame<float>(aerial::Atmosphere{}, view,
                                                     aerial::Model::hoffman_preetham)
                            .value());
        }
        return f;
    }();
    return frames[std::size_t(which)];
}

void refine(aerial::mesh::Mesh mesh) {
    if (aerial::mesh::validate_mesh(mesh)) return;
    if (mesh.n_faces() > kMaxFaces) return;
    aerial::mesh::AdaptiveSettings settings;
    settings.max_vertices = 4 * mesh.n_vertices() + 64;
    settings.colour.max_samples_per_edge = 3;
    auto adaptive =
        aerial::mesh::AdaptiveMesh::create(std::move(mesh), aerial::mesh::Surface{}, settings);
    check(adaptive.ok(), "AdaptiveMesh::create rejected a mesh validate_mesh accepted");
    aerial::mesh::AdaptiveMesh& refined = adaptive.value();
    for (int which = 0; which < 2; ++which) {
        const auto stats = refined.update(frame_at(which));
        check(std::isfinite(stats.max_error_lsb), "non-finite max_error_lsb after an update");
        check(stats.vertices <= settings.max_vertices, "the update went over its vertex budget");
    }
    for (const auto v : refined.mesh().vertices()) {
        const auto p = refined.mesh().point(v);
        check(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]),
              "a non-finite vertex after refinement");
    }
    const auto dense =
        aerial::validation::dense_error(refined.mesh(), frame_at(1), settings.colour, 0.05, 4);
    check(dense.ok(), "dense_error rejected a refined mesh");
    check(std::isfinite(dense->max_lsb) && std::isfinite(dense->rmse_lsb),
          "non-finite dense error");
}

/// The loaded triangles as an aerial::mesh::Mesh (faces OpenMesh refuses, such as ones that would
/// make an edge non-manifold, are skipped as an engine's importer would), then refined.
void through_adaptive_mesh(const aerial::scene::MeshData& data) {
    aerial::mesh::Mesh mesh;
    std::vector<aerial::mesh::Mesh::VertexHandle> handles;
    for (std::size_t i = 0; i < data.vertex_count(); ++i) {
        handles.push_back(mesh.add_vertex(aerial::mesh::Mesh::Point(
            data.positions[3 * i], data.positions[3 * i + 1], data.positions[3 * i + 2])));
    }
    for (std::size_t i = 0; i + 2 < data.indices.size(); i += 3) {
        mesh.add_face(handles[data.indices[i]], handles[data.indices[i + 1]],
                      handles[data.indices[i + 2]]);
    }
    refine(std::move(mesh));
}

void through_scene_reader(const std::string& bytes, const char* format) {
    const std::string file = "/tmp/aerial-fuzz-mesh-" + std::to_string(::getpid()) + "." + format;
    std::FILE* f = std::fopen(file.c_str(), "wb");
    if (!f) aerial::fuzz::fail("cannot write the temporary mesh file");
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
    auto data = aerial::scene::load_mesh_file(file);
    std::remove(file.c_str());
    if (!data) {
        check(data.error().field == file &&
                  data.error().message.rfind("aerial::scene::load_mesh_file(): " + file + ": ",
                                             0) == 0,
              "a load_mesh_file error without the function and the path");
        return;
    }
    check(!aerial::scene::validate(*data), "load_mesh_file returned an invalid mesh");
    for (float v : data->positions) check(std::isfinite(v), "a non-finite position");
    for (float v : data->normals) check(std::isfinite(v), "a non-finite normal");
    through_adaptive_mesh(*data);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    omerr().disable();  // OpenMesh's own error stream: the fuzzer only wants crashes
    omlog().disable();
    omout().disable();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const char* format = kFormats[data[0] % 3];
    const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
    through_scene_reader(bytes, format);
    return 0;
}
