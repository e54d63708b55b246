// aerial::mesh: the shapes, the colour error, adaptive bisection and coarsening, decimation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"
#include "aerial/validation/dense_error.hpp"
#include "frames.hpp"

namespace {

using aerial::mesh::AdaptiveMesh;
using aerial::mesh::AdaptiveSettings;
using aerial::mesh::Mesh;
using aerial_test::make_frame;
using aerial_test::sun_at;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

glm::dvec3 to_glm(const Mesh::Point& p) { return {p[0], p[1], p[2]}; }

// Calls fn(f, p) for every live face f, with p its three corners in the face's order.
template <class Fn>
void for_each_live_face(const Mesh& mesh, Fn&& fn) {
    for (auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        glm::dvec3 p[3];
        int k = 0;
        for (auto v : mesh.fv_range(f)) p[k++] = to_glm(mesh.point(v));
        fn(f, p);
    }
}

// The dome scene of the tests: eye 2 m above sea level, dome of 80 km, only L_in shown, exposure
// putting the sky 90 degrees from the sun at mid-grey.
struct DomeScene {
    aerial::mesh::DomeOptions dome;
    aerial::mesh::ColourOptions colour;
    aerial::Frame<float> frame;

    DomeScene(double sun_elevation_deg, double mie_g, double sun_azimuth_deg = 0.0)
        : frame(make_frame({0, 0, 2}, sun_at(sun_elevation_deg, sun_azimuth_deg), mie_g)) {
        dome.centre = {0, 0, 2};
        colour.texel = glm::vec3(0.0f);
        const glm::dvec3 side = dome.centre + dome.radius_m * sun_at(30.0, 90.0);
        const auto s = aerial::scatter(frame, glm::vec3(side));
        const float brightest = std::max({s.in_scattering.x, s.in_scattering.y, s.in_scattering.z});
        colour.display.exposure = 0.5f / brightest;
    }
};

AdaptiveSettings dome_settings(const DomeScene& scene) {
    AdaptiveSettings settings;
    settings.colour = scene.colour;
    settings.lock_boundary = false;
    return settings;
}

AdaptiveMesh refined_dome(const DomeScene& scene, const AdaptiveSettings& settings,
                          int frequency = 4) {
    auto base = aerial::mesh::geodesic_dome(frequency, scene.dome);
    EXPECT_TRUE(base.ok());
    auto adaptive =
        AdaptiveMesh::create(base.value(), aerial::mesh::Surface::sphere(scene.dome), settings);
    EXPECT_TRUE(adaptive.ok()) << adaptive.error().message;
    AdaptiveMesh m = std::move(adaptive).value();
    m.update(scene.frame);
    return m;
}

// Every live face's colour error, computed afresh through the public function.
float max_face_error(const Mesh& mesh, const aerial::Frame<float>& frame,
                     const aerial::mesh::ColourOptions& colour) {
    float worst = 0.0f;
    for_each_live_face(mesh, [&](Mesh::FaceHandle, const glm::dvec3* p) {
        glm::vec3 c[3];
        for (int i = 0; i < 3; ++i) c[i] = aerial::mesh::display_colour(frame, colour, p[i]);
        worst = std::max(
            worst, aerial::mesh::colour_error(frame, colour, p[0], p[1], p[2], c[0], c[1], c[2]));
    });
    return worst;
}

// Conforming and manifold: every vertex manifold, every edge with one or two faces, and the only
// boundary is where `on_border` says (a T-junction would open a crack inside).
template <class OnBorder>
void expect_conforming(const Mesh& mesh, OnBorder on_border) {
    for (auto v : mesh.vertices()) {
        if (mesh.status(v).deleted()) continue;
        EXPECT_TRUE(mesh.is_manifold(v)) << "vertex " << v.idx() << " is not manifold";
        if (mesh.is_boundary(v)) {
            EXPECT_TRUE(on_border(to_glm(mesh.point(v))))
                << "boundary vertex " << v.idx() << " is inside: a crack or a T-junction";
        }
    }
    for (auto e : mesh.edges()) {
        if (mesh.status(e).deleted()) continue;
        EXPECT_FALSE(mesh.is_boundary(mesh.halfedge_handle(e, 0)) &&
                     mesh.is_boundary(mesh.halfedge_handle(e, 1)))
            << "edge " << e.idx() << " has no face";
    }
}

// No face turned over: each face's normal points away from `outward_of` the face, or lies
// across it: a decimated dome may join three vertices of its horizon ring, a face in the eye's
// horizontal plane that the eye sees edge-on.
template <class Outward>
void expect_not_flipped(const Mesh& mesh, Outward outward) {
    for_each_live_face(mesh, [&](Mesh::FaceHandle f, const glm::dvec3* p) {
        const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        EXPECT_GE(glm::dot(n, outward((p[0] + p[1] + p[2]) / 3.0)), 0.0)
            << "face " << f.idx() << " is flipped";
        EXPECT_GT(glm::length(n), 0.0) << "face " << f.idx() << " has no area";
    });
}

std::vector<glm::dvec3> positions(const Mesh& mesh) {
    std::vector<glm::dvec3> out;
    for (auto v : mesh.vertices())
        if (!mesh.status(v).deleted()) out.push_back(to_glm(mesh.point(v)));
    return out;
}

/// Every vertex on the dome's sphere, and the base mesh's vertices (the first original.size()
/// handles) exactly where they were.
void expect_on_sphere_with_originals_unmoved(const Mesh& mesh,
                                             const aerial::mesh::DomeOptions& dome,
                                             const std::vector<glm::dvec3>& original) {
    for (auto v : mesh.vertices()) {
        const glm::dvec3 p = to_glm(mesh.point(v));
        EXPECT_NEAR(glm::length(p - dome.centre), dome.radius_m, 1e-6);
        if (std::size_t(v.idx()) < original.size()) {
            EXPECT_EQ(p, original[std::size_t(v.idx())])
                << "original vertex " << v.idx() << " moved";
        }
    }
}

TEST(MeshShapes, CountsOfTheDomesAndTheGrid) {
    for (int f : {1, 3, 8}) {
        auto dome = aerial::mesh::geodesic_dome(f);
        ASSERT_TRUE(dome.ok());
        EXPECT_EQ(dome->n_vertices(), std::size_t(2 * f * f + 2 * f + 1)) << "frequency " << f;
        EXPECT_EQ(dome->n_faces(), std::size_t(4 * f * f)) << "frequency " << f;
    }
    auto latlong = aerial::mesh::latlong_dome(5, 12);
    ASSERT_TRUE(latlong.ok());
    EXPECT_EQ(latlong->n_vertices(), std::size_t(5 * 12 + 1));
    auto grid = aerial::mesh::terrain_grid(aerial::mesh::rolling_hills(0, 0, 1000, 20, 300), 4, 3);
    ASSERT_TRUE(grid.ok());
    EXPECT_EQ(grid->n_vertices(), std::size_t(5 * 4));
    EXPECT_EQ(grid->n_faces(), std::size_t(2 * 4 * 3));
}

TEST(MeshShapes, DomesAreOnTheSphereFacingOutwardAndOpenOnlyAtTheHorizon) {
    aerial::mesh::DomeOptions dome;
    dome.centre = {10, -20, 5};
    dome.radius_m = 5000;
    for (auto made :
         {aerial::mesh::geodesic_dome(6, dome), aerial::mesh::latlong_dome(6, 16, dome)}) {
        ASSERT_TRUE(made.ok());
        for (const glm::dvec3& p : positions(made.value()))
            EXPECT_NEAR(glm::length(p - dome.centre), dome.radius_m, 1e-6);
        expect_conforming(made.value(), [&](const glm::dvec3& p) {
            return std::abs(p.z - dome.centre.z) < 1e-6;
        });
        expect_not_flipped(made.value(), [&](const glm::dvec3& c) { return c - dome.centre; });
    }
}

TEST(MeshShapes, BadSizesAndBadSurfacesAreNamed) {
    EXPECT_EQ(aerial::mesh::geodesic_dome(0).error().field, "frequency");
    EXPECT_EQ(aerial::mesh::geodesic_dome(0).error().message,
              "aerial::mesh::geodesic_dome(): frequency: expected 1 .. 2048, got 0");
    EXPECT_EQ(aerial::mesh::latlong_dome(4, 2).error().field, "segments");
    aerial::mesh::DomeOptions dome;
    dome.radius_m = -1;
    EXPECT_EQ(aerial::mesh::geodesic_dome(4, dome).error().field, "radius_m");
    auto field = aerial::mesh::rolling_hills(0, 0, 100, 1, 50);
    field.height_m = [](double x, double) { return x > 50 ? std::nan("") : 0.0; };
    const auto grid = aerial::mesh::terrain_grid(field, 4, 4);
    ASSERT_FALSE(grid.ok());
    EXPECT_EQ(grid.error().field, "height_m");
    EXPECT_EQ(grid.error().message.rfind("aerial::mesh::terrain_grid(): height_m: expected finite "
                                         "heights, got nan at (",
                                         0),
              0u)
        << grid.error().message;
}

TEST(ColourError, IsZeroWhereTheColourIsLinearAndGrowsWithTheTriangle) {
    const DomeScene scene(10.0, 0.76);
    const glm::dvec3 c = scene.dome.centre;
    auto error_of = [&](double size_deg) {
        const glm::dvec3 p[3] = {c + scene.dome.radius_m * sun_at(20, 80),
                                 c + scene.dome.radius_m * sun_at(20, 80 + size_deg),
                                 c + scene.dome.radius_m * sun_at(20 + size_deg, 80)};
        glm::vec3 col[3];
        for (int k = 0; k < 3; ++k)
            col[k] = aerial::mesh::display_colour(scene.frame, scene.colour, p[k]);
        return aerial::mesh::colour_error(scene.frame, scene.colour, p[0], p[1], p[2], col[0],
                                          col[1], col[2]);
    };
    EXPECT_LT(error_of(0.01), 0.05f);
    EXPECT_GT(error_of(20.0), error_of(5.0));
    EXPECT_GT(error_of(20.0), 1.0f) << "a 20 degree triangle of sky should show more than a step";
}

TEST(AdaptiveMesh, RefinedDomeMeetsTheTargetConformingAndUnflipped) {
    const DomeScene scene(10.0, 0.76);
    const AdaptiveSettings settings = dome_settings(scene);
    auto base = aerial::mesh::geodesic_dome(4, scene.dome);
    ASSERT_TRUE(base.ok());
    const std::vector<glm::dvec3> original = positions(base.value());
    AdaptiveMesh m = refined_dome(scene, settings);
    const Mesh& mesh = m.mesh();
    EXPECT_GT(aerial::mesh::live_vertices(mesh), original.size() * 2) << "nothing was refined";
    // The error target, recomputed from scratch on every face.
    EXPECT_LE(max_face_error(mesh, scene.frame, settings.colour), settings.split_lsb);
    // New vertices on the sphere, originals where they were.
    expect_on_sphere_with_originals_unmoved(mesh, scene.dome, original);
    expect_conforming(mesh, [&](const glm::dvec3& p) {
        return std::abs(p.z - scene.dome.centre.z) < 1e-6 * scene.dome.radius_m;
    });
    expect_not_flipped(mesh, [&](const glm::dvec3& c) { return c - scene.dome.centre; });
    // The independent dense measure agrees within the estimate's sampling.
    const auto dense = aerial::validation::dense_error(mesh, scene.frame, settings.colour, 0.01);
    ASSERT_TRUE(dense.ok());
    EXPECT_LT(dense->max_lsb, 2.0 * settings.split_lsb);
}

TEST(AdaptiveMesh, IsDeterministic) {
    const DomeScene scene(2.0, 0.9);
    const AdaptiveSettings settings = dome_settings(scene);
    const auto a = positions(refined_dome(scene, settings).mesh());
    const auto b = positions(refined_dome(scene, settings).mesh());
    ASSERT_EQ(a.size(), b.size());
    EXPECT_TRUE(a == b) << "two runs of the same input gave different meshes";
}

TEST(AdaptiveMesh, StopsAtTheVertexBudget) {
    const DomeScene scene(2.0, 0.9);
    AdaptiveSettings settings = dome_settings(scene);
    settings.max_vertices = 200;
    AdaptiveMesh m = refined_dome(scene, settings);
    EXPECT_LE(aerial::mesh::live_vertices(m.mesh()), 200u);
    const auto stats = m.update(scene.frame);
    EXPECT_FALSE(stats.complete);
    EXPECT_GT(stats.max_error_lsb, settings.split_lsb);
}

TEST(AdaptiveMesh, CoarsensWhenTheSunMovesAwayAndDoesNotOscillate) {
    const DomeScene low(5.0, 0.9);
    AdaptiveSettings settings = dome_settings(low);
    AdaptiveMesh m = refined_dome(low, settings);
    const std::size_t at_low = aerial::mesh::live_vertices(m.mesh());
    // Sun moved high and to the other side: the refinement around the old sun folds back.
    DomeScene high(60.0, 0.9, 180.0);
    high.colour = low.colour;
    const auto moved = m.update(high.frame);
    EXPECT_GT(moved.merges, 0u);
    EXPECT_LE(max_face_error(m.mesh(), high.frame, settings.colour), settings.split_lsb);
    // The same frame again changes nothing.
    const auto again = m.update(high.frame);
    EXPECT_EQ(again.splits, 0u);
    EXPECT_EQ(again.merges, 0u);
    // Alternating between two sun positions 0.14 degrees apart settles: after the first round trip
    // no update splits or merges (hysteresis).
    DomeScene nudged(60.1, 0.9, 180.1);
    nudged.colour = low.colour;
    for (int i = 0; i < 2; ++i) {
        m.update(nudged.frame);
        m.update(high.frame);
    }
    const auto a = m.update(nudged.frame);
    const auto b = m.update(high.frame);
    EXPECT_EQ(a.splits + a.merges + b.splits + b.merges, 0u) << "the mesh oscillates";
    EXPECT_NE(aerial::mesh::live_vertices(m.mesh()), at_low);
    m.compact();
    EXPECT_EQ(m.mesh().n_vertices(), aerial::mesh::live_vertices(m.mesh()));
    const auto after_compact = m.update(high.frame);
    EXPECT_EQ(after_compact.splits + after_compact.merges, 0u);
}

struct TerrainScene {
    // 20 km of hills in haze, where aerial perspective is strong.
    aerial::mesh::Heightfield field = aerial::mesh::rolling_hills(-10000, -10000, 20000, 100, 3000);
    aerial::mesh::ColourOptions colour;
    TerrainScene() {
        colour.texel = glm::vec3(0.8f);
        colour.display.exposure = 2.0f;
    }
    aerial::Frame<float> frame(const glm::dvec3& eye) const {
        return make_frame(eye, sun_at(10.0), 0.76, "hazy");
    }
};

TEST(AdaptiveMesh, TerrainKeepsLockedBordersAndUpdatesOnlyWhereTheViewChanged) {
    const TerrainScene scene;
    auto base = aerial::mesh::terrain_grid(scene.field, 16, 16);
    ASSERT_TRUE(base.ok());
    std::vector<glm::dvec3> border;
    for (auto v : base->vertices())
        if (base->is_boundary(v)) border.push_back(to_glm(base->point(v)));
    AdaptiveSettings settings;
    settings.colour = scene.colour;
    settings.lock_boundary = true;
    // The longest-edge rule: its mesh is as fine away from the eye as near it, so the faces near
    // the eye are under half of it (the colour-edge mesh is coarser away from the eye).
    settings.colour_edge = false;
    auto made =
        AdaptiveMesh::create(base.value(), aerial::mesh::Surface::terrain(scene.field), settings);
    ASSERT_TRUE(made.ok()) << made.error().message;
    AdaptiveMesh m = std::move(made).value();
    const glm::dvec3 eye{0, 0, scene.field.height_m(0, 0) + 2};
    const auto frame = scene.frame(eye);
    const auto first = m.update(frame);
    EXPECT_GT(first.splits, 0u);
    const Mesh& mesh = m.mesh();
    std::vector<glm::dvec3> border_after;
    for (auto v : mesh.vertices())
        if (!mesh.status(v).deleted() && mesh.is_boundary(v))
            border_after.push_back(to_glm(mesh.point(v)));
    EXPECT_TRUE(border == border_after) << "the locked border changed";
    for (auto v : mesh.vertices()) {
        const glm::dvec3 p = to_glm(mesh.point(v));
        EXPECT_NEAR(p.z, scene.field.height_m(p.x, p.y), 1e-9) << "vertex off the heightfield";
    }
    expect_conforming(mesh, [](const glm::dvec3& p) {
        return std::abs(std::abs(p.x) - 10000) < 1e-6 || std::abs(std::abs(p.y) - 10000) < 1e-6;
    });
    expect_not_flipped(mesh, [](const glm::dvec3&) { return glm::dvec3(0, 0, 1); });
    // A step of 30 m re-estimates only the faces near the eye (closer than 1.5 km at 2 %).
    const auto moved = m.update(scene.frame(eye + glm::dvec3(30, 0, 0)));
    EXPECT_GT(moved.faces_estimated, 0u);
    EXPECT_LT(moved.faces_estimated, aerial::mesh::live_faces(mesh) / 2);
}

// Without a time slice the sweep visits only the faces its index says can be stale; with a slice
// too long to run out it visits every face. Both must re-estimate, split and merge the same.
TEST(AdaptiveMesh, IndexedSweepReEstimatesExactlyTheFacesTheFullSweepDoes) {
    const TerrainScene scene;
    auto base = aerial::mesh::terrain_grid(scene.field, 16, 16);
    ASSERT_TRUE(base.ok());
    for (const std::size_t budget : {std::size_t(6000), std::size_t(700)}) {
        AdaptiveSettings settings;
        settings.colour = scene.colour;
        settings.lock_boundary = true;  // faces above the target that stay: the heap's other source
        settings.max_vertices = budget;
        AdaptiveSettings full_settings = settings;
        full_settings.indexed_sweep = false;
        const auto surface = aerial::mesh::Surface::terrain(scene.field);
        AdaptiveMesh indexed = AdaptiveMesh::create(base.value(), surface, settings).value();
        AdaptiveMesh full = AdaptiveMesh::create(base.value(), surface, full_settings).value();
        // The index under a time slice it never runs out of: the same as without one.
        AdaptiveSettings sliced_settings = settings;
        sliced_settings.time_slice_ms = 1e9;
        AdaptiveMesh sliced = AdaptiveMesh::create(base.value(), surface, sliced_settings).value();
        std::size_t merges = 0, partial = 0;
        for (int i = 0; i < 40; ++i) {
            // Out and back along x, with the sun turning in steps both below and above 0.002 rad.
            const double x = 60.0 * (i < 20 ? i : 40 - i);
            const glm::dvec3 eye{x, 0.3 * x, scene.field.height_m(x, 0.3 * x) + 2 + (i % 3)};
            const double azimuth = (i / 5) * 0.3 + (i % 2) * 0.05;
            const auto frame =
                make_frame(eye, sun_at(10.0 + 0.05 * (i % 4), azimuth), 0.76, "hazy");
            if (i == 25) {
                indexed.compact();
                full.compact();
                sliced.compact();
            }
            if (i == 32) {
                indexed.invalidate();
                full.invalidate();
                sliced.invalidate();
            }
            const auto a = indexed.update(frame);
            const auto b = full.update(frame);
            const auto c = sliced.update(frame);
            ASSERT_EQ(c.faces_estimated, b.faces_estimated) << "sliced, update " << i;
            ASSERT_EQ(c.splits + c.merges, b.splits + b.merges) << "sliced, update " << i;
            ASSERT_EQ(c.max_error_lsb, b.max_error_lsb) << "sliced, update " << i;
            ASSERT_EQ(a.faces_estimated, b.faces_estimated) << "update " << i;
            ASSERT_EQ(a.splits, b.splits) << "update " << i;
            ASSERT_EQ(a.merges, b.merges) << "update " << i;
            ASSERT_EQ(a.vertices, b.vertices) << "update " << i;
            ASSERT_EQ(a.faces, b.faces) << "update " << i;
            ASSERT_EQ(a.complete, b.complete) << "update " << i;
            ASSERT_EQ(a.max_error_lsb, b.max_error_lsb) << "update " << i;
            if (i > 0 && a.faces_estimated < a.faces) ++partial;
            merges += a.merges;
        }
        EXPECT_GT(partial, 10u) << "the sequence never left faces fresh";
        EXPECT_GT(merges, 0u) << "the sequence never coarsened";
        ASSERT_TRUE(positions(indexed.mesh()) == positions(full.mesh()));
        for (auto f : indexed.mesh().faces())
            ASSERT_EQ(indexed.face_error(f), full.face_error(f)) << "face " << f.idx();
    }
}

TEST(AdaptiveMesh, BadInputIsAnErrorNamingIt) {
    auto base = aerial::mesh::geodesic_dome(2);
    ASSERT_TRUE(base.ok());
    Mesh nan_mesh = base.value();
    nan_mesh.set_point(Mesh::VertexHandle(3), Mesh::Point(std::nan(""), 0, 0));
    auto made = AdaptiveMesh::create(nan_mesh, aerial::mesh::Surface{}, AdaptiveSettings{});
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().field, "base");
    // The one message style, pinned whole: the function the caller called (create, not the
    // validate_mesh it calls), the field, expected and got.
    EXPECT_EQ(made.error().message,
              "aerial::mesh::AdaptiveMesh::create(): base: expected finite positions, got (nan, 0, "
              "0) at vertex 3");
    made = AdaptiveMesh::create(Mesh{}, aerial::mesh::Surface{}, AdaptiveSettings{});
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().message, "aerial::mesh::AdaptiveMesh::create(): base: has no faces");
    AdaptiveSettings bad;
    bad.merge_ratio = 0.5f;
    made = AdaptiveMesh::create(base.value(), aerial::mesh::Surface{}, bad);
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().field, "merge_ratio");
    EXPECT_EQ(made.error().message,
              "aerial::mesh::AdaptiveMesh::create(): merge_ratio: expected a finite value >= 1, "
              "got 0.5");
    EXPECT_EQ(aerial::mesh::validate(bad)->message,
              "aerial::mesh::validate(): merge_ratio: expected a finite value >= 1, got 0.5");
    bad = AdaptiveSettings{};
    bad.colour.display.exposure = 0.0f;
    EXPECT_EQ(AdaptiveMesh::create(base.value(), aerial::mesh::Surface{}, bad).error().field,
              "exposure");
    aerial::mesh::Surface sphere;
    sphere.kind = aerial::mesh::Surface::Kind::sphere;
    sphere.radius_m = 0.0;
    EXPECT_EQ(AdaptiveMesh::create(base.value(), sphere, AdaptiveSettings{}).error().field,
              "surface");
}

