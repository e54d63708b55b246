// The built-in sky dome (per vertex, the 2002 model to a fitted virtual dome) and sun disc.
#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "aerial/gl_api.hpp"
#include "aerial/phase.hpp"
#include "aerial/scene_renderer.hpp"

namespace aerial::scene {
namespace {

constexpr int kDomeRings = 24;     ///< rings from 10° below the horizon to just below the zenith
constexpr int kDomeSegments = 40;  ///< vertices a ring (961 vertices with the zenith)
constexpr double kLowestElevationRad = -10.0 * kPi / 180.0;
constexpr int kSunRimVertices = 24;
/// The sun disc's colour is 1 - exp(-k T / max(T)) per channel (T: transmittance to the eye).
constexpr float kSunSaturation = 4.0f;
/// The eye may climb or sink this much (m) before the dome's fitted radii are recomputed.
constexpr double kRefitAltitudeM = 25.0;

/// Unit vectors spanning the plane perpendicular to `up`.
void horizontal_basis(const glm::dvec3& up, glm::dvec3& e1, glm::dvec3& e2) {
    e1 = glm::normalize(
        glm::cross(up, std::abs(up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    e2 = glm::cross(up, e1);
}

double eye_altitude_m(const SkyDrawContext& c) {
    const FrameSettings& s = *c.settings;
    return altitude_above_sphere<double>(c.camera->eye * s.meters_per_unit, s.up,
                                         s.atmosphere.planet_radius_m);
}

struct Dome {
    bool fitted = false;
    Atmosphere atmosphere;
    glm::dvec3 up{0.0};
    double altitude_m = 0.0;
    std::vector<double> ring_elevation_rad;
    std::vector<double> ring_distance_m;  ///< fitted virtual-dome radius of each ring
    std::vector<float> positions;
    std::vector<std::uint8_t> black, colours;
    std::vector<std::uint32_t> indices;

    void fit(const Atmosphere& a, const glm::dvec3& world_up, double altitude) {
        atmosphere = a;
        up = world_up;
        altitude_m = altitude;
        ring_elevation_rad.clear();
        ring_distance_m.clear();
        const double beta = a.extinction().g;
        for (int i = 0; i <= kDomeRings; ++i) {
            // Rings crowd towards the horizon, where the colour changes fastest.
            const double t = double(i) / kDomeRings;
            const double e =
                kLowestElevationRad + (kPi / 2 - kLowestElevationRad) * std::pow(t, 1.6);
            ring_elevation_rad.push_back(e);
            // The optical depth (green) of the exponential atmosphere from the eye to space;
            // below the horizon the horizon's (the ground hides those directions).
            const double cos_zenith = std::sin(std::max(0.0, e));
            const double transmittance =
                sun_transmittance(a, std::max(0.0, altitude), cos_zenith).g;
            const double tau = transmittance > 0.0 ? -std::log(transmittance) : 50.0;
            ring_distance_m.push_back(beta > 0.0 ? tau / beta : 0.0);
        }
        indices.clear();
        for (int i = 0; i + 1 < kDomeRings; ++i) {
            for (int j = 0; j < kDomeSegments; ++j) {
                const std::uint32_t a0 = std::uint32_t(i * kDomeSegments + j);
                const std::uint32_t a1 = std::uint32_t(i * kDomeSegments + (j + 1) % kDomeSegments);
                const std::uint32_t b0 = a0 + kDomeSegments, b1 = a1 + kDomeSegments;
                indices.insert(indices.end(), {a0, a1, b1, a0, b1, b0});
            }
        }
        const std::uint32_t apex = std::uint32_t(kDomeRings * kDomeSegments);
        for (int j = 0; j < kDomeSegments; ++j) {
            const std::uint32_t a0 = std::uint32_t((kDomeRings - 1) * kDomeSegments + j);
            const std::uint32_t a1 =
                std::uint32_t((kDomeRings - 1) * kDomeSegments + (j + 1) % kDomeSegments);
            indices.insert(indices.end(), {a0, a1, apex});
        }
        fitted = true;
    }

    bool needs_fit(const Atmosphere& a, const glm::dvec3& world_up, double altitude) const {
        if (!fitted || up != world_up || std::abs(altitude - altitude_m) > kRefitAltitudeM)
            return true;
        return a.rayleigh_scattering != atmosphere.rayleigh_scattering ||
               a.mie_scattering != atmosphere.mie_scattering ||
               a.mie_absorption != atmosphere.mie_absorption || a.mie_g != atmosphere.mie_g ||
               a.rayleigh_scale_height_m != atmosphere.rayleigh_scale_height_m ||
               a.mie_scale_height_m != atmosphere.mie_scale_height_m ||
               a.planet_radius_m != atmosphere.planet_radius_m ||
               a.atmosphere_radius_m != atmosphere.atmosphere_radius_m ||
               a.sun_irradiance != atmosphere.sun_irradiance;
    }
};

void draw_dome(Dome& dome, const SkyDrawContext& c) {
    const FrameSettings& s = *c.settings;
    const double altitude = eye_altitude_m(c);
    if (dome.needs_fit(s.atmosphere, s.up, altitude)) dome.fit(s.atmosphere, s.up, altitude);
    glm::dvec3 e1, e2;
    horizontal_basis(s.up, e1, e2);
    const double draw_radius = 0.5 * c.camera->far_units;
    const std::size_t n = std::size_t(kDomeRings * kDomeSegments + 1);
    dome.positions.resize(3 * n);
    dome.colours.assign(4 * n, 255);
    dome.black.assign(4 * n, 0);
    const Frame<float>& frame = *c.hoffman_preetham;
    const bool height = c.model != nullptr && c.model->model == Model::height;
    const double top = s.atmosphere.atmosphere_radius_m;
    const glm::dvec3 centre_to_eye =
        c.camera->eye * s.meters_per_unit + s.up * s.atmosphere.planet_radius_m;
    for (std::size_t v = 0; v < n; ++v) {
        const bool apex = v + 1 == n;
        const int ring = apex ? kDomeRings : int(v / kDomeSegments);
        const double e = dome.ring_elevation_rad[std::size_t(ring)];
        const double phi = apex ? 0.0 : 2.0 * kPi * double(v % kDomeSegments) / kDomeSegments;
        const glm::dvec3 dir =
            std::cos(e) * (std::cos(phi) * e1 + std::sin(phi) * e2) + std::sin(e) * s.up;
        const glm::dvec3 p = c.camera->eye + dir * draw_radius;
        dome.positions[3 * v] = float(p.x);
        dome.positions[3 * v + 1] = float(p.y);
        dome.positions[3 * v + 2] = float(p.z);
        glm::vec3 in_scattering;
        if (height) {
            // To the top of the atmosphere along the direction (the horizon's below it).
            const glm::dvec3 d =
                std::cos(std::max(0.0, e)) * (std::cos(phi) * e1 + std::sin(phi) * e2) +
                std::sin(std::max(0.0, e)) * s.up;
            const double b = glm::dot(centre_to_eye, d);
            const double c2 = glm::dot(centre_to_eye, centre_to_eye) - top * top;
            const double t = -b + std::sqrt(std::max(0.0, b * b - c2));
            const glm::dvec3 point = c.camera->eye + d * (t / s.meters_per_unit);
            in_scattering = scatter(*c.model, glm::vec3(point)).in_scattering;
        } else {
            in_scattering = hoffman_preetham_closed_form<float>(
                                frame, float(dome.ring_distance_m[std::size_t(ring)]),
                                float(glm::dot(dir, s.sun_dir)), frame.sun_irradiance_eye)
                                .in_scattering;
        }
        for (int ch = 0; ch < 3; ++ch) {
            dome.colours[4 * v + std::size_t(ch)] =
                to_unorm8(display_value(s.display, in_scattering[ch]));
        }
        dome.black[4 * v + 3] = 255;
    }
    gl::ApplyOptions apply = *c.apply;
    apply.textured = false;
    gl::VertexColours colours{dome.black.data(), dome.colours.data(), 0, 0, n};
    const gl::Api& api = *c.api;
    (void)gl::draw_with_colours(api, apply, colours, [&] {
        api.VertexPointer(3, GL_FLOAT, 0, dome.positions.data());
        api.DrawElements(GL_TRIANGLES, GLsizei(dome.indices.size()), GL_UNSIGNED_INT,
                         dome.indices.data());
    });
}

}  // namespace

SkyDrawer default_sky_drawer() {
    auto dome = std::make_shared<Dome>();
    return [dome](const SkyDrawContext& c) { draw_dome(*dome, c); };
}

SkyDrawer default_sun_drawer(double angular_radius_rad) {
    return [angular_radius_rad](const SkyDrawContext& c) {
        const FrameSettings& s = *c.settings;
        const double cos_zenith = glm::dot(s.sun_dir, s.up);
        const glm::dvec3 t =
            sun_transmittance(s.atmosphere, std::max(0.0, eye_altitude_m(c)), cos_zenith) *
            s.atmosphere.sun_irradiance;
        const double brightest = std::max(t.x, std::max(t.y, t.z));
        if (!(brightest > 0.0)) return;  // below the horizon
        const double distance = 0.49 * c.camera->far_units;
        const double radius = distance * std::tan(angular_radius_rad);
        glm::dvec3 e1 = glm::normalize(glm::cross(
            s.sun_dir, std::abs(s.sun_dir.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
        glm::dvec3 e2 = glm::cross(s.sun_dir, e1);
        const glm::dvec3 centre = c.camera->eye + s.sun_dir * distance;
        std::vector<float> positions{float(centre.x), float(centre.y), float(centre.z)};
        for (int i = 0; i < kSunRimVertices; ++i) {
            const double a = 2.0 * kPi * i / kSunRimVertices;
            const glm::dvec3 p = centre + radius * (std::cos(a) * e1 + std::sin(a) * e2);
            positions.insert(positions.end(), {float(p.x), float(p.y), float(p.z)});
        }
        std::vector<std::uint32_t> indices;
        for (int i = 0; i < kSunRimVertices; ++i) {
            indices.insert(indices.end(), {0u, std::uint32_t(1 + i),
                                           std::uint32_t(1 + (i + 1) % kSunRimVertices)});
        }
        const std::size_t n = positions.size() / 3;
        std::vector<std::uint8_t> colour(4 * n), black(4 * n, 0);
        for (std::size_t v = 0; v < n; ++v) {
            for (int ch = 0; ch < 3; ++ch) {
                // Far brighter than the sky: saturating, white at noon, yellow to orange low.
                colour[4 * v + std::size_t(ch)] =
                    to_unorm8(1.0f - std::exp(-kSunSaturation * float(t[ch] / brightest)));
            }
            colour[4 * v + 3] = 255;
        }
        gl::ApplyOptions apply = *c.apply;
        apply.textured = false;
        gl::VertexColours colours{colour.data(), black.data(), 0, 0, n};
        const gl::Api& api = *c.api;
        (void)gl::draw_with_colours(api, apply, colours, [&] {
            api.VertexPointer(3, GL_FLOAT, 0, positions.data());
            api.DrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT,
                             indices.data());
        });
    };
}

}  // namespace aerial::scene
