// DecimatingMesh: the run-time adaptive mesh started from a decimated one and rebuilt when the
// sun has moved on (aerial/mesh.hpp).
#include <algorithm>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "aerial/mesh.hpp"
#include "frames.hpp"

namespace {

using aerial::mesh::DecimatingMesh;
using aerial::mesh::DecimatingSettings;
using aerial_test::make_frame;
using aerial_test::sun_at;

struct Dome {
    aerial::mesh::DomeOptions dome;
    DecimatingSettings settings;
    Dome() {
        dome.centre = {0, 0, 2};
        settings.adaptive.colour.texel = glm::vec3(0.0f);
        const auto frame = make_frame(dome.centre, sun_at(10.0), 0.9);
        const auto side =
            aerial::scatter(frame, glm::vec3(dome.centre + dome.radius_m * sun_at(30.0, 90.0)));
        settings.adaptive.colour.display.exposure =
            0.5f / std::max({side.in_scattering.x, side.in_scattering.y, side.in_scattering.z});
        settings.adaptive.lock_boundary = false;
        // Coarse bounds keep the test quick.
        settings.adaptive.split_lsb = 3.0f;
        settings.fine_split_lsb = 1.5f;
        settings.decimate_lsb = 2.5f;
        settings.background = false;
    }
    aerial::Frame<float> frame(double sun_elevation_deg) const {
        return make_frame(dome.centre, sun_at(sun_elevation_deg), 0.9);
    }
    DecimatingMesh create() const {
        auto made = DecimatingMesh::create(aerial::mesh::geodesic_dome(4, dome).value(),
                                           aerial::mesh::Surface::sphere(dome), settings);
        EXPECT_TRUE(made.ok()) << made.error().message;
        return std::move(made).value();
    }
};

// The first update is the offline pipeline: refine to fine_split_lsb, decimate to decimate_lsb.
TEST(DecimatingMesh, FirstUpdateGivesTheDecimatedMesh) {
    const Dome d;
    DecimatingMesh m = d.create();
    const auto frame = d.frame(10.0);
    const auto stats = m.update(frame);
    ASSERT_TRUE(stats.ok()) << stats.error().message;
    EXPECT_EQ(m.stats().rebuilds, 1u);
    EXPECT_TRUE(m.stats().switched);
    EXPECT_LE(stats->max_error_lsb, d.settings.adaptive.split_lsb);

    aerial::mesh::AdaptiveSettings fine = d.settings.adaptive;
    fine.split_lsb = d.settings.fine_split_lsb;
    auto refined =
        aerial::mesh::AdaptiveMesh::create(aerial::mesh::geodesic_dome(4, d.dome).value(),
                                           aerial::mesh::Surface::sphere(d.dome), fine)
            .value();
    refined.update(frame);
    aerial::mesh::DecimateOptions options;
    options.colour = d.settings.adaptive.colour;
    options.max_lsb = d.settings.decimate_lsb;
    const auto decimated = aerial::mesh::decimate(refined.mesh(), frame, options).value();
    EXPECT_EQ(aerial::mesh::live_vertices(m.mesh()), aerial::mesh::live_vertices(decimated));
    EXPECT_LT(aerial::mesh::live_vertices(m.mesh()), aerial::mesh::live_vertices(refined.mesh()));
}

// Below rebuild_sun_rad the adaptive mesh follows the sun alone; beyond it the mesh is rebuilt.
TEST(DecimatingMesh, RebuildsWhenTheSunHasTurnedByTheThreshold) {
    Dome d;
    d.settings.rebuild_sun_rad = 1.0 * 3.14159265358979 / 180.0;
    DecimatingMesh m = d.create();
    ASSERT_TRUE(m.update(d.frame(10.0)).ok());
    const auto near = m.update(d.frame(10.6));
    ASSERT_TRUE(near.ok());
    EXPECT_EQ(m.stats().rebuilds, 1u);
    EXPECT_FALSE(m.stats().switched);
    EXPECT_LE(near->max_error_lsb, d.settings.adaptive.split_lsb);
    const auto far = m.update(d.frame(11.2));
    ASSERT_TRUE(far.ok());
    EXPECT_EQ(m.stats().rebuilds, 2u);
    EXPECT_TRUE(m.stats().switched);
    EXPECT_LE(far->max_error_lsb, d.settings.adaptive.split_lsb);
    EXPECT_GT(m.stats().rebuild_ms, 0.0);
}

// On its own thread: updates go on with the current mesh until the rebuild is done.
TEST(DecimatingMesh, BackgroundRebuildSwitchesWhenDone) {
    Dome d;
    d.settings.background = true;
    d.settings.rebuild_sun_rad = 0.5 * 3.14159265358979 / 180.0;
    DecimatingMesh m = d.create();
    ASSERT_TRUE(m.update(d.frame(10.0)).ok());  // the first rebuild runs inside it
    ASSERT_TRUE(m.update(d.frame(11.0)).ok());
    EXPECT_TRUE(m.stats().rebuilding);
    EXPECT_EQ(m.stats().rebuilds, 1u);
    for (int i = 0; i < 600 && m.stats().rebuilds < 2; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        ASSERT_TRUE(m.update(d.frame(11.0)).ok());
    }
    EXPECT_EQ(m.stats().rebuilds, 2u);
    EXPECT_FALSE(m.stats().rebuilding);
}

TEST(DecimatingMesh, BadSettingsAreNamed) {
    Dome d;
    d.settings.decimate_lsb = 4.0f;
    auto made = DecimatingMesh::create(aerial::mesh::geodesic_dome(4, d.dome).value(),
                                       aerial::mesh::Surface::sphere(d.dome), d.settings);
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().message,
              "aerial::mesh::DecimatingMesh::create(): decimate_lsb: expected in [fine_split_lsb, "
              "adaptive.split_lsb], got 4");
    d = Dome();
    d.settings.rebuild_sun_rad = 0.0;
    made = DecimatingMesh::create(aerial::mesh::geodesic_dome(4, d.dome).value(),
                                  aerial::mesh::Surface::sphere(d.dome), d.settings);
    ASSERT_FALSE(made.ok());
    EXPECT_EQ(made.error().field, "rebuild_sun_rad");
}

}  // namespace