TEST(Decimate, RemovesVerticesKeepsTheBorderAndStaysUnderTheBound) {
    // A mesh that meets 2 steps everywhere, decimated to 4 steps.
    DomeScene scene(30.0, 0.76);
    scene.colour.max_samples_per_edge = 4;
    AdaptiveSettings settings = dome_settings(scene);
    settings.split_lsb = 2.0f;
    const Mesh fine = refined_dome(scene, settings, 8).mesh();
    ASSERT_LE(max_face_error(fine, scene.frame, scene.colour), 2.0f);
    aerial::mesh::DecimateOptions options;
    options.colour = scene.colour;
    options.max_lsb = 4.0f;
    auto decimated = aerial::mesh::decimate(fine, scene.frame, options);
    ASSERT_TRUE(decimated.ok()) << decimated.error().message;
    EXPECT_LT(decimated->n_vertices(), aerial::mesh::live_vertices(fine) * 3 / 4);
    std::size_t border = 0, border_after = 0;
    for (auto v : fine.vertices())
        border += !fine.status(v).deleted() && fine.is_boundary(v) ? 1 : 0;
    for (auto v : decimated->vertices()) border_after += decimated->is_boundary(v) ? 1 : 0;
    EXPECT_EQ(border, border_after);
    EXPECT_LE(max_face_error(decimated.value(), scene.frame, options.colour), options.max_lsb);
    expect_not_flipped(decimated.value(),
                       [&](const glm::dvec3& c) { return c - scene.dome.centre; });
    Mesh empty;
    EXPECT_EQ(aerial::mesh::decimate(empty, scene.frame, options).error().message,
              "aerial::mesh::decimate(): mesh: has no faces");
}

}  // namespace

