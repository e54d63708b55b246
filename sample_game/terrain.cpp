#include "terrain.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>

namespace sample {
namespace {

/// Lattice value in [0, 1) at integer point (ix, iy): a 32-bit integer hash (murmur3 finaliser).
double lattice_value(std::int64_t ix, std::int64_t iy, std::uint32_t seed) {
    std::uint32_t h = static_cast<std::uint32_t>(ix) * 0x8da6b343u ^
                      static_cast<std::uint32_t>(iy) * 0xd8163841u ^ seed * 0xcb1ab31fu;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return static_cast<double>(h) * (1.0 / 4294967296.0);
}

/// Smooth value noise in [0, 1], period 1 lattice.
double value_noise(double x, double y, std::uint32_t seed) {
    const double fx = std::floor(x), fy = std::floor(y);
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
    const double tx = x - fx, ty = y - fy;
    const auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
    const double u = fade(tx), v = fade(ty);
    const double a = lattice_value(ix, iy, seed), b = lattice_value(ix + 1, iy, seed);
    const double c = lattice_value(ix, iy + 1, seed), d = lattice_value(ix + 1, iy + 1, seed);
    return (a + (b - a) * u) + ((c + (d - c) * u) - (a + (b - a) * u)) * v;
}

/// Weight of an octave of wavelength `wavelength_m` for a sample covering `footprint_m`: 1 when
/// the octave is resolved (4 samples per wavelength), fading to 0 at 2 (Nyquist).
double octave_weight(double wavelength_m, double footprint_m) {
    return std::clamp((wavelength_m - 2.0 * footprint_m) / (2.0 * footprint_m), 0.0, 1.0);
}

/// Turns the plane by about 37 degrees between octaves, so that their lattices do not line up
/// (value noise on aligned lattices shows a grid of plateaus).
void rotate(double& x, double& y) {
    const double rx = 0.8 * x - 0.6 * y;
    y = 0.6 * x + 0.8 * y;
    x = rx;
}

/// Fractal sum of value noise in about [-1, 1]: octaves halve in wavelength and amplitude.
double fbm(double x_m, double y_m, double wavelength_m, int octaves, double footprint_m,
           std::uint32_t seed) {
    double sum = 0.0, amplitude = 1.0, norm = 0.0;
    for (int i = 0; i < octaves; ++i) {
        const double w = octave_weight(wavelength_m, footprint_m);
        if (w <= 0.0) break;
        const double n = value_noise(x_m / wavelength_m, y_m / wavelength_m, seed + i);
        sum += w * amplitude * (2.0 * n - 1.0);
        rotate(x_m, y_m);
        norm += amplitude;
        amplitude *= 0.5;
        wavelength_m *= 0.5;
    }
    return norm > 0.0 ? sum / norm * 2.0 : 0.0;
}

/// Ridged fractal in about [0, 1]: sharp crests where the noise crosses its middle value.
double ridged(double x_m, double y_m, double wavelength_m, int octaves, double footprint_m,
              std::uint32_t seed) {
    double sum = 0.0, amplitude = 1.0, norm = 0.0, previous = 1.0;
    for (int i = 0; i < octaves; ++i) {
        const double w = octave_weight(wavelength_m, footprint_m);
        if (w <= 0.0) break;
        const double n = value_noise(x_m / wavelength_m, y_m / wavelength_m, seed + i);
        double r = 1.0 - std::abs(2.0 * n - 1.0);
        r *= r;
        sum += w * amplitude * r * previous;  // finer crests only where coarser ones stand
        previous = r;
        rotate(x_m, y_m);
        norm += amplitude;
        amplitude *= 0.5;
        wavelength_m *= 0.5;
    }
    return norm > 0.0 ? sum / norm : 0.0;
}

double smoothstep(double edge0, double edge1, double x) {
    const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

}  // namespace

double terrain_height_m(double x_m, double y_m, double footprint_m) {
    // Large-scale land mass (sea where it is low), rolling hills, and mountain ranges on the
    // high ground. Wavelengths in metres.
    const double land = fbm(x_m, y_m, 40000.0, 3, footprint_m, 11u) + 0.1;
    const double hills = fbm(x_m, y_m, 2500.0, 7, footprint_m, 23u);
    const double mountains = ridged(x_m, y_m, 9000.0, 8, footprint_m, 37u);
    const double height =
        400.0 * land + 100.0 * hills + 2200.0 * smoothstep(0.0, 0.6, land) * mountains;
    return std::max(height, 0.0);
}

double surface_z_m(double x_m, double y_m, double footprint_m, double planet_radius_m) {
    return terrain_height_m(x_m, y_m, footprint_m) -
           (x_m * x_m + y_m * y_m) / (2.0 * planet_radius_m);
}

glm::dvec3 terrain_normal(double x_m, double y_m, double footprint_m) {
    const double e = std::max(footprint_m, 1.0);
    const double dx =
        terrain_height_m(x_m + e, y_m, footprint_m) - terrain_height_m(x_m - e, y_m, footprint_m);
    const double dy =
        terrain_height_m(x_m, y_m + e, footprint_m) - terrain_height_m(x_m, y_m - e, footprint_m);
    return glm::normalize(glm::dvec3(-dx, -dy, 2.0 * e));
}

glm::dvec3 terrain_albedo(Surface surface, double height_m, const glm::dvec3& normal) {
    const glm::dvec3 water{0.02, 0.04, 0.06};
    const glm::dvec3 grass{0.09, 0.15, 0.05};
    const glm::dvec3 rock{0.20, 0.19, 0.17};
    const glm::dvec3 snow{0.80, 0.82, 0.85};
    if (surface == Surface::water) return water;
    const double flat = normal.z;  // 1 on level ground
    const glm::dvec3 soil = glm::mix(rock, grass, smoothstep(0.7, 0.85, flat));
    const double snowy = smoothstep(1500.0, 1800.0, height_m) * smoothstep(0.6, 0.75, flat);
    return glm::mix(soil, snow, snowy);
}

}  // namespace sample
