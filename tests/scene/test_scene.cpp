// The scene graph without GL: validation, traversal, heightfield tiles, procedural terrain and
// mesh files read through OpenMesh.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "aerial/scene.hpp"
#include "aerial/scene_file.hpp"

namespace {

using namespace aerial::scene;

/// `name` in the temporary directory, prefixed with the running test's suite and name: ctest
/// runs tests as parallel processes that share the directory, and two tests writing the same
/// name (test_scene and test_off_reader both have a huge.off) would read each other's
/// half-written files.
std::string temp_file(const std::string& name, const std::string& text) {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string path =
        ::testing::TempDir() + test->test_suite_name() + "." + test->name() + "." + name;
    std::ofstream(path) << text;
    return path;
}

std::shared_ptr<const MeshData> triangle() {
    auto mesh = std::make_shared<MeshData>();
    mesh->positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    mesh->indices = {0, 1, 2};
    return mesh;
}

TEST(SceneGraph, TraversalComposesTransformsParentsFirst) {
    auto root = make_group("world");
    root->transform = glm::translate(glm::dmat4(1.0), glm::dvec3(10, 0, 0));
    Node* group = root->add(make_group("group"));
    group->transform = glm::scale(glm::dmat4(1.0), glm::dvec3(2.0));
    Node* leaf = group->add(make_mesh("leaf", triangle()));
    leaf->transform = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 5, 0));
    Node* hidden = root->add(make_mesh("hidden", triangle()));
    hidden->visible = false;
    std::vector<std::string> order;
    glm::dvec3 leaf_origin{0.0};
    traverse(*root, [&](const Node& n, const glm::dmat4& world) {
        order.push_back(n.name);
        if (&n == leaf) leaf_origin = glm::dvec3(world * glm::dvec4(0, 0, 0, 1));
    });
    EXPECT_EQ(order, (std::vector<std::string>{"world", "group", "leaf"}));
    EXPECT_EQ(leaf_origin, glm::dvec3(10, 10, 0)) << "translate(10) * scale(2) * translate(5)";
}

TEST(SceneGraph, ValidateNamesTheNodePathAndField) {
    auto root = make_group("world");
    auto bad = std::make_shared<MeshData>(*triangle());
    bad->indices = {0, 1, 7};
    root->add(make_group("tiles"))->add(make_mesh("tile 0", bad));
    auto error = validate(*root);
    ASSERT_TRUE(error);
    EXPECT_EQ(error->field, "world/tiles/tile 0");
    // The one message style, pinned whole: the node's path is the field, the mesh's own field
    // and its expected and got follow.
    EXPECT_EQ(error->message,
              "aerial::scene::validate(): world/tiles/tile 0: mesh indices: expected values < 3 "
              "(the vertex count), got 7 at index 2");

    auto terrain = make_group("world");
    terrain->add(make_terrain_tile("flat", triangle()));
    error = validate(*terrain);
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("without normals"), std::string::npos) << error->message;

    auto texture = std::make_shared<Texture>();
    texture->width = 3;
    texture->height = 4;
    texture->rgb.resize(36);
    auto textured = make_group("world");
    textured->add(make_mesh("m", triangle(), texture));
    error = validate(*textured);
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("width: expected a power of two"), std::string::npos)
        << error->message;
}

TEST(Texture, MipmapLevelsAreBoxAveragesRoundedHalfUpDownToOnePixel) {
    Texture t;
    t.width = 4;
    t.height = 2;
    // Red: 2 x 2 blocks summing to 7 (7 / 4 = 1.75 -> 2) and 2 (0.5 -> 1); green 255, blue 0.
    const int red[2][4] = {{1, 2, 0, 1}, {2, 2, 0, 1}};
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 4; ++x) t.rgb.insert(t.rgb.end(), {std::uint8_t(red[y][x]), 255, 0});
    }
    const auto levels = mipmap_levels(t);
    ASSERT_EQ(levels.size(), 3u) << "4x2, 2x1, 1x1";
    EXPECT_EQ(levels[0], t.rgb);
    ASSERT_EQ(levels[1].size(), 2u * 3u);
    EXPECT_EQ(levels[1][0], 2);
    EXPECT_EQ(levels[1][3], 1);
    EXPECT_EQ(levels[1][1], 255);
    ASSERT_EQ(levels[2].size(), 3u);
    EXPECT_EQ(levels[2][0], 2) << "(2 + 1) / 2 = 1.5 rounds up";
    EXPECT_EQ(levels[2][1], 255);
    EXPECT_EQ(levels[2][2], 0);
}