// ---- Morphing, distance level of detail --------------------------------

namespace {

// What the screen shows at each vertex (8-bit steps, any vertex handle), morphed.
std::vector<float> shown_lsb(const AdaptiveMesh& m, const aerial::Frame<float>& frame,
                             const aerial::mesh::ColourOptions& colour) {
    const Mesh& mesh = m.mesh();
    std::vector<float> out(3 * mesh.n_vertices(), 0.0f);
    for (auto v : mesh.vertices()) {
        if (mesh.status(v).deleted()) continue;
        const glm::vec3 c = aerial::mesh::display_colour(frame, colour, to_glm(mesh.point(v)));
        for (int k = 0; k < 3; ++k) out[3 * std::size_t(v.idx()) + std::size_t(k)] = 255.0f * c[k];
    }
    m.morph_into(out.data(), 3, 3);
    return out;
}

float distance3(const float* a, const float* b) {
    float d = 0.0f;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(a[k] - b[k]));
    return d;
}

// The largest jump of the colour shown at a vertex's place from one update to the next, while
// the sun stands still after one big move: when a vertex is born (against the mean of its parent
// edge, what the screen showed there), while it morphs, and when coarsening removes it (its last
// colour against its parents' mean).
struct Pops {
    float largest = 0.0f;
    float birth_gap = 0.0f;  ///< largest |own colour - what the screen showed there| at a birth
    std::size_t births = 0, removals = 0;
    std::size_t vertices_after_move = 0, vertices_at_end = 0;
    float settled_error = 0.0f;  ///< at the end: |shown - exact| over live vertices
};

