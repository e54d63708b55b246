// The module's OFF reader (module/src/scene/off_reader.cpp) behind load_mesh_file: from a valid
// file it gives the mesh OpenMesh's own OFF reader gives, and it refuses malformed files with a
// message naming the line, where OpenMesh reserved gigabytes (found by fuzz_mesh_io).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "aerial/scene.hpp"

namespace {

using aerial::scene::load_mesh_file;
using aerial::scene::MeshData;

struct Traits : OpenMesh::DefaultTraits {
    VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::TexCoord2D);
    FaceAttributes(OpenMesh::Attributes::Normal);
};
using OpenMeshTriMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

/// `name` in the temporary directory, prefixed with the running test's suite and name: ctest
/// runs tests as parallel processes that share the directory, and two tests writing the same
/// name (test_scene and test_off_reader both have a huge.off) would read each other's
/// half-written files.
std::string temp_file(const std::string& name, const std::string& text) {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string path =
        ::testing::TempDir() + test->test_suite_name() + "." + test->name() + "." + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

/// The file as OpenMesh's own OFF reader builds it, in load_mesh_file's layout.
MeshData through_openmesh(const std::string& path) {
    OpenMeshTriMesh mesh;
    mesh.request_vertex_normals();
    mesh.request_vertex_texcoords2D();
    mesh.request_face_normals();
    OpenMesh::IO::Options options;
    options += OpenMesh::IO::Options::VertexNormal;
    options += OpenMesh::IO::Options::VertexTexCoord;
    EXPECT_TRUE(OpenMesh::IO::read_mesh(mesh, path, options)) << path;
    if (!options.check(OpenMesh::IO::Options::VertexNormal)) {
        mesh.update_face_normals();
        mesh.update_vertex_normals();
    }
    MeshData out;
    for (const auto vh : mesh.vertices()) {
        const auto p = mesh.point(vh);
        auto n = mesh.normal(vh);
        if (n.norm() > 0.0f) n.normalize();
        out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
        out.normals.insert(out.normals.end(), {n[0], n[1], n[2]});
        if (options.check(OpenMesh::IO::Options::VertexTexCoord)) {
            const auto t = mesh.texcoord2D(vh);
            out.texcoords.insert(out.texcoords.end(), {t[0], t[1]});
        }
    }
    for (const auto fh : mesh.faces()) {
        for (const auto vh : mesh.fv_range(fh)) out.indices.push_back(std::uint32_t(vh.idx()));
    }
    return out;
}

TEST(OffReader, GivesTheMeshOpenMeshGivesForValidFiles) {
    const struct {
        const char* name;
        const char* text;
    } files[] = {
        {"triangle.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"crlf.off", "OFF\r\n4 1 4\r\n0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n"},
        {"polygon.off", "OFF\n5 1 0\n0 0 0\n2 0 0\n3 1 0\n1 2 0\n-1 1 0\n5 0 1 2 3 4\n"},
        {"normals.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0.6 0.8\n0 1 0 1 0 0\n3 0 1 2\n"},
        {"texcoords.off", "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n"},
        {"colours.off",
         "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2 1 0 0\n"},
        {"everything.off",
         "STCNOFF\n3 1 0\n0 0 0 0 0 1 0.5 0.5 0.5 0 0\n1 0 0 0 0 1 0.5 0.5 0.5 1 0\n"
         "0 1 0 0 0 1 0.5 0.5 0.5 0 1\n3 0 1 2\n"},
        // Three faces on one edge: OpenMesh's importer gives the third its own vertices.
        {"nonmanifold.off",
         "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 -1 0\n3 0 1 2\n3 0 1 3\n3 0 1 4\n"},
    };
    for (const auto& f : files) {
        SCOPED_TRACE(f.name);
        const std::string path = temp_file(f.name, f.text);
        const auto ours = load_mesh_file(path);
        ASSERT_TRUE(ours) << ours.error().message;
        const MeshData theirs = through_openmesh(path);
        EXPECT_EQ(ours->indices, theirs.indices);
        EXPECT_EQ(ours->positions, theirs.positions);
        EXPECT_EQ(ours->texcoords, theirs.texcoords);
        ASSERT_EQ(ours->normals.size(), theirs.normals.size());
        for (std::size_t i = 0; i < theirs.normals.size(); ++i) {
            // load_mesh_file gives a vertex without a normal (0, 0, 1); compare the others.
            if (theirs.normals[i - i % 3] == 0.0f && theirs.normals[i - i % 3 + 1] == 0.0f &&
                theirs.normals[i - i % 3 + 2] == 0.0f) {
                continue;
            }
            EXPECT_NEAR(ours->normals[i], theirs.normals[i], 1e-6f) << "normal component " << i;
        }
    }
}

// Geomview's OFF allows the counts on the header line and '#' comments anywhere; OpenMesh's
// reader reads no mesh from either.
TEST(OffReader, ReadsCountsOnTheHeaderLineAndComments) {
    const auto apart =
        load_mesh_file(temp_file("apart.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    const auto together =
        load_mesh_file(temp_file("together.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    ASSERT_TRUE(apart) << apart.error().message;
    ASSERT_TRUE(together) << together.error().message;
    EXPECT_EQ(together->positions, apart->positions);
    EXPECT_EQ(together->indices, apart->indices);
    const auto comments = load_mesh_file(temp_file(
        "comments.off", "# a triangle\nOFF\n\n3 1 0  # counts\n0 0 0\n1 0 0 #x\n0 1 0\n3 0 1 2\n"));
    ASSERT_TRUE(comments) << comments.error().message;
    EXPECT_EQ(comments->positions, apart->positions);
    EXPECT_EQ(comments->indices, apart->indices);
}

TEST(OffReader, RefusesMalformedFilesNamingTheLine) {
    const struct {
        const char* name;
        std::string text;
        const char* expected;
    } cases[] = {
        // fuzz_mesh_io: OpenMesh read this header's counts as billions and reserved 14 GB.
        {"vtab.off",
         std::string("OFF\x0b\x0b"
                     "0  0\n"),
         "line 1: it does not start with an OFF"},
        {"empty.off", "", "the file is empty"},
        {"word.off", "OFFICE\n3 1 0\n", "got 'OFFICE'"},
        {"fourd.off", "4OFF\n3 1 0\n", "4OFF and nOFF"},
        {"binary.off", "OFF BINARY\n", "binary OFF is not supported"},
        {"nocounts.off", "OFF\n", "no vertex and face counts"},
        {"counts.off", "OFF\n3 x 0\n", "line 2: expected the vertex and face counts"},
        {"negative.off", "OFF\n-3 1 0\n", "line 2: expected the vertex and face counts"},
        {"huge.off", "OFF\n90000000 1 0\n0 0 0\n", "declares 90000000 vertices"},
        {"short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n", "declares 3 vertices and 1 faces"},
        {"notnumber.off", "OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n",
         "line 4: vertex 1: 'x' is not a number"},
        {"fields.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n",
         "line 4: vertex 1 has 2 numbers, expected 3"},
        {"colourless.off", "COFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "line 3: vertex 0 has 3 numbers, expected 3 plus 3 or 4 colour components"},
        {"index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
         "line 6: face 0: vertex index '7' is not one of the 3 vertices"},
        {"edge.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
         "line 6: face 0: expected its vertex count (3 or more), got '2'"},
        {"corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n",
         "expected 4 vertex indices and at most 4 colour components, got 3 numbers"},
        {"trailing.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n",
         "line 7: more lines than the header's 3 vertices and 1 faces"},
    };
    for (const auto& c : cases) {
        const auto r = load_mesh_file(temp_file(c.name, c.text));
        ASSERT_FALSE(r) << c.name;
        EXPECT_NE(r.error().message.find(c.name), std::string::npos) << r.error().message;
        EXPECT_NE(r.error().message.find(c.expected), std::string::npos) << r.error().message;
    }
}

}  // namespace