TEST(Heightfield, GridMatchesTheFunctionWithUnitNormals) {
    HeightfieldSpec spec;
    spec.origin_x = 100;
    spec.origin_y = -50;
    spec.size = 80;
    spec.resolution = 5;
    spec.texture_repeat = 40;
    // A plane z = 0.5 x: every normal is (-0.5, 0, 1) / sqrt(1.25).
    auto mesh = heightfield_mesh(spec, [](double x, double) { return 0.5 * x; });
    ASSERT_TRUE(mesh) << mesh.error().message;
    EXPECT_FALSE(validate(*mesh));
    EXPECT_EQ(mesh->vertex_count(), 25u);
    EXPECT_EQ(mesh->indices.size(), 4u * 4u * 6u);
    const double k = 1.0 / std::sqrt(1.25);
    for (std::size_t i = 0; i < mesh->vertex_count(); ++i) {
        EXPECT_NEAR(mesh->positions[3 * i + 2], 0.5 * mesh->positions[3 * i], 1e-4);
        EXPECT_NEAR(mesh->normals[3 * i], -0.5 * k, 1e-5);
        EXPECT_NEAR(mesh->normals[3 * i + 2], k, 1e-5);
    }
    EXPECT_FLOAT_EQ(mesh->positions[3 * 24], 180.0f) << "the last corner is origin + size";
    EXPECT_FLOAT_EQ(mesh->texcoords[2 * 24], 180.0f / 40.0f);
}

TEST(Heightfield, BadSpecsAndHeightsNameTheField) {
    HeightfieldSpec spec;
    spec.resolution = 1;
    auto flat = [](double, double) { return 0.0; };
    EXPECT_EQ(heightfield_mesh(spec, flat).error().field, "resolution");
    spec = {};
    spec.size = -1;
    EXPECT_EQ(heightfield_mesh(spec, flat).error().field, "size");
    spec = {};
    auto result = heightfield_mesh(spec, [](double x, double) { return x > 500 ? NAN : 0.0; });
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().field, "height");
}

TEST(ProceduralTerrain, DeterministicInRangeAndSeedDependent) {
    ProceduralTerrain t;
    t.amplitude = 600;
    double lo = 1e9, hi = -1e9, differ = 0;
    ProceduralTerrain other = t;
    other.seed = 2;
    for (int i = 0; i < 2000; ++i) {
        const double x = 37.0 * i - 30000, y = 11.0 * i * i - 8000;
        const double h = procedural_height(t, x, y);
        EXPECT_EQ(h, procedural_height(t, x, y));
        lo = std::min(lo, h);
        hi = std::max(hi, h);
        differ += std::abs(h - procedural_height(other, x, y));
    }
    EXPECT_GE(lo, 0.0);
    EXPECT_LE(hi, 600.0);
    EXPECT_GT(hi - lo, 150.0) << "hills, not a plain";
    EXPECT_GT(differ / 2000, 10.0) << "another seed, another landscape";
}

TEST(MeshFile, ReadsObjQuadsAsTrianglesWithTexcoordsAndComputedNormals) {
    const std::string path = temp_file("quad.obj",
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                       "f 1/1 2/2 3/3 4/4\n");
    auto mesh = load_mesh_file(path);
    ASSERT_TRUE(mesh) << mesh.error().message;
    EXPECT_EQ(mesh->vertex_count(), 4u);
    EXPECT_EQ(mesh->indices.size(), 6u) << "one quad, two triangles";
    ASSERT_EQ(mesh->normals.size(), 12u);
    for (int v = 0; v < 4; ++v) EXPECT_NEAR(mesh->normals[3 * v + 2], 1.0f, 1e-6);
    EXPECT_EQ(mesh->texcoords.size(), 8u);
}