// `quantized_relocating`: the estimate aerial-tess grades domes with (8-bit vertex colours,
// samples on the sphere) and AdaptiveSettings::relocate, at 2 steps.
Pops sun_move_pops(int morph_updates, bool quantized_relocating = false) {
    const DomeScene low(5.0, 0.9);
    AdaptiveSettings settings = dome_settings(low);
    if (quantized_relocating) {
        settings.colour.quantized_vertices = true;
        settings.colour.on_dome_sphere = true;
        settings.colour.dome = low.dome;
        settings.relocate = true;
        settings.split_lsb = 2.0f;  // a smaller mesh: relocation tries up to 48 positions a vertex
    }
    settings.morph_updates = morph_updates;
    settings.compact_garbage_ratio = 0.0f;  // vertices are followed by handle across updates
    AdaptiveMesh m = refined_dome(low, settings);
    for (int i = 0; i <= morph_updates; ++i) m.update(low.frame);
    DomeScene high(60.0, 0.9, 180.0);
    high.colour = low.colour;
    Pops pops;
    std::vector<float> previous = shown_lsb(m, low.frame, low.colour);
    int quiet = 0;  // updates in a row without splits or merges
    for (int t = 1; t <= 400 && quiet <= morph_updates + 1; ++t) {
        const Mesh& mesh = m.mesh();
        std::vector<char> alive(mesh.n_vertices());
        for (auto v : mesh.vertices()) alive[std::size_t(v.idx())] = !mesh.status(v).deleted();
        const auto stats = m.update(high.frame);
        quiet = stats.splits + stats.merges == 0 ? quiet + 1 : 0;
        if (t == 1) pops.vertices_after_move = aerial::mesh::live_vertices(mesh);
        const std::vector<float> now = shown_lsb(m, high.frame, high.colour);
        auto at = [](const std::vector<float>& c, OpenMesh::VertexHandle v) {
            return &c[3 * std::size_t(v.idx())];
        };
        // What the screen showed at each new vertex before its split in this frame: the mean of
        // its parents' such values (new vertices come in the order of the splits, parents first).
        std::vector<float> before = now;
        for (auto v : mesh.vertices()) {
            const bool new_vertex = std::size_t(v.idx()) >= alive.size();
            if (!new_vertex || mesh.status(v).deleted()) continue;
            const auto [a, b] = m.parents(v);
            for (int k = 0; k < 3; ++k) {
                before[3 * std::size_t(v.idx()) + std::size_t(k)] =
                    0.5f * (at(before, a)[k] + at(before, b)[k]);
            }
            const glm::vec3 own = 255.0f * aerial::mesh::display_colour(high.frame, high.colour,
                                                                        to_glm(mesh.point(v)));
            pops.birth_gap = std::max(pops.birth_gap, distance3(&own[0], at(before, v)));
        }
        for (std::size_t i = 0; i < mesh.n_vertices(); ++i) {  // vertices() skips deleted ones
            const auto v = OpenMesh::VertexHandle(int(i));
            const bool was = std::size_t(v.idx()) < alive.size() && alive[std::size_t(v.idx())];
            const bool is = !mesh.status(v).deleted();
            // Not a structured binding: a lambda may not capture one in C++17 (clang rejects it).
            const auto parents = m.parents(v);
            const auto a = parents.first, b = parents.second;
            auto parents_mean = [&](const std::vector<float>& c, float* mean) {
                for (int k = 0; k < 3; ++k) mean[k] = 0.5f * (at(c, a)[k] + at(c, b)[k]);
            };
            float mean[3];
            if (is && !was) {
                pops.largest = std::max(pops.largest, distance3(at(now, v), at(before, v)));
                ++pops.births;
            } else if (was && !is && t >= 2 && !mesh.status(a).deleted() &&
                       !mesh.status(b).deleted()) {
                parents_mean(now, mean);
                pops.largest = std::max(pops.largest, distance3(at(previous, v), mean));
                ++pops.removals;
            } else if (was && is && t >= 2) {
                pops.largest = std::max(pops.largest, distance3(at(now, v), at(previous, v)));
            }
        }
        previous = now;
    }
    pops.vertices_at_end = aerial::mesh::live_vertices(m.mesh());
    for (auto v : m.mesh().vertices()) {
        if (m.mesh().status(v).deleted()) continue;
        const glm::vec3 c = 255.0f * aerial::mesh::display_colour(high.frame, high.colour,
                                                                  to_glm(m.mesh().point(v)));
        pops.settled_error =
            std::max(pops.settled_error, distance3(&previous[3 * std::size_t(v.idx())], &c[0]));
    }
    return pops;
}

}  // namespace

