// Bad data through the mesh and batch APIs: non-finite positions, zero-area and degenerate
// triangles, coordinates at 1e7 m, empty meshes, a vertex budget far too small. Each is a clear
// error naming what is wrong or a finite, valid result; nothing crashes, no NaN colour comes out,
// and what the caller already had (output buffers, the base mesh) is left as it was on failure.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"

namespace {

using aerial::mesh::AdaptiveMesh;
using aerial::mesh::AdaptiveSettings;
using aerial::mesh::Mesh;

constexpr double kInf = std::numeric_limits<double>::infinity();

aerial::Frame<float> frame_at(const glm::dvec3& eye, const glm::dvec3& sun) {
    aerial::View view;
    view.eye = eye;
    view.sun_dir = glm::normalize(sun);
    auto frame = aerial::prepare_frame<float>(*aerial::atmosphere_preset("hazy"), view,
                                              aerial::Model::height);
    EXPECT_TRUE(frame) << frame.error().message;
    return frame.value();
}

/// Every live vertex has a finite position and every live face three distinct live vertices.
::testing::AssertionResult well_formed(const Mesh& mesh) {
    for (auto v : mesh.vertices()) {
        if (mesh.status(v).deleted()) continue;
        const auto p = mesh.point(v);
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
            return ::testing::AssertionFailure() << "vertex " << v.idx() << " is not finite";
        }
    }
    for (auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        int n = 0;
        for (auto v : mesh.fv_range(f)) {
            if (mesh.status(v).deleted()) {
                return ::testing::AssertionFailure()
                       << "face " << f.idx() << " uses deleted vertex " << v.idx();
            }
            ++n;
        }
        if (n != 3) return ::testing::AssertionFailure() << "face " << f.idx() << " has " << n;
    }
    return ::testing::AssertionSuccess();
}

std::vector<Mesh::Point> points_of(const Mesh& mesh) {
    std::vector<Mesh::Point> out;
    for (auto v : mesh.vertices()) out.push_back(mesh.point(v));
    return out;
}

/// A 4 x 4 grid of 100 m cells around (x0, y0, 0), plus triangles that are degenerate: one of
/// zero area with three collinear vertices, one with two coincident vertices, one sliver.
Mesh grid_with_degenerate_triangles(double x0, double y0) {
    Mesh mesh;
    std::vector<Mesh::VertexHandle> grid;
    for (int j = 0; j <= 4; ++j) {
        for (int i = 0; i <= 4; ++i) {
            grid.push_back(mesh.add_vertex(Mesh::Point(x0 + 100.0 * i, y0 + 100.0 * j, 0.0)));
        }
    }
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            const auto a = grid[std::size_t(j * 5 + i)], b = grid[std::size_t(j * 5 + i + 1)];
            const auto c = grid[std::size_t((j + 1) * 5 + i)],
                       d = grid[std::size_t((j + 1) * 5 + i + 1)];
            mesh.add_face(a, b, d);
            mesh.add_face(a, d, c);
        }
    }
    // Separate pieces (so the grid stays manifold): collinear, coincident, sliver.
    const double z = 50.0;
    auto p = [&](double x, double y, double h) {
        return mesh.add_vertex(Mesh::Point(x0 + x, y0 + y, h));
    };
    mesh.add_face(p(0, 600, z), p(100, 600, z), p(200, 600, z));
    const auto twin = p(300, 600, z);
    mesh.add_face(twin, p(300, 600, z), p(300, 700, z));
    mesh.add_face(p(500, 600, z), p(900, 600, z), p(700, 600.000001, z));
    return mesh;
}

TEST(BadMeshData, NonFinitePositionsAreAnErrorNamingTheVertexAndTheBaseIsUntouched) {
    auto base = aerial::mesh::geodesic_dome(3);
    ASSERT_TRUE(base);
    for (double bad : {std::nan(""), kInf, -kInf}) {
        Mesh mesh = base.value();
        mesh.set_point(Mesh::VertexHandle(5), Mesh::Point(0.0, bad, 1.0));
        const auto before = points_of(mesh);
        const auto error = aerial::mesh::validate_mesh(mesh, "terrain");
        ASSERT_TRUE(error.has_value());
        EXPECT_EQ(error->field, "terrain");
        EXPECT_EQ(error->message.rfind("aerial::mesh::validate_mesh(): terrain: expected finite "
                                       "positions, got (0, ",
                                       0),
                  0u)
            << error->message;
        EXPECT_NE(error->message.find("vertex 5"), std::string::npos) << error->message;
        auto made = AdaptiveMesh::create(mesh, aerial::mesh::Surface{}, AdaptiveSettings{});
        ASSERT_FALSE(made);
        EXPECT_NE(made.error().message.find("vertex 5"), std::string::npos) << made.error().message;
        const auto after = points_of(mesh);
        ASSERT_EQ(before.size(), after.size());
        for (std::size_t i = 0; i < before.size(); ++i) {
            // NaN != NaN: the same NaN-ness, then the same value.
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(std::isnan(before[i][c]), std::isnan(after[i][c]));
                if (!std::isnan(before[i][c])) {
                    EXPECT_EQ(before[i][c], after[i][c]);
                }
            }
        }
    }
}

