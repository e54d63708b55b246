// Shared by the core tests: seeded random sampling, and the sampler of extreme inputs used by
// the stability sweeps of the models and of the batch kernels.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <random>

#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"

namespace aerial::testing {

/// prepare_frame for an extreme atmosphere: without the atmosphere's own table of the higher
/// orders (tabulating scale heights of metres takes minutes), but for `height` with the `earth`
/// preset's slice for the same view attached, so that the higher orders' path of the models and
/// kernels runs on extreme inputs too (any slice is valid data for it).
template <class T>
Result<Frame<T>> extreme_frame(const Atmosphere& a, const View& v, Model model) {
    FrameOptions without;
    without.multiple_scattering = false;
    auto frame = prepare_frame<T>(a, v, model, without);
    if (!frame.ok() || model != Model::height) return frame;
    View earth_view = v;
    earth_view.eye = glm::dvec3(0.0, 0.0, 300.0);
    earth_view.meters_per_unit = 1.0;
    earth_view.up = glm::dvec3(0.0, 0.0, 1.0);
    const auto earth = prepare_frame<T>(Atmosphere{}, earth_view, model);
    Frame<T> out = *frame;
    if (earth.ok()) out.multiple_scattering = earth->multiple_scattering;
    return out;
}

using aerial::Atmosphere;
using aerial::View;
using glm::dvec3;

class Random {
  public:
    explicit Random(unsigned seed) : rng_(seed) {}
    double uniform(double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng_);
    }
    double log_uniform(double lo, double hi) {
        return std::exp(uniform(std::log(lo), std::log(hi)));
    }
    bool chance(double p) { return uniform(0.0, 1.0) < p; }
    template <class T, size_t N>
    T pick(const T (&values)[N]) {
        return values[std::uniform_int_distribution<size_t>(0, N - 1)(rng_)];
    }
    dvec3 unit() {
        std::normal_distribution<double> n;
        dvec3 v;
        do v = {n(rng_), n(rng_), n(rng_)};
        while (glm::length(v) < 1e-6);
        return glm::normalize(v);
    }

  protected:
    std::mt19937_64& engine() { return rng_; }

  private:
    std::mt19937_64 rng_;
};

/// Extreme atmospheres, views and points: coefficients from 0 to 1 /m, |g| up to 0.999, scale
/// heights 1 m to 1000 km, planets 1 km to 10^5 km, eyes below sea level and above the
/// atmosphere, the sun straight up, down, on and below the horizon, distances 0 to 10^7 m, and
/// about 2 % of points that are not positions (NaN, Inf, beyond kMaxDistanceM).
class ExtremeSampler : public Random {
  public:
    using Random::Random;

    double coefficient() {
        if (chance(0.25)) return pick({0.0, 1e-30, 1e-20, 1e-12, 1.0});
        return log_uniform(1e-9, 1e-1);
    }
    dvec3 coefficients() { return {coefficient(), coefficient(), coefficient()}; }

    Atmosphere atmosphere() {
        Atmosphere a;
        if (chance(0.2)) return a;
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
        const int kind = std::uniform_int_distribution<int>(0, 4)(engine());
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
        if (chance(0.1)) v.meters_per_unit = pick({1e-3, 0.3048, 1e3});
        return v;
    }

    /// A point in engine units; about 2 % are not positions.
    dvec3 point(const View& v) {
        constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
        constexpr double kInf = std::numeric_limits<double>::infinity();
        if (chance(0.02)) {
            const dvec3 bad[] = {{kNaN, 0, 0}, {0, kInf, 0},     {0, 0, -kInf},
                                 {1e30, 0, 0}, {0, -3e38, 3e38}, {2e12, 0, 0}};
            return pick(bad);
        }
        const double s = chance(0.1) ? pick({0.0, 1e-6, 1e7}) : log_uniform(1e-3, 1e7);
        const int kind = std::uniform_int_distribution<int>(0, 3)(engine());
        const dvec3 dir = kind == 0 ? v.sun_dir : kind == 1 ? -v.sun_dir : unit();
        return v.eye + dir * (s / v.meters_per_unit);
    }
};

}  // namespace aerial::testing
