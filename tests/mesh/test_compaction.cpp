// aerial::mesh::AdaptiveMesh compacting itself: the arrays stay bounded, and compaction changes
// nothing an engine can see but the handle numbers.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"
#include "frames.hpp"

namespace {

using aerial::mesh::AdaptiveMesh;
using aerial::mesh::AdaptiveSettings;
using aerial::mesh::Mesh;

// What an engine can see of the mesh, in handle order with the deleted elements left out: each
// live face's corner positions and estimate, each live vertex's position, morph weight, parents'
// positions and morphed value.
struct Visible {
    std::vector<double> faces;
    std::vector<float> errors;
    std::vector<double> vertices;
    std::vector<float> weights, morphed;
    bool operator==(const Visible& o) const {
        return faces == o.faces && errors == o.errors && vertices == o.vertices &&
               weights == o.weights && morphed == o.morphed;
    }
};

Visible visible(const AdaptiveMesh& adaptive) {
    const Mesh& mesh = adaptive.mesh();
    Visible out;
    for (auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        for (auto v : mesh.fv_range(f))
            for (int k = 0; k < 3; ++k) out.faces.push_back(mesh.point(v)[k]);
        out.errors.push_back(adaptive.face_error(f));
    }
    // A smooth value per vertex to morph (three components, stride 4).
    std::vector<float> values(4 * mesh.n_vertices(), 0.0f);
    for (auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        for (int k = 0; k < 3; ++k)
            values[4 * std::size_t(v.idx()) + std::size_t(k)] = float(std::sin(1e-4 * p[k]));
    }
    adaptive.morph_into(values.data(), 3, 4);
    for (auto v : mesh.vertices()) {
        if (mesh.status(v).deleted()) continue;
        for (int k = 0; k < 3; ++k) out.vertices.push_back(mesh.point(v)[k]);
        out.weights.push_back(adaptive.morph_weight(v));
        const auto [a, b] = adaptive.parents(v);
        for (auto parent : {a, b})
            for (int k = 0; k < 3; ++k)
                out.vertices.push_back(parent.is_valid() ? mesh.point(parent)[k] : -1.0);
        for (int k = 0; k < 3; ++k)
            out.morphed.push_back(values[4 * std::size_t(v.idx()) + std::size_t(k)]);
    }
    return out;
}

void expect_compaction_gives_the_results_of_never_compacting(bool relocate, int updates) {
    aerial::mesh::DomeOptions dome;
    dome.centre = {0, 0, 2};
    auto base = aerial::mesh::geodesic_dome(4, dome);
    ASSERT_TRUE(base.ok());
    AdaptiveSettings settings;
    settings.colour.texel = glm::vec3(0.0f);
    settings.colour.display.exposure = 12.0f;
    settings.lock_boundary = false;
    settings.max_vertices = 500;  // at the budget, it splits and merges in every update
    settings.morph_updates = 2;   // vertices fading in and out when compaction comes
    // A lower ratio than the default 0.5, so that compaction comes several times in the run and
    // a compaction also renumbers what an earlier one left.
    settings.compact_garbage_ratio = 0.25f;
    settings.relocate = relocate;
    AdaptiveSettings never = settings, explicit_settings = settings;
    never.compact_garbage_ratio = 0.0f;
    explicit_settings.compact_garbage_ratio = 0.0f;
    const auto surface = aerial::mesh::Surface::sphere(dome);
    AdaptiveMesh automatic = AdaptiveMesh::create(base.value(), surface, settings).value();
    AdaptiveMesh reference = AdaptiveMesh::create(base.value(), surface, never).value();
    AdaptiveMesh by_hand = AdaptiveMesh::create(base.value(), surface, explicit_settings).value();

    std::size_t compactions = 0, splits = 0, merges = 0;
    const int kUpdates = updates;
    for (int i = 0; i < kUpdates; ++i) {
        // The sun goes round and up and down; the eye climbs and comes back down.
        const glm::dvec3 sun =
            aerial_test::sun_at(3.0 + 20.0 * (1.0 - std::cos(i * 0.3)), 40.0 * i);
        const glm::dvec3 eye{0.0, 0.0, 2.0 + 40.0 * (i % 30)};
        const auto frame = aerial_test::make_frame(eye, sun, 0.9);
        const auto a = automatic.update(frame);
        const auto r = reference.update(frame);
        const auto h = by_hand.update(frame);
        by_hand.compact();
        ASSERT_FALSE(r.compacted);
        compactions += a.compacted;
        splits += r.splits;
        merges += r.merges;
        for (const auto* s : {&a, &h}) {
            ASSERT_EQ(s->faces_estimated, r.faces_estimated) << "update " << i;
            ASSERT_EQ(s->splits, r.splits) << "update " << i;
            ASSERT_EQ(s->merges, r.merges) << "update " << i;
            ASSERT_EQ(s->vertices, r.vertices) << "update " << i;
            ASSERT_EQ(s->faces, r.faces) << "update " << i;
            ASSERT_EQ(s->complete, r.complete) << "update " << i;
            ASSERT_EQ(s->max_error_lsb, r.max_error_lsb) << "update " << i;
        }
        const Visible seen = visible(reference);
        ASSERT_TRUE(visible(automatic) == seen) << "automatic compaction changed update " << i;
        ASSERT_TRUE(visible(by_hand) == seen) << "compact() after each update changed update " << i;

        // Bounded: the deleted elements stay within a quarter of the live ones (the ratio).
        const Mesh& m = automatic.mesh();
        const std::size_t live_v = aerial::mesh::live_vertices(m);
        const std::size_t live_f = aerial::mesh::live_faces(m);
        ASSERT_LE(m.n_vertices() - live_v, live_v / 4) << "update " << i;
        ASSERT_LE(m.n_faces() - live_f, live_f / 4) << "update " << i;
        ASSERT_LE(m.n_edges(), 3 * m.n_faces() / 2 + m.n_vertices()) << "update " << i;
        ASSERT_EQ(by_hand.mesh().n_vertices(), live_v) << "update " << i;
    }
    const Mesh& grown = reference.mesh();
    const std::size_t live = aerial::mesh::live_vertices(grown);
    std::printf(
        "compaction%s: %zu updates, %zu splits, %zu merges, %zu compactions; vertex slots "
        "%zu with compaction, %zu without, %zu live\n",
        relocate ? " (relocating)" : "", std::size_t(kUpdates), splits, merges, compactions,
        automatic.mesh().n_vertices(), grown.n_vertices(), live);
    EXPECT_GT(merges, 0u) << "nothing was coarsened: no garbage to collect";
    EXPECT_GE(compactions, 2u);
    EXPECT_GT(grown.n_vertices() - live, live / 4)
        << "without compaction the deleted vertices should have passed the bound";
}

}  // namespace

TEST(AdaptiveMeshCompaction, KeepsTheArraysBoundedAndGivesTheResultsOfNeverCompacting) {
    expect_compaction_gives_the_results_of_never_compacting(false, 70);
}

// Relocated vertices (AdaptiveSettings::relocate) are renumbered with everything else.
TEST(AdaptiveMeshCompaction, GivesTheResultsOfNeverCompactingWithRelocatedVertices) {
    expect_compaction_gives_the_results_of_never_compacting(true, 50);  // 48 trials a vertex
}

namespace {

TEST(AdaptiveMeshCompaction, ANegativeOrNonFiniteRatioIsAnErrorNamingIt) {
    for (const float ratio : {-0.5f, std::nanf(""), INFINITY}) {
        AdaptiveSettings settings;
        settings.compact_garbage_ratio = ratio;
        const auto e = aerial::mesh::validate(settings);
        ASSERT_TRUE(e.has_value()) << ratio;
        EXPECT_EQ(e->field, "compact_garbage_ratio");
        EXPECT_NE(e->message.find("compact_garbage_ratio"), std::string::npos) << e->message;
    }
}

}  // namespace