TEST(AdaptiveMesh, MorphingBlendsNewVerticesInAndFadesRemovedOnesOutWithoutPops) {
    const Pops instant = sun_move_pops(0);
    ASSERT_GT(instant.births, 0u) << "the sun move refined nothing";
    ASSERT_GT(instant.largest, 2.0f) << "without morphing nothing popped: the test shows nothing";
    constexpr int kUpdates = 8;
    const Pops morphed = sun_move_pops(kUpdates);
    EXPECT_GT(morphed.births, 0u);
    EXPECT_GT(morphed.removals, 0u) << "no faded vertex was removed";
    // A new vertex starts where its parent edge was and moves 1/8 of the way per update; a chain
    // of new vertices moves with its parents, so allow a quarter of the pop without morphing.
    EXPECT_LE(morphed.largest, instant.largest / 4.0f)
        << "largest change at a vertex per update: " << morphed.largest << " LSB morphed, "
        << instant.largest << " LSB at once";
    // Births move 1 / kUpdates of their gap per update.
    EXPECT_LE(morphed.largest, 1.01f * morphed.birth_gap / kUpdates + 0.01f)
        << "birth gap " << morphed.birth_gap;
    std::printf(
        "morph: largest change per update %.2f LSB (at once %.2f), birth gap %.2f, "
        "vertices after the move %zu / %zu, at the end %zu / %zu\n",
        morphed.largest, instant.largest, morphed.birth_gap, morphed.vertices_after_move,
        instant.vertices_after_move, morphed.vertices_at_end, instant.vertices_at_end);
    EXPECT_LT(morphed.vertices_at_end, morphed.vertices_after_move) << "coarsening never ended";
    EXPECT_LE(morphed.settled_error, 1e-3f) << "morphs did not finish";
    EXPECT_LE(instant.settled_error, 1e-3f);
}

