// The sky measured against `reference`: probe directions, and the error of a sky method, a
// per-vertex dome and an RGBA8 cubemap along them.
#include "aerial/validation/sky_measure.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "aerial/phase.hpp"
#include "common/error_text.hpp"
#include "core/sky_internal.hpp"

namespace aerial::validation {

using detail::display_8bit;
using detail::elevation_of;
using detail::quantised;
using glm::dvec3;

Result<SkyProbe> make_sky_probe(const Atmosphere& atmosphere, const View& view, int elevation_steps,
                                int azimuth_steps, ToneCurve curve) {
    constexpr const char* kFunction = "validation::make_sky_probe";
    if (elevation_steps < 1) {
        return aerial::detail::invalid(kFunction, "elevation_steps", ">= 1",
                                       aerial::detail::number(elevation_steps));
    }
    if (azimuth_steps < 1) {
        return aerial::detail::invalid(kFunction, "azimuth_steps", ">= 1",
                                       aerial::detail::number(azimuth_steps));
    }
    auto sky = prepare_sky(atmosphere, view, SkyMethod::reference);
    if (!sky) return aerial::detail::from(kFunction, sky.error());
    const dvec3 up = sky->view.up;
    const dvec3 helper = std::abs(up.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    const dvec3 east = glm::normalize(helper - up * glm::dot(helper, up));
    const dvec3 north = glm::cross(up, east);
    SkyProbe p;
    p.curve = curve;
    const double sun_elevation = elevation_of(*sky, sky->view.sun_dir);
    const dvec3 e_sun = sun_irradiance_at_altitude(atmosphere, sky->eye_altitude_m, sun_elevation);
    auto ambient = sky_ambient(atmosphere, sky->eye_altitude_m, sun_elevation);
    if (!ambient) return aerial::detail::from(kFunction, ambient.error());
    p.exposure = auto_exposure(e_sun, sun_elevation, *ambient, atmosphere.sun_irradiance);
    for (int r = 0; r <= elevation_steps; ++r) {
        // The top row stops short of the zenith (where every azimuth is the same direction).
        const double e = (kPi / 2) * std::min(double(r), elevation_steps - 0.25) / elevation_steps;
        for (int s = 0; s < azimuth_steps; ++s) {
            const double az = 2 * kPi * (s + 0.37) / azimuth_steps;
            const dvec3 d =
                std::cos(e) * (std::cos(az) * east + std::sin(az) * north) + std::sin(e) * up;
            p.directions.push_back(d);
            p.elevations_rad.push_back(e);
            p.reference.push_back(sky_radiance(*sky, d));
            p.reference_display.push_back(display_8bit(p.reference.back(), p.exposure, curve));
        }
    }
    return p;
}

namespace {

/// Accumulates per-direction errors.
struct ErrorSum {
    SkyError e;
    double lsb_sum = 0;
    std::size_t n = 0;
    void add(const dvec3& reference, const dvec3* value, const dvec3& reference_display,
             const dvec3& display) {
        if (value != nullptr) {
            for (int c = 0; c < 3; ++c) {
                if (reference[c] > 0) {
                    e.max_relative = std::max(e.max_relative,
                                              std::abs((*value)[c] - reference[c]) / reference[c]);
                }
            }
        }
        const dvec3 d = glm::abs(display - reference_display);
        const double lsb = std::max({d.x, d.y, d.z});
        e.max_lsb = std::max(e.max_lsb, lsb);
        lsb_sum += lsb;
        ++n;
    }
    SkyError done() {
        e.mean_lsb = n > 0 ? lsb_sum / double(n) : 0.0;
        return e;
    }
};

}  // namespace

SkyError measure_sky_method(const SkyProbe& probe, const SkyContext& sky) {
    ErrorSum sum;
    for (std::size_t k = 0; k < probe.directions.size(); ++k) {
        const dvec3 value = sky_radiance(sky, probe.directions[k]);
        sum.add(probe.reference[k], &value, probe.reference_display[k],
                display_8bit(value, probe.exposure, probe.curve));
    }
    return sum.done();
}

SkyError measure_sky_dome(const SkyProbe& probe, const SkyContext& sky, const SkyDomeMesh& mesh) {
    const std::vector<dvec3> colours = shade_sky_dome(sky, mesh);
    std::vector<dvec3> display;
    for (const dvec3& c : colours) {
        display.push_back(quantised(display_8bit(c, probe.exposure, probe.curve)));
    }
    ErrorSum sum;
    for (std::size_t k = 0; k < probe.directions.size(); ++k) {
        const dvec3 d = probe.directions[k];
        // The triangle the ray from the centre goes through (Moller-Trumbore), and the
        // barycentric weights there: perspective-correct interpolation of the vertex colours.
        bool found = false;
        dvec3 value(0.0), shown(0.0);
        for (std::size_t t = 0; t + 2 < mesh.indices.size() && !found; t += 3) {
            const dvec3& a = mesh.directions[mesh.indices[t]];
            const dvec3& b = mesh.directions[mesh.indices[t + 1]];
            const dvec3& c = mesh.directions[mesh.indices[t + 2]];
            const dvec3 e1 = b - a, e2 = c - a;
            const dvec3 p = glm::cross(d, e2);
            const double det = glm::dot(e1, p);
            if (std::abs(det) < 1e-15) continue;
            const dvec3 q = -a;  // ray origin (0) minus a
            const double u = glm::dot(q, p) / det;
            const dvec3 r = glm::cross(q, e1);
            const double v = glm::dot(d, r) / det;
            const double dist = glm::dot(e2, r) / det;
            constexpr double kEdge = -1e-9;
            if (u < kEdge || v < kEdge || u + v > 1 - kEdge || dist <= 0) continue;
            const double w = 1 - u - v;
            const std::uint32_t ia = mesh.indices[t], ib = mesh.indices[t + 1],
                                ic = mesh.indices[t + 2];
            value = colours[ia] * w + colours[ib] * u + colours[ic] * v;
            shown = display[ia] * w + display[ib] * u + display[ic] * v;
            found = true;
        }
        if (!found) continue;  // below the lowest ring cannot happen for probe directions
        sum.add(probe.reference[k], &value, probe.reference_display[k], shown);
    }
    return sum.done();
}

SkyError measure_sky_cubemap(const SkyProbe& probe,
                             const std::array<std::vector<std::uint8_t>, 6>& faces, int size) {
    ErrorSum sum;
    for (std::size_t k = 0; k < probe.directions.size(); ++k) {
        sum.add(probe.reference[k], nullptr, probe.reference_display[k],
                sample_cubemap_rgba8(faces, size, probe.directions[k]));
    }
    return sum.done();
}

}  // namespace aerial::validation