TEST(MeshFile, ReadsOffAndPly) {
    auto off = load_mesh_file(temp_file("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    ASSERT_TRUE(off) << off.error().message;
    EXPECT_EQ(off->indices.size(), 3u);
    auto ply = load_mesh_file(temp_file(
        "t.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
    ASSERT_TRUE(ply) << ply.error().message;
    EXPECT_EQ(ply->vertex_count(), 3u);
}

TEST(MeshFile, ErrorsNameThePathAndTheProblem) {
    const std::string missing = ::testing::TempDir() + "no_such_mesh.obj";
    auto r = load_mesh_file(missing);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().field, missing);
    EXPECT_EQ(r.error().message, "aerial::scene::load_mesh_file(): " + missing +
                                     ": cannot open the file (missing or unreadable)");

    r = load_mesh_file(temp_file("mesh.stl", "solid x\n"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("unknown mesh format '.stl'"), std::string::npos)
        << r.error().message;

    r = load_mesh_file(temp_file("broken.off", "OFF\n3 1 0\n0 0 0\nthis is not a number\n"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("broken.off"), std::string::npos) << r.error().message;

    r = load_mesh_file(temp_file("points.obj", "v 0 0 0\nv 1 0 0\n"));
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("no faces"), std::string::npos) << r.error().message;
}

// Files that made OpenMesh's readers allocate gigabytes, loop forever or write past a buffer
// (found by fuzz_mesh_io) are refused before OpenMesh sees them, and the error says why.
TEST(MeshFile, RefusesWhatOpenMeshWouldMisread) {
    const struct {
        const char* name;
        const char* text;
        const char* expected;
    } cases[] = {
        {"huge.ply",
         "ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\nend_header\n",
         "declares 100000000 vertex elements"},
        {"huger.ply",
         "ply\nformat ascii 1.0\nelement vertex 88888888888888888888888888\nproperty float "
         "x\nend_header\n",
         "declares over 10^18 vertex elements"},
        {"fraction.ply",
         "ply\nformat ascii 1.0\nelement vertex .0\nelement vertex 3\nproperty float x\n"
         "end_header\n0\n1\n2\n",
         "header line 3: expected 'element NAME COUNT' with COUNT a decimal integer"},
        {"signed.ply", "ply\nformat ascii 1.0\nelement vertex +3\nproperty float x\nend_header\n",
         "COUNT a decimal integer"},
        {"formatless.ply",
         "ply\nend_header binary_little_endian 1.0\nelement vertex 3\nend_header\n",
         "header line 2: expected 'end_header' alone on its line"},
        {"unformatted.ply", "ply\nelement vertex 0\nend_header\n", "no 'format' line"},
        {"endless.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_`eader\n",
         "not a PLY keyword"},
        {"format.ply",
         "ply\nformat ascii \xcc\xd1"
         "ent vertex 3\nend_header\n",
         "format ascii"},
        {"orphan.ply",
         "ply\nformat ascii 1.0\ncomment vertex 3\nproperty float x\nelement face 0\n"
         "property list uchar int vertex_indices\nend_header\n",
         "header line 4: a property before any 'element' line"},
        {"list.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n10 0 0\n0 10 1\n3 0 1 2\n555555555555555555555555555555555\n",
         "a list of '555555555555555555555555555555555' entries in a file of"},
        {"plus.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n10 0 0\n0 10 1\n3 0 1 2555+55555555555555555555\n",
         "the value '2555+55555555555555555555' is not a number"},
        {"index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 4/1 1/1 2/1\n", "face index '4/1'"},
        {"unread.obj", "v 0 0 0\nv 1 x 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n",
         "line 2: expected 'v X Y Z"},
        {"control.obj", "v 0 0 0\nv 1 \x01 0\nv 0 1 0\nf 1 2 3\n",
         "line 2: a control character (byte 1)"},
        {"texcoord.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 x\nf 1/1 2/1 3/1\n",
         "line 4: expected 'vt U V [W]'"},
        {"header.off", "OFF(  0\x11 2 \xc9\n", "OFF header word"},
        {"huge.off", "OFF\n90000000 1 0\n0 0 0\n", "declares 90000000 vertices"},
    };
    for (const auto& c : cases) {
        const auto r = load_mesh_file(temp_file(c.name, c.text));
        ASSERT_FALSE(r) << c.name;
        EXPECT_NE(r.error().message.find(c.name), std::string::npos) << r.error().message;
        EXPECT_NE(r.error().message.find(c.expected), std::string::npos) << r.error().message;
    }
    // What they guard keeps working: relative indices, texture coordinates, ASCII PLY lists.
    EXPECT_TRUE(load_mesh_file(
        temp_file("lists.ply",
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                  "end_header\n0 0 0\n10 0 0\n0 10 1\n3 0 1 2\n")));
    EXPECT_TRUE(load_mesh_file(
        temp_file("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf -3/1 -2/1 -1/1\n")));
}

// The one message style for the scene file, pinned whole: the function the caller called, the
// field's path in the file, expected and got; a file's content errors end with its path.
TEST(SceneFile, MessagesAreFunctionFieldExpectedGot) {
    const std::string text =
        R"({"camera": {"eye": [0, 0, 100], "direction": [0, 1, 0], "fov_y_deg": 200},)"
        R"( "sun": {"elevation_deg": 30, "azimuth_deg": 0}, "terrain": {}})";
    const auto parsed = scene_file_from_json(text);
    ASSERT_FALSE(parsed);
    EXPECT_EQ(parsed.error().field, "camera.fov_y_deg");
    EXPECT_EQ(parsed.error().message,
              "aerial::scene::scene_file_from_json(): camera.fov_y_deg: expected a number in "
              "(0, 180), got 200");

    const std::string path = temp_file("scene.json", text);
    const auto loaded = load_scene_file(path);
    ASSERT_FALSE(loaded);
    EXPECT_EQ(loaded.error().field, "camera.fov_y_deg");
    EXPECT_EQ(loaded.error().message,
              "aerial::scene::load_scene_file(): camera.fov_y_deg: expected a number in (0, 180), "
              "got 200 (in " +
                  path + ")");

    // An error of the atmosphere the file holds: its field under "atmosphere.".
    const auto atmosphere = scene_file_from_json(
        R"({"camera": {"eye": [0, 0, 100], "direction": [0, 1, 0]}, "atmosphere": {"mie_g": 2},)"
        R"( "sun": {"elevation_deg": 30, "azimuth_deg": 0}, "terrain": {}})");
    ASSERT_FALSE(atmosphere);
    EXPECT_EQ(atmosphere.error().field, "atmosphere.mie_g");
    EXPECT_EQ(atmosphere.error().message,
              "aerial::scene::scene_file_from_json(): atmosphere.mie_g: expected |g| < 1 (g > 0 "
              "scatters forwards), got 2");

    const std::string missing = ::testing::TempDir() + "no_such_scene.json";
    EXPECT_EQ(load_scene_file(missing).error().message,
              "aerial::scene::load_scene_file(): " + missing + ": cannot open the scene file");
}

// Geometry whose vertices a float cannot hold is refused by name, never built as infinities.
TEST(SceneFile, GeometryBeyondTheFloatRangeIsRefused) {
    const std::string head = R"({"camera": {"eye": [0, 0, 100], "direction": [0, 1, 0]},)"
                             R"( "sun": {"elevation_deg": 30, "azimuth_deg": 0}, )";
    const auto field_of = [&](const std::string& rest) {
        const auto parsed = scene_file_from_json(head + rest + "}");
        return parsed ? std::string("accepted") : parsed.error().field;
    };
    EXPECT_EQ(field_of(R"("terrain": {"size": 1e300})"), "terrain");
    EXPECT_EQ(field_of(R"("terrain": {"height_amplitude": 1e39})"), "terrain");
    EXPECT_EQ(field_of(R"("terrain": {"texture_repeat": 1e-300})"), "terrain");
    EXPECT_EQ(field_of(R"("boxes": [{"center": [0, 0, 0], "size": [1, 1, 1]},)"
                       R"( {"center": [1e10, 0, 0], "size": [1, 1, 1]}])"),
              "boxes[1]");
    EXPECT_EQ(field_of(R"("terrain": {"size": 1e6, "height_amplitude": 1e4})"), "accepted");
}

}  // namespace