TEST(BadMeshData, EmptyMeshesAreAnErrorNamingTheMesh) {
    const auto error = aerial::mesh::validate_mesh(Mesh{}, "dome");
    ASSERT_TRUE(error.has_value());
    EXPECT_EQ(error->field, "dome");
    EXPECT_NE(error->message.find("no faces"), std::string::npos) << error->message;
    Mesh vertices_only;
    vertices_only.add_vertex(Mesh::Point(0, 0, 0));
    vertices_only.add_vertex(Mesh::Point(1, 0, 0));
    EXPECT_TRUE(aerial::mesh::validate_mesh(vertices_only).has_value());
    EXPECT_FALSE(AdaptiveMesh::create(vertices_only, aerial::mesh::Surface{}, AdaptiveSettings{}));
    EXPECT_EQ(aerial::mesh::live_vertices(Mesh{}), 0u);
    EXPECT_EQ(aerial::mesh::live_faces(Mesh{}), 0u);
}

TEST(BadMeshData, DegenerateTrianglesRefineWithoutNansAndWithinTheBudget) {
    Mesh mesh = grid_with_degenerate_triangles(-200.0, 200.0);
    ASSERT_FALSE(aerial::mesh::validate_mesh(mesh).has_value());
    AdaptiveSettings settings;
    settings.split_lsb = 0.25f;  // split a lot
    settings.max_vertices = 300;
    settings.lock_boundary = false;
    settings.colour.display.exposure = 20.0f;
    auto made = AdaptiveMesh::create(mesh, aerial::mesh::Surface{}, settings);
    ASSERT_TRUE(made) << made.error().message;
    AdaptiveMesh adaptive = std::move(made).value();
    for (int frame = 0; frame < 40; ++frame) {
        const double a = 0.15 * frame;
        const auto stats =
            adaptive.update(frame_at({20.0 * std::cos(a), -300.0 + 10.0 * frame, 30.0},
                                     {std::cos(a), std::sin(a), 0.05 + 0.02 * frame}));
        ASSERT_LE(stats.vertices, settings.max_vertices) << "frame " << frame;
        ASSERT_TRUE(std::isfinite(stats.max_error_lsb)) << "frame " << frame;
        ASSERT_TRUE(well_formed(adaptive.mesh())) << "frame " << frame;
        for (auto f : adaptive.mesh().faces()) {
            if (adaptive.mesh().status(f).deleted()) continue;
            ASSERT_TRUE(std::isfinite(adaptive.face_error(f))) << "face " << f.idx();
        }
    }
    adaptive.compact();
    EXPECT_TRUE(well_formed(adaptive.mesh()));
}

TEST(BadMeshData, CoordinatesAt1e7MetresStayFiniteAndWithinTheBudget) {
    // 10 000 km from the origin (engines with one world frame for a planet): the eye is near the
    // mesh, so distances are small but the coordinates are large.
    const double x0 = 1e7, y0 = -1e7;
    Mesh mesh = grid_with_degenerate_triangles(x0, y0);
    AdaptiveSettings settings;
    settings.split_lsb = 0.5f;
    settings.max_vertices = 400;
    settings.colour.display.exposure = 20.0f;
    auto made = AdaptiveMesh::create(mesh, aerial::mesh::Surface{}, settings);
    ASSERT_TRUE(made) << made.error().message;
    AdaptiveMesh adaptive = std::move(made).value();
    for (int frame = 0; frame < 10; ++frame) {
        const auto stats = adaptive.update(frame_at({x0 + 200.0, y0 - 400.0 + 50.0 * frame, 20.0},
                                                    {0.3, 0.9, 0.1 + 0.05 * frame}));
        ASSERT_LE(stats.vertices, settings.max_vertices);
        ASSERT_TRUE(std::isfinite(stats.max_error_lsb));
        ASSERT_TRUE(well_formed(adaptive.mesh()));
    }
    // The batch path on the same coordinates: every colour finite and valid.
    const aerial::Frame<float> frame = frame_at({x0 + 200.0, y0 - 400.0, 20.0}, {0.3, 0.9, 0.2});
    std::vector<float> xyz;
    for (auto v : adaptive.mesh().vertices()) {
        const auto p = adaptive.mesh().point(v);
        xyz.insert(xyz.end(), {float(p[0]), float(p[1]), float(p[2])});
    }
    const std::size_t n = xyz.size() / 3;
    std::vector<float> fex(3 * n, -1.0f), lin(3 * n, -1.0f);
    aerial::BatchOutputs outputs;
    outputs.extinction_rgb = fex.data();
    outputs.in_scattering_rgb = lin.data();
    auto stats = aerial::shade_into(frame, aerial::Positions::aos(xyz.data(), n), outputs);
    ASSERT_TRUE(stats) << stats.error().message;
    EXPECT_EQ(stats->invalid_vertices, 0u);
    for (std::size_t i = 0; i < 3 * n; ++i) {
        ASSERT_TRUE(std::isfinite(fex[i]) && fex[i] >= 0.0f && fex[i] <= 1.0f) << i;
        ASSERT_TRUE(std::isfinite(lin[i]) && lin[i] >= 0.0f) << i;
    }
}

