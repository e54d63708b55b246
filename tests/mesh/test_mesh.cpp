// aerial::mesh: the shapes, the colour error, adaptive bisection and coarsening, decimation.
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"

namespace {

using aerial::mesh::AdaptiveMesh;
using aerial::mesh::AdaptiveSettings;
using aerial::mesh::Mesh;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

glm::dvec3 to_glm(const Mesh::Point& p) { return {p[0], p[1], p[2]}; }

glm::dvec3 sun_at(double elevation_deg, double azimuth_deg = 0.0) {
    const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

aerial::Frame<float> make_frame(const glm::dvec3& eye, const glm::dvec3& sun, double mie_g,
                                const char* preset = "earth") {
    auto atmosphere = aerial::atmosphere_preset(preset);
    EXPECT_TRUE(atmosphere.ok());
    aerial::Atmosphere a = atmosphere.value();
    a.mie_g = mie_g;
    aerial::View view;
    view.eye = eye;
    view.sun_dir = glm::normalize(sun);
    auto frame = aerial::prepare_frame<float>(a, view, aerial::Model::height);
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    return frame.value();
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
    for (auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        glm::dvec3 p[3];
        glm::vec3 c[3];
        int k = 0;
        for (auto v : mesh.fv_range(f)) {
            p[k] = to_glm(mesh.point(v));
            c[k] = aerial::mesh::display_colour(frame, colour, p[k]);
            ++k;
        }
        worst = std::max(
            worst, aerial::mesh::colour_error(frame, colour, p[0], p[1], p[2], c[0], c[1], c[2]));
    }
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

// No face turned over: each face's normal points away from `outward_of` the face.
template <class Outward>
void expect_not_flipped(const Mesh& mesh, Outward outward) {
    for (auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        glm::dvec3 p[3];
        int k = 0;
        for (auto v : mesh.fv_range(f)) p[k++] = to_glm(mesh.point(v));
        const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        EXPECT_GT(glm::dot(n, outward((p[0] + p[1] + p[2]) / 3.0)), 0.0)
            << "face " << f.idx() << " is flipped";
    }
}

std::vector<glm::dvec3> positions(const Mesh& mesh) {
    std::vector<glm::dvec3> out;
    for (auto v : mesh.vertices())
        if (!mesh.status(v).deleted()) out.push_back(to_glm(mesh.point(v)));
    return out;
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
    EXPECT_EQ(aerial::mesh::latlong_dome(4, 2).error().field, "segments");
    aerial::mesh::DomeOptions dome;
    dome.radius_m = -1;
    EXPECT_EQ(aerial::mesh::geodesic_dome(4, dome).error().field, "radius_m");
    auto field = aerial::mesh::rolling_hills(0, 0, 100, 1, 50);
    field.height_m = [](double x, double) { return x > 50 ? std::nan("") : 0.0; };
    const auto grid = aerial::mesh::terrain_grid(field, 4, 4);
    ASSERT_FALSE(grid.ok());
    EXPECT_EQ(grid.error().field, "height_m");
    EXPECT_NE(grid.error().message.find("not finite"), std::string::npos) << grid.error().message;
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
    for (auto v : mesh.vertices()) {
        const glm::dvec3 p = to_glm(mesh.point(v));
        EXPECT_NEAR(glm::length(p - scene.dome.centre), scene.dome.radius_m, 1e-6);
        if (std::size_t(v.idx()) < original.size()) {
            EXPECT_EQ(p, original[std::size_t(v.idx())])
                << "original vertex " << v.idx() << " moved";
        }
    }
    expect_conforming(mesh, [&](const glm::dvec3& p) {
        return std::abs(p.z - scene.dome.centre.z) < 1e-6 * scene.dome.radius_m;
    });
    expect_not_flipped(mesh, [&](const glm::dvec3& c) { return c - scene.dome.centre; });
    // The independent dense measure agrees within the estimate's sampling.
    const auto dense = aerial::mesh::dense_error(mesh, scene.frame, settings.colour, 0.01);
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
        full_settings.time_slice_ms = 1e9;
        const auto surface = aerial::mesh::Surface::terrain(scene.field);
        AdaptiveMesh indexed = AdaptiveMesh::create(base.value(), surface, settings).value();
        AdaptiveMesh full = AdaptiveMesh::create(base.value(), surface, full_settings).value();
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
            }
            if (i == 32) {
                indexed.invalidate();
                full.invalidate();
            }
            const auto a = indexed.update(frame);
            const auto b = full.update(frame);
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
    EXPECT_EQ(made.error().message, "base: vertex 3 has a non-finite position");
    made = AdaptiveMesh::create(Mesh{}, aerial::mesh::Surface{}, AdaptiveSettings{});
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().message, "base: has no faces");
    AdaptiveSettings bad;
    bad.merge_ratio = 0.5f;
    made = AdaptiveMesh::create(base.value(), aerial::mesh::Surface{}, bad);
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().field, "merge_ratio");
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
              "mesh: has no faces");
}

}  // namespace
