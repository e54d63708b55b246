// The ozone layer's column along a straight ray, in closed form: the tent profile is linear in
// the distance r from the planet's centre, and along a ray r(t) = sqrt(t^2 + 2 r0 mu t + r0^2),
// whose integral has a closed form. The `height` and 2002 models take the layer's transmittance
// towards the sun once per frame and per chained sky piece, so it has to be cheap and exact.
#include <algorithm>
#include <array>
#include <cmath>

#include <glm/exponential.hpp>

#include "aerial/scattering.hpp"
#include "math.hpp"

namespace aerial {
namespace {

/// Integral of r(t) = sqrt((t + b)^2 + c) over [t0, t1], c >= 0 (c: the squared distance of the
/// ray's line from the centre, b: where along the ray that distance is reached, negated).
double integral_of_radius(double t0, double t1, double b, double c) {
    auto primitive = [&](double t) {
        const double u = t + b;
        const double root = std::sqrt(u * u + c);
        // (u root + c asinh(u / sqrt c)) / 2, with asinh's limit for c -> 0.
        const double log_term = c > 0.0 ? c * std::asinh(u / std::sqrt(c)) : 0.0;
        return 0.5 * (u * root + log_term);
    };
    return primitive(t1) - primitive(t0);
}

}  // namespace

/// The ozone layer's column (m of peak-density equivalent) from a point at `altitude_m` along a
/// direction of zenith cosine `mu`, up to the atmosphere's top; the ray is not stopped by the
/// planet (callers choose the direction).
double ozone_column_m(const Atmosphere& a, double altitude_m, double mu) {
    const double ground = a.planet_radius_m;
    const double r0 = ground + altitude_m;
    const double half = 0.5 * a.ozone_width_m;
    const double top = a.atmosphere_radius_m;
    // Radii of the tent's foot, peak and head, clipped to the atmosphere.
    const std::array<double, 3> radii{
        std::clamp(ground + a.ozone_center_altitude_m - half, 0.0, top),
        std::clamp(ground + a.ozone_center_altitude_m, 0.0, top),
        std::clamp(ground + a.ozone_center_altitude_m + half, 0.0, top)};
    const double b = r0 * mu;                         // r(t)^2 = (t + b)^2 + c
    const double c = std::max(0.0, r0 * r0 - b * b);  // = r0^2 (1 - mu^2)
    // Where the ray crosses each radius, beyond its start.
    std::array<double, 8> cuts{};
    int n = 0;
    cuts[n++] = 0.0;
    for (double radius : radii) {
        const double disc = radius * radius - c;
        if (disc < 0.0) continue;
        const double root = std::sqrt(disc);
        for (double t : {-b - root, -b + root}) {
            if (t > 0.0) cuts[n++] = t;
        }
    }
    // At most seven cuts: an insertion sort (std::sort's unrolled threshold of 16 makes GCC warn
    // about the fixed array).
    for (int i = 1; i < n; ++i) {
        for (int j = i; j > 0 && cuts[j] < cuts[j - 1]; --j) std::swap(cuts[j], cuts[j - 1]);
    }
    double column = 0.0;
    for (int i = 0; i + 1 < n; ++i) {
        const double t0 = cuts[i], t1 = cuts[i + 1];
        if (!(t1 > t0)) continue;
        const double tm = 0.5 * (t0 + t1);
        const double rm = std::sqrt((tm + b) * (tm + b) + c);
        const double length = t1 - t0;
        if (rm > radii[0] && rm < radii[1]) {  // rising side: (r - foot) / half
            column += (integral_of_radius(t0, t1, b, c) - radii[0] * length) / half;
        } else if (rm >= radii[1] && rm < radii[2]) {  // falling side: (head - r) / half
            column += (radii[2] * length - integral_of_radius(t0, t1, b, c)) / half;
        }
    }
    return column;
}

glm::dvec3 ozone_transmittance(const Atmosphere& atmosphere, double altitude_m, double cos_zenith) {
    if (atmosphere.ozone_absorption == glm::dvec3(0.0)) return glm::dvec3(1.0);
    const double h = std::max(altitude_m, 0.0);
    const double horizon = detail::horizon_cosine(atmosphere.planet_radius_m, h);
    // A blocked sun: the column at the horizon's cosine, where sunlight grazing the shadow comes
    // from.
    const double mu = std::clamp(std::max(cos_zenith, horizon), -1.0, 1.0);
    return glm::exp(-atmosphere.ozone_absorption * ozone_column_m(atmosphere, h, mu));
}

}  // namespace aerial