TEST(BadMeshData, ABudgetSmallerThanTheBaseMeshRefinesNothing) {
    auto base = aerial::mesh::geodesic_dome(6);
    ASSERT_TRUE(base);
    AdaptiveSettings settings;
    settings.max_vertices = 10;  // the base alone has 85
    settings.split_lsb = 0.1f;
    auto made = AdaptiveMesh::create(base.value(), aerial::mesh::Surface{}, settings);
    ASSERT_TRUE(made) << made.error().message;
    const auto stats = made.value().update(frame_at({0, 0, 2}, {0.5, 0.2, 0.1}));
    EXPECT_EQ(stats.splits, 0u);
    EXPECT_EQ(stats.vertices, aerial::mesh::live_vertices(base.value()));
    EXPECT_FALSE(stats.complete) << "the budget stopped refinement, and the stats say so";
}

TEST(BadBatchData, NonFiniteAndFarPositionsGiveNeutralColoursAndAreCounted) {
    const aerial::Frame<float> frame = frame_at({0, 0, 100}, {0.3, 0.8, 0.4});
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> xyz = {100, 2000,  50, nan, 0,    0,    0, inf, 0, -inf, 0,
                                    0,   3e12f, 0,  0,   1e7f, 1e7f, 0, 0,   0, 100};
    const std::size_t n = xyz.size() / 3;
    std::vector<std::uint8_t> fex(4 * n, 7), lin(4 * n, 7);
    aerial::BatchOutputs outputs;
    outputs.extinction_rgba8 = fex.data();
    outputs.in_scattering_rgba8 = lin.data();
    for (aerial::Kernel kernel :
         {aerial::Kernel::simd, aerial::Kernel::simd_fast, aerial::Kernel::scalar}) {
        aerial::BatchSettings settings;
        settings.kernel = kernel;
        auto stats =
            aerial::shade_into(frame, aerial::Positions::aos(xyz.data(), n), outputs, settings);
        ASSERT_TRUE(stats) << stats.error().message;
        EXPECT_EQ(stats->invalid_vertices, 4u) << "NaN, +Inf, -Inf and 3e12 m";
        for (std::size_t v : {1u, 2u, 3u, 4u}) {
            for (std::size_t c = 0; c < 3; ++c) {
                EXPECT_EQ(fex[4 * v + c], 255) << "vertex " << v << ": F_ex = 1";
                EXPECT_EQ(lin[4 * v + c], 0) << "vertex " << v << ": L_in = 0";
            }
        }
        // The valid ones (the eye itself and one 1.4e7 m away included) keep alpha 255.
        for (std::size_t v : {0u, 5u, 6u}) EXPECT_EQ(fex[4 * v + 3], 255) << v;
    }
}

TEST(BadBatchData, ARejectedCallLeavesTheCallersBuffersUntouched) {
    const aerial::Frame<float> frame = frame_at({0, 0, 100}, {0.3, 0.8, 0.4});
    const std::vector<float> xyz = {100, 2000, 50, 0, 500, 10};
    std::vector<std::uint8_t> fex(8, 7), lin(8, 9);
    aerial::BatchOutputs outputs;
    outputs.extinction_rgba8 = fex.data();
    outputs.in_scattering_rgba8 = lin.data();
    aerial::BatchSettings settings;
    settings.display.exposure = std::nanf("");
    auto rejected =
        aerial::shade_into(frame, aerial::Positions::aos(xyz.data(), 2), outputs, settings);
    ASSERT_FALSE(rejected);
    EXPECT_NE(rejected.error().message.find("exposure"), std::string::npos)
        << rejected.error().message;
    aerial::Positions null_positions;
    null_positions.count = 2;
    rejected = aerial::shade_into(frame, null_positions, outputs);
    ASSERT_FALSE(rejected);
    aerial::BatchOutputs lit_without_lighting;
    lit_without_lighting.lit_rgba8 = fex.data();
    lit_without_lighting.in_scattering_rgba8 = lin.data();
    rejected =
        aerial::shade_into(frame, aerial::Positions::aos(xyz.data(), 2), lit_without_lighting);
    ASSERT_FALSE(rejected);
    for (std::uint8_t b : fex) EXPECT_EQ(b, 7);
    for (std::uint8_t b : lin) EXPECT_EQ(b, 9);
    // An empty batch is fine and writes nothing.
    auto empty = aerial::shade_into(frame, aerial::Positions::aos(xyz.data(), 0), outputs);
    ASSERT_TRUE(empty) << empty.error().message;
    EXPECT_EQ(empty->vertices, 0u);
    for (std::uint8_t b : fex) EXPECT_EQ(b, 7);
}

}  // namespace