TEST(MeshShapes, DistanceLodIsAConformingGridDenserNearTheEye) {
    const auto field = aerial::mesh::rolling_hills(-10000, -10000, 20000, 100, 3000);
    const glm::dvec2 eye{2500.0, -4000.0};
    auto lod = aerial::mesh::terrain_distance_lod(field, 32, eye, 2.0);
    ASSERT_TRUE(lod.ok()) << lod.error().message;
    EXPECT_EQ(lod->n_vertices(), std::size_t(33 * 33));
    EXPECT_EQ(lod->n_faces(), std::size_t(2 * 32 * 32));
    auto on_border = [](const glm::dvec3& p) {
        return std::abs(std::abs(p.x) - 10000.0) < 1e-6 || std::abs(std::abs(p.y) - 10000.0) < 1e-6;
    };
    expect_conforming(lod.value(), on_border);
    expect_not_flipped(lod.value(), [](const glm::dvec3&) { return glm::dvec3(0, 0, 1); });
    // Edge lengths (in the plane) against distance from the eye: short near, long far.
    double near_longest = 0.0, far_shortest = 1e30;
    for (auto e : lod->edges()) {
        const auto h = lod->halfedge_handle(e, 0);
        const glm::dvec3 a = to_glm(lod->point(lod->from_vertex_handle(h)));
        const glm::dvec3 b = to_glm(lod->point(lod->to_vertex_handle(h)));
        const double length = glm::length(glm::dvec2(a - b));
        const double distance = glm::length(glm::dvec2(0.5 * (a + b)) - eye);
        if (distance < 200.0) near_longest = std::max(near_longest, length);
        if (distance > 9000.0) far_shortest = std::min(far_shortest, length);
        EXPECT_GE(a.x, -10000.0 - 1e-6);
        EXPECT_LE(a.x, 10000.0 + 1e-6);
    }
    const double uniform = 20000.0 / 32.0;
    EXPECT_LT(near_longest, 0.4 * uniform);
    EXPECT_GT(far_shortest, 0.5 * uniform);
    EXPECT_GT(far_shortest, 2.0 * near_longest);
    // Exponent 1 is the uniform grid; bad input is named.
    auto grid = aerial::mesh::terrain_grid(field, 8, 8);
    auto flat = aerial::mesh::terrain_distance_lod(field, 8, eye, 1.0);
    ASSERT_TRUE(flat.ok());
    for (auto v : grid->vertices())
        EXPECT_LT(glm::length(to_glm(grid->point(v)) - to_glm(flat->point(v))), 1e-6);
    auto bad = aerial::mesh::terrain_distance_lod(field, 8, eye, 0.5);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().field, "exponent");
    auto nan_eye = aerial::mesh::terrain_distance_lod(field, 8, {std::nan(""), 0.0}, 2.0);
    ASSERT_FALSE(nan_eye.ok());
    EXPECT_EQ(nan_eye.error().field, "eye_xy");
}

