// Stability sweep: over a million combinations of extreme atmospheres, views and points, in float
// and in double, every model output is finite and physical (0 <= F_ex <= 1, L_in >= 0,
// E_sun >= 0). Seeded, so a failure names a reproducible case. AERIAL_TEST_SCALE (test_scale.hpp)
// runs the first part of each sweep.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "extreme_sampler.hpp"
#include "test_scale.hpp"

namespace {

using aerial::Atmosphere;
using aerial::Model;
using aerial::View;
using glm::dvec3;

template <class T>
bool physical(const aerial::Scattering<T>& s) {
    for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(s.extinction[c]) || !std::isfinite(s.in_scattering[c]) ||
            !std::isfinite(s.sun_irradiance[c])) {
            return false;
        }
        if (s.extinction[c] < T(0) || s.extinction[c] > T(1)) return false;
        if (s.in_scattering[c] < T(0) || s.sun_irradiance[c] < T(0)) return false;
    }
    return true;
}

template <class T>
std::string describe(const aerial::Scattering<T>& s) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "F=(%g %g %g) L=(%g %g %g) E=(%g %g %g)",
                  double(s.extinction.x), double(s.extinction.y), double(s.extinction.z),
                  double(s.in_scattering.x), double(s.in_scattering.y), double(s.in_scattering.z),
                  double(s.sun_irradiance.x), double(s.sun_irradiance.y),
                  double(s.sun_irradiance.z));
    return buffer;
}

/// Runs `frames` random (atmosphere, view) pairs with `points` random points each.
template <class T>
void sweep(Model model, unsigned seed, int full_frames, int points) {
    const int frames = aerial::testing::scaled_count(full_frames, "frames");
    aerial::testing::ExtremeSampler sampler(seed);
    long long evaluated = 0, bad = 0;
    for (int f = 0; f < frames; ++f) {
        const Atmosphere a = sampler.atmosphere();
        const View v = sampler.view(a);
        const auto frame = aerial::testing::extreme_frame<T>(a, v, model);
        ASSERT_TRUE(frame.ok()) << "frame " << f << ": " << frame.error().message;
        for (int p = 0; p < points; ++p) {
            const dvec3 x = sampler.point(v);
            const auto s = aerial::scatter(*frame, glm::vec<3, T>(x));
            ++evaluated;
            if (!physical(s) && ++bad <= 5) {
                ADD_FAILURE() << aerial::model_name(model) << " frame " << f << " point " << p
                              << ": " << describe(s) << "\n  atmosphere " << aerial::to_json(a)
                              << "  eye " << v.eye.x << "," << v.eye.y << "," << v.eye.z << " sun "
                              << v.sun_dir.x << "," << v.sun_dir.y << "," << v.sun_dir.z << " up "
                              << v.up.x << "," << v.up.y << "," << v.up.z << " point " << x.x << ","
                              << x.y << "," << x.z;
            }
        }
    }
    std::printf("%s %s: %lld combinations, %lld unphysical\n",
                std::string(aerial::model_name(model)).c_str(), sizeof(T) == 4 ? "float" : "double",
                evaluated, bad);
    EXPECT_EQ(bad, 0);
}

// 2000 frames x 500 points = 10^6 combinations per model and precision.
constexpr int kFrames = 2000;
constexpr int kPointsPerFrame = 500;

TEST(Stability, HoffmanPreethamFloatIsAlwaysPhysical) {
    sweep<float>(Model::hoffman_preetham, 1, kFrames, kPointsPerFrame);
}
TEST(Stability, HoffmanPreethamDoubleIsAlwaysPhysical) {
    sweep<double>(Model::hoffman_preetham, 2, kFrames, kPointsPerFrame);
}
TEST(Stability, HeightFloatIsAlwaysPhysical) {
    sweep<float>(Model::height, 3, kFrames, kPointsPerFrame);
}
TEST(Stability, HeightDoubleIsAlwaysPhysical) {
    sweep<double>(Model::height, 4, kFrames, kPointsPerFrame);
}
TEST(Stability, ReferenceIsAlwaysPhysical) {
    // The integrator is slow on purpose (converged, double): a smaller sweep of the same ranges.
    sweep<double>(Model::single_scattering, 5, 200, 5);
}

}  // namespace
