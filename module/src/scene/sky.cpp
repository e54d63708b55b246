// The scene's built-in sky dome (the core sky of aerial/sky.hpp, drawn per vertex) and sun disc.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/phase.hpp"
#include "aerial/scene_renderer.hpp"
#include "frame_plan.hpp"
#include "sky_dome.hpp"

namespace aerial::scene {
namespace detail {

SkyMethod dome_method(Model model) {
    return model == Model::height ? SkyMethod::dome_height : SkyMethod::dome_hp;
}

Result<bool> SkyDome::update_mesh(const glm::dvec3& up) {
    if (!directions_.empty() && mesh_up_ == up) return false;
    auto mesh = make_sky_dome_mesh(rings_, segments_, up);
    if (!mesh) return aerial::detail::from(kRender, mesh.error());
    mesh_ = std::move(mesh).value();
    mesh_up_ = up;
    directions_ = mesh_.directions;
    indices_ = mesh_.indices;
    // The skirt: one ring below ring 0 (whose directions are horizontal), joined to it.
    const std::uint32_t skirt = std::uint32_t(directions_.size());
    for (int s = 0; s < segments_; ++s) {
        directions_.push_back(std::cos(kSkirtElevationRad) * mesh_.directions[std::size_t(s)] +
                              std::sin(kSkirtElevationRad) * up);
    }
    const auto ring0 = [&](int s) { return std::uint32_t(s % segments_); };
    const auto below = [&](int s) { return skirt + std::uint32_t(s % segments_); };
    for (int s = 0; s < segments_; ++s) {
        indices_.insert(indices_.end(), {below(s), ring0(s + 1), below(s + 1)});
        indices_.insert(indices_.end(), {below(s), ring0(s), ring0(s + 1)});
    }
    return true;
}

Result<bool> SkyDome::update_fit(const Atmosphere& atmosphere, double eye_altitude_m) {
    if (fitted_ && atmosphere == fit_atmosphere_ &&
        std::abs(eye_altitude_m - fit_altitude_m_) <= kRefitAltitudeM) {
        return false;
    }
    auto fit = fit_virtual_dome(atmosphere, eye_altitude_m);
    if (!fit) return aerial::detail::from(kRender, fit.error());
    fit_ = std::move(fit).value();
    fit_atmosphere_ = atmosphere;
    fit_altitude_m_ = eye_altitude_m;
    fitted_ = true;
    ++fits_;
    return true;
}

Result<SkyContext> SkyDome::prepare(const FrameSettings& settings, const glm::dvec3& eye) {
    const double up_length = glm::length(settings.up);
    if (!(up_length > 0.0) || !std::isfinite(up_length)) {
        return aerial::detail::invalid(kRender, "up", "a finite non-zero vector",
                                       aerial::detail::vector(settings.up));
    }
    const glm::dvec3 up = settings.up / up_length;
    if (auto mesh = update_mesh(up); !mesh) return mesh.error();
    View view;
    view.eye = eye;
    view.sun_dir = settings.sun_dir;
    view.up = up;
    view.meters_per_unit = settings.meters_per_unit;
    const SkyMethod method = dome_method(settings.model);
    SkyOptions options;
    if (method == SkyMethod::dome_hp) {
        // The altitude prepare_sky finds for the same view.
        const double altitude = altitude_above_sphere(eye * settings.meters_per_unit, up,
                                                      settings.atmosphere.planet_radius_m);
        if (auto fit = update_fit(settings.atmosphere, altitude); !fit) return fit.error();
        options.dome = &fit_;
    }
    auto sky = prepare_sky(settings.atmosphere, view, method, options);
    if (!sky) return aerial::detail::from(kRender, sky.error());
    return sky;
}

std::vector<glm::dvec3> SkyDome::radiance(const SkyContext& sky) const {
    std::vector<glm::dvec3> radiance = shade_sky_dome(sky, mesh_);
    // The skirt (after the mesh's vertices) repeats ring 0, whose vertices come first.
    const std::size_t mesh_vertices = radiance.size();
    for (std::size_t v = mesh_vertices; v < directions_.size(); ++v) {
        radiance.push_back(radiance[v - mesh_vertices]);
    }
    return radiance;
}

const std::vector<std::uint8_t>& SkyDome::encode(const std::vector<glm::dvec3>& radiance,
                                                 const Display& display) {
    colours_.assign(4 * radiance.size(), 255);
    for (std::size_t v = 0; v < radiance.size(); ++v) {
        for (int ch = 0; ch < 3; ++ch) {
            colours_[4 * v + std::size_t(ch)] =
                to_unorm8(display_value(display, float(radiance[v][ch])));
        }
    }
    return colours_;
}

}  // namespace detail

namespace {

constexpr int kSunRimVertices = 24;
/// The sun disc's colour is 1 - exp(-k T / max(T)) per channel (T: transmittance to the eye).
constexpr float kSunSaturation = 4.0f;

double eye_altitude_m(const SkyDrawContext& c) {
    const FrameSettings& s = *c.settings;
    return altitude_above_sphere<double>(c.camera->eye * s.meters_per_unit, s.up,
                                         s.atmosphere.planet_radius_m);
}

/// The dome's buffers between frames: a dome per light (each keeps its own fit).
struct DomeDrawer {
    std::array<detail::SkyDome, 2> domes{detail::SkyDome{kSkyDomeRings, kSkyDomeSegments},
                                         detail::SkyDome{kSkyDomeRings, kSkyDomeSegments}};
    std::vector<float> positions;
    std::vector<std::uint8_t> black;
};

void draw_dome(DomeDrawer& d, const SkyDrawContext& c) {
    const FrameSettings& s = *c.settings;
    // The sum of the lights' skies. render() has checked the same settings and camera: an
    // error here draws no sky.
    const std::vector<const FrameSettings*> lights =
        c.lights.empty() ? std::vector<const FrameSettings*>{c.settings} : c.lights;
    std::vector<glm::dvec3> radiance;
    for (std::size_t i = 0; i < lights.size() && i < d.domes.size(); ++i) {
        auto sky = d.domes[i].prepare(*lights[i], c.camera->eye);
        if (!sky) return;
        const std::vector<glm::dvec3> light = d.domes[i].radiance(*sky);
        if (radiance.empty()) radiance.assign(light.size(), glm::dvec3(0.0));
        for (std::size_t v = 0; v < light.size(); ++v) radiance[v] += light[v];
    }
    detail::SkyDome& dome = d.domes[0];
    const std::vector<std::uint8_t>& colours = dome.encode(radiance, s.display);
    const std::vector<glm::dvec3>& directions = dome.directions();
    const std::size_t n = directions.size();
    const double draw_radius = 0.5 * c.camera->far_units;
    d.positions.resize(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        const glm::dvec3 p = c.camera->eye + directions[v] * draw_radius;
        d.positions[3 * v] = float(p.x);
        d.positions[3 * v + 1] = float(p.y);
        d.positions[3 * v + 2] = float(p.z);
    }
    d.black.assign(4 * n, 0);
    for (std::size_t v = 0; v < n; ++v) d.black[4 * v + 3] = 255;
    gl::ApplyOptions apply = *c.apply;
    apply.textured = false;
    gl::VertexColours vertex_colours{d.black.data(), colours.data(), 0, 0, n};
    const gl::Api& api = *c.api;
    const std::vector<std::uint32_t>& indices = dome.indices();
    (void)gl::draw_with_colours(api, apply, vertex_colours, [&] {
        api.VertexPointer(3, GL_FLOAT, 0, d.positions.data());
        api.DrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT, indices.data());
    });
}

}  // namespace

SkyDrawer default_sky_drawer() {
    auto dome = std::make_shared<DomeDrawer>();
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