TEST(ColourError, QuantizedVerticesMeasureTheColoursAsDrawnInEightBits) {
    const DomeScene scene(10.0, 0.90);
    aerial::mesh::ColourOptions quantized = scene.colour;
    quantized.quantized_vertices = true;
    quantized.max_samples_per_edge = 2;  // edge midpoints and the centroid
    // A triangle far smaller than a colour step: the float error is ~0, the quantized one is the
    // vertices' rounding, interpolated to the samples.
    const glm::dvec3 c = scene.dome.centre;
    const glm::dvec3 p[3] = {c + scene.dome.radius_m * sun_at(20, 80),
                             c + scene.dome.radius_m * sun_at(20, 80.001),
                             c + scene.dome.radius_m * sun_at(20.001, 80)};
    glm::vec3 col[3], offset[3];
    for (int k = 0; k < 3; ++k) {
        col[k] = aerial::mesh::display_colour(scene.frame, scene.colour, p[k]);
        offset[k] = 255.0f * (glm::round(col[k] * 255.0f) / 255.0f - col[k]);
    }
    float expected = 0.0f;
    const float w[4][3] = {
        {0.5f, 0.5f, 0.0f}, {0.0f, 0.5f, 0.5f}, {0.5f, 0.0f, 0.5f}, {1.0f / 3, 1.0f / 3, 1.0f / 3}};
    for (const auto& s : w) {
        const glm::vec3 e = glm::abs(s[0] * offset[0] + s[1] * offset[1] + s[2] * offset[2]);
        expected = std::max({expected, e.x, e.y, e.z});
    }
    const float float_error = aerial::mesh::colour_error(scene.frame, scene.colour, p[0], p[1],
                                                         p[2], col[0], col[1], col[2]);
    const float quantized_error = aerial::mesh::colour_error(scene.frame, quantized, p[0], p[1],
                                                             p[2], col[0], col[1], col[2]);
    EXPECT_LT(float_error, 0.01f);
    EXPECT_NEAR(quantized_error, expected, 0.01f);
    EXPECT_GT(quantized_error, 0.05f) << "the rounding of three vertices should show";
    EXPECT_LE(quantized_error, 0.51f);
    // Below half a step the target cannot be met with 8-bit vertex colours: an error.
    AdaptiveSettings settings = dome_settings(scene);
    settings.colour.quantized_vertices = true;
    settings.split_lsb = 0.5f;
    auto base = aerial::mesh::geodesic_dome(4, scene.dome);
    ASSERT_TRUE(base.ok());
    auto made =
        AdaptiveMesh::create(base.value(), aerial::mesh::Surface::sphere(scene.dome), settings);
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().field, "split_lsb");
    // Above it, refinement meets the quantized target on every face.
    settings.split_lsb = 1.0f;
    AdaptiveMesh m = refined_dome(scene, settings);
    EXPECT_LE(max_face_error(m.mesh(), scene.frame, settings.colour), settings.split_lsb);
}

TEST(ColourError, OnDomeSphereTakesTheExactColourWhereTheViewRayMeetsTheDome) {
    const DomeScene scene(10.0, 0.90);
    aerial::mesh::ColourOptions on_sphere = scene.colour;
    on_sphere.on_dome_sphere = true;
    on_sphere.dome = scene.dome;
    // A tiny triangle at half the dome's radius, low in the sky, showing the colours of the
    // dome behind it: exact on the sphere, several steps off at 40 km.
    const glm::dvec3 c = scene.dome.centre;
    const glm::dvec3 d[3] = {sun_at(5, 80), sun_at(5, 80.001), sun_at(5.001, 80)};
    glm::dvec3 p[3];
    glm::vec3 col[3];
    for (int k = 0; k < 3; ++k) {
        p[k] = c + 0.5 * scene.dome.radius_m * d[k];
        col[k] =
            aerial::mesh::display_colour(scene.frame, scene.colour, c + scene.dome.radius_m * d[k]);
    }
    EXPECT_LT(aerial::mesh::colour_error(scene.frame, on_sphere, p[0], p[1], p[2], col[0], col[1],
                                         col[2]),
              0.05f);
    EXPECT_GT(aerial::mesh::colour_error(scene.frame, scene.colour, p[0], p[1], p[2], col[0],
                                         col[1], col[2]),
              2.0f);
}

// The smallest angle (degrees) over the live faces.
double smallest_angle_deg(const Mesh& mesh) {
    double smallest = 180.0;
    for_each_live_face(mesh, [&](Mesh::FaceHandle, const glm::dvec3* p) {
        for (int i = 0; i < 3; ++i) {
            const glm::dvec3 a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
            smallest = std::min(
                smallest, std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) / kDegree);
        }
    });
    return smallest;
}

// Starting each bisection path from the edge with the largest midpoint error (within the angle
// bound) keeps every guarantee of the longest-edge rule, keeps the shape, and needs fewer
// vertices for the same target on the g = 0.9 dome.
TEST(AdaptiveMesh, ColourEdgeChoiceKeepsTheGuaranteesAndTheShape) {
    for (double sun : {2.0, 10.0, 30.0}) {
        SCOPED_TRACE(sun);
        const DomeScene scene(sun, 0.9);
        AdaptiveSettings longest = dome_settings(scene);
        longest.colour.quantized_vertices = true;
        longest.colour.on_dome_sphere = true;
        longest.colour.dome = scene.dome;
        longest.colour_edge = false;
        AdaptiveSettings settings = longest;
        settings.colour_edge = true;
        AdaptiveMesh m = refined_dome(scene, settings);
        const Mesh& mesh = m.mesh();
        const auto again = m.update(scene.frame);
        EXPECT_TRUE(again.complete);
        EXPECT_LE(again.max_error_lsb, settings.split_lsb);
        EXPECT_LE(max_face_error(mesh, scene.frame, settings.colour), settings.split_lsb);
        for (auto v : mesh.vertices()) {
            if (!mesh.status(v).deleted()) {
                EXPECT_NEAR(glm::length(to_glm(mesh.point(v)) - scene.dome.centre),
                            scene.dome.radius_m, 1e-6);
            }
        }
        expect_conforming(mesh, [&](const glm::dvec3& p) {
            return std::abs(p.z - scene.dome.centre.z) < 1e-6 * scene.dome.radius_m;
        });
        expect_not_flipped(mesh, [&](const glm::dvec3& c) { return c - scene.dome.centre; });
        const std::size_t colour_count = aerial::mesh::live_vertices(mesh);
        const std::size_t longest_count =
            aerial::mesh::live_vertices(refined_dome(scene, longest).mesh());
        const double angle = smallest_angle_deg(mesh);
        std::printf("sun %g deg: %zu vertices (longest edge %zu), smallest angle %.1f deg\n", sun,
                    colour_count, longest_count, angle);
        EXPECT_LT(colour_count, longest_count);
        EXPECT_GE(angle, 0.5 * double(settings.colour_edge_min_angle_deg));
        EXPECT_TRUE(positions(mesh) == positions(refined_dome(scene, settings).mesh()))
            << "two runs of the same input gave different meshes";
    }
    const DomeScene scene(2.0, 0.9);
    AdaptiveSettings settings = dome_settings(scene);
    settings.colour_edge = true;
    settings.max_vertices = 200;
    AdaptiveMesh m = refined_dome(scene, settings);
    EXPECT_LE(aerial::mesh::live_vertices(m.mesh()), 200u);
    EXPECT_FALSE(m.update(scene.frame).complete);
    settings.colour_edge_min_angle_deg = 61.0f;
    auto base = aerial::mesh::geodesic_dome(4, scene.dome);
    ASSERT_TRUE(base.ok());
    const auto bad =
        AdaptiveMesh::create(base.value(), aerial::mesh::Surface::sphere(scene.dome), settings);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().field, "colour_edge_min_angle_deg");
}

