// Stability sweep: over a million combinations of extreme atmospheres, views and points, in float
// and in double, every model output is finite and physical (0 <= F_ex <= 1, L_in >= 0,
// E_sun >= 0). Seeded, so a failure names a reproducible case.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"

namespace {

using aerial::Atmosphere;
using aerial::Model;
using aerial::View;
using glm::dvec3;

class Sampler {
  public:
    explicit Sampler(unsigned seed) : rng_(seed) {}

    double uniform(double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng_);
    }
    double log_uniform(double lo, double hi) {
        return std::exp(uniform(std::log(lo), std::log(hi)));
    }
    template <class T, size_t N>
    T pick(const T (&values)[N]) {
        return values[std::uniform_int_distribution<size_t>(0, N - 1)(rng_)];
    }
    bool chance(double p) { return uniform(0.0, 1.0) < p; }

    dvec3 unit() {
        std::normal_distribution<double> n;
        dvec3 v;
        do v = {n(rng_), n(rng_), n(rng_)};
        while (glm::length(v) < 1e-6);
        return glm::normalize(v);
    }

    double coefficient() {
        if (chance(0.25)) return pick({0.0, 1e-30, 1e-20, 1e-12, 1.0});
        return log_uniform(1e-9, 1e-1);
    }
    dvec3 coefficients() { return {coefficient(), coefficient(), coefficient()}; }

    Atmosphere atmosphere() {
        Atmosphere a;
        if (chance(0.2)) return a;  // earth
        a.rayleigh_scattering = coefficients();
        a.mie_scattering = coefficients();
        a.mie_absorption = chance(0.5) ? dvec3(0.0) : coefficients();
        a.mie_g = chance(0.5) ? pick({-0.999, -0.9, 0.0, 0.76, 0.9, 0.99, 0.999})
                              : uniform(-0.999, 0.999);
        a.rayleigh_scale_height_m = chance(0.2) ? pick({1.0, 1e6}) : log_uniform(1.0, 1e6);
        a.mie_scale_height_m = chance(0.2) ? pick({1.0, 1e6}) : log_uniform(1.0, 1e6);
        a.planet_radius_m =
            chance(0.5) ? pick({6360e3, 3389.5e3, 1e3, 1e8}) : log_uniform(1e3, 1e8);
        a.atmosphere_radius_m = a.planet_radius_m + log_uniform(1.0, 1e6);
        a.sun_irradiance = {uniform(0, 10), uniform(0, 10), chance(0.1) ? 0.0 : uniform(0, 10)};
        return a;
    }

    View view(const Atmosphere& a) {
        View v;
        v.up = chance(0.5) ? pick({dvec3(0, 0, 1), dvec3(0, 1, 0), dvec3(-1, 0, 0)}) : unit();
        const double top = a.atmosphere_radius_m - a.planet_radius_m;
        const double altitude =
            pick({-5000.0, -100.0, 0.0, 2.0, 1000.0, 10000.0, top, top + 1e5, 1e7});
        const dvec3 sideways = glm::normalize(glm::cross(v.up, unit()));
        v.eye = v.up * (chance(0.8) ? altitude : uniform(-5000.0, 1e5)) +
                sideways * (chance(0.5) ? 0.0 : log_uniform(1.0, 1e6));
        // Straight up, straight down, on the horizon, below it, or anywhere.
        const int kind = std::uniform_int_distribution<int>(0, 4)(rng_);
        if (kind == 0)
            v.sun_dir = v.up;
        else if (kind == 1)
            v.sun_dir = -v.up;
        else if (kind == 2)
            v.sun_dir = sideways;
        else if (kind == 3)
            v.sun_dir = glm::normalize(sideways - v.up * uniform(0.001, 0.3));
        else
            v.sun_dir = unit();
        return v;
    }

    dvec3 point(const View& v) {
        double s = chance(0.1) ? pick({0.0, 1e-6, 1e7}) : log_uniform(1e-3, 1e7);
        int kind = std::uniform_int_distribution<int>(0, 3)(rng_);
        const dvec3 dir = kind == 0 ? v.sun_dir : kind == 1 ? -v.sun_dir : unit();
        return v.eye + dir * s;
    }

  private:
    std::mt19937_64 rng_;
};

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
void sweep(Model model, unsigned seed, int frames, int points) {
    Sampler sampler(seed);
    long long evaluated = 0, bad = 0;
    for (int f = 0; f < frames; ++f) {
        const Atmosphere a = sampler.atmosphere();
        const View v = sampler.view(a);
        const auto frame = aerial::prepare_frame<T>(a, v, model);
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
    sweep<double>(Model::reference, 5, 200, 5);
}

}  // namespace