// Relocation (AdaptiveSettings::relocate) moves new vertices within their one-ring: every
// guarantee of the refinement still holds, and it needs fewer vertices for the same target.
TEST(AdaptiveMesh, RelocationKeepsTheGuaranteesAndNeedsFewerVertices) {
    const DomeScene scene(10.0, 0.9);
    AdaptiveSettings settings = dome_settings(scene);
    settings.colour.quantized_vertices = true;
    settings.colour.on_dome_sphere = true;
    settings.colour.dome = scene.dome;
    settings.split_lsb = 2.0f;  // a smaller mesh: relocation tries up to 48 positions a vertex
    AdaptiveSettings fixed = settings;
    settings.relocate = true;
    auto base = aerial::mesh::geodesic_dome(4, scene.dome);
    ASSERT_TRUE(base.ok());
    const std::vector<glm::dvec3> original = positions(base.value());
    auto made =
        AdaptiveMesh::create(base.value(), aerial::mesh::Surface::sphere(scene.dome), settings);
    ASSERT_TRUE(made.ok()) << made.error().message;
    AdaptiveMesh m = std::move(made).value();
    const auto first = m.update(scene.frame);
    const Mesh& mesh = m.mesh();
    // Vertices off their split edge's projected midpoint (a vertex moves only when it is born).
    const auto sphere = aerial::mesh::Surface::sphere(scene.dome);
    expect_on_sphere_with_originals_unmoved(mesh, scene.dome, original);
    std::size_t moved = 0;
    for (auto v : mesh.vertices()) {
        if (std::size_t(v.idx()) < original.size()) continue;
        const glm::dvec3 p = to_glm(mesh.point(v));
        const auto [a, b] = m.parents(v);
        const glm::dvec3 mid =
            sphere.project(0.5 * (to_glm(mesh.point(a)) + to_glm(mesh.point(b))));
        if (glm::length(p - mid) > 1e-6 * scene.dome.radius_m) ++moved;
        if (mesh.is_boundary(v)) {
            EXPECT_LT(glm::length(p - mid), 1e-6 * scene.dome.radius_m);
        }
    }
    EXPECT_GT(moved, 0u) << "no vertex was relocated";
    EXPECT_LE(moved, first.relocated);
    // The target, recomputed from scratch on every face, and a second update changes nothing.
    EXPECT_LE(max_face_error(mesh, scene.frame, settings.colour), settings.split_lsb);
    const auto again = m.update(scene.frame);
    EXPECT_TRUE(again.complete);
    EXPECT_EQ(again.splits + again.merges, 0u);
    EXPECT_LE(again.max_error_lsb, settings.split_lsb);
    expect_conforming(mesh, [&](const glm::dvec3& p) {
        return std::abs(p.z - scene.dome.centre.z) < 1e-6 * scene.dome.radius_m;
    });
    expect_not_flipped(mesh, [&](const glm::dvec3& c) { return c - scene.dome.centre; });
    EXPECT_GE(smallest_angle_deg(mesh), 0.5 * double(std::min(settings.colour_edge_min_angle_deg,
                                                              settings.relocate_min_angle_deg)));
    const std::size_t relocated = aerial::mesh::live_vertices(mesh);
    const std::size_t midpoints = aerial::mesh::live_vertices(refined_dome(scene, fixed).mesh());
    std::printf("relocation: %zu vertices (%zu moved) against %zu at the edge midpoints\n",
                relocated, moved, midpoints);
    EXPECT_LT(relocated, midpoints);
    EXPECT_TRUE(positions(mesh) == positions(refined_dome(scene, settings).mesh()))
        << "two runs of the same input gave different meshes";

    // Coarsening undoes relocated bisections (the collapse restores the parents wherever the
    // vertex went) and settles.
    DomeScene high(60.0, 0.9, 180.0);
    high.colour = scene.colour;
    const auto turned = m.update(high.frame);
    EXPECT_GT(turned.merges, 0u);
    EXPECT_LE(max_face_error(mesh, high.frame, settings.colour), settings.split_lsb);
    const auto settled = m.update(high.frame);
    EXPECT_EQ(settled.splits + settled.merges, 0u);
    expect_not_flipped(mesh, [&](const glm::dvec3& c) { return c - scene.dome.centre; });

    // The budget.
    settings.max_vertices = 200;
    AdaptiveMesh small = refined_dome(scene, settings);
    EXPECT_LE(aerial::mesh::live_vertices(small.mesh()), 200u);
    EXPECT_FALSE(small.update(scene.frame).complete);

    settings.relocate_min_angle_deg = 61.0f;
    const auto bad =
        AdaptiveMesh::create(base.value(), aerial::mesh::Surface::sphere(scene.dome), settings);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().field, "relocate_min_angle_deg");
}

TEST(AdaptiveMesh, RelocatedVerticesMorphInAndOutWithoutPops) {
    const Pops instant = sun_move_pops(0, true);
    ASSERT_GT(instant.births, 0u) << "the sun move refined nothing";
    ASSERT_GT(instant.largest, 2.0f) << "without morphing nothing popped: the test shows nothing";
    constexpr int kUpdates = 8;
    const Pops morphed = sun_move_pops(kUpdates, true);
    EXPECT_GT(morphed.removals, 0u) << "no faded vertex was removed";
    EXPECT_LE(morphed.largest, instant.largest / 4.0f);
    EXPECT_LE(morphed.largest, 1.01f * morphed.birth_gap / kUpdates + 0.01f)
        << "birth gap " << morphed.birth_gap;
    std::printf("relocated morph: largest change per update %.2f LSB (at once %.2f)\n",
                morphed.largest, instant.largest);
    EXPECT_LT(morphed.vertices_at_end, morphed.vertices_after_move) << "coarsening never ended";
    EXPECT_LE(morphed.settled_error, 1e-3f) << "morphs did not finish";
}
