#include "adaptive_sky.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/trigonometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/mesh.hpp"

namespace sample {
namespace {

// Beyond the atmosphere overhead and a long path near the horizon, close to the renderer's own
// dome (which shades each direction to the top of the atmosphere).
constexpr double kDomeRadiusM = 400000.0;
constexpr int kMorphUpdates = 8;
/// The skirt below the open horizon of the dome: a ring down to this depression, then a fan to
/// the nadir. Without it the eye, above the terrain, sees past the terrain's edge below the
/// horizontal plane, where nothing was drawn (a black band of up to 6.5 % of the image).
constexpr double kSkirtDepressionDeg = 30.0;

struct AdaptiveSky {
    std::optional<aerial::mesh::AdaptiveMesh> mesh;
    glm::dvec3 centre{0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    aerial::Display display;
    std::shared_ptr<AdaptiveSkyStats> stats;
    std::vector<float> shade_positions, draw_positions;
    std::vector<std::uint8_t> primary, secondary;
    std::vector<std::uint32_t> indices;
};

/// Appends the skirt (kSkirtDepressionDeg) to the drawn arrays: for every horizon vertex of the
/// dome a vertex straight below it at that depression with the horizon vertex's colour (the
/// renderer's dome shows the horizon's colour below the horizon too), two triangles per horizon
/// edge, and a fan from that ring to the nadir in the mean horizon colour. The triangles follow
/// the dome's winding: each crosses its horizon edge in the direction the dome's face does not.
void add_skirt(AdaptiveSky& sky, const aerial::mesh::Mesh& mesh, const glm::dvec3& eye,
               double radius) {
    const std::size_t n = mesh.n_vertices();
    const double depression = glm::radians(kSkirtDepressionDeg);
    std::vector<std::uint32_t> below(n, UINT32_MAX);
    std::uint32_t next = std::uint32_t(n);
    glm::dvec3 mean_colour(0.0);
    std::size_t ring = 0;
    auto skirt_vertex = [&](aerial::mesh::Mesh::VertexHandle v) {
        std::uint32_t& b = below[std::size_t(v.idx())];
        if (b != UINT32_MAX) return b;
        b = next++;
        const auto& p = mesh.point(v);
        glm::dvec3 d = glm::dvec3(p[0], p[1], p[2]) - sky.centre;
        d -= glm::dot(d, sky.up) * sky.up;
        const double length = glm::length(d);
        const glm::dvec3 h = length > 0.0 ? d / length : glm::dvec3(0.0);
        const glm::dvec3 x =
            eye + radius * (std::cos(depression) * h - std::sin(depression) * sky.up);
        for (int k = 0; k < 3; ++k) sky.draw_positions.push_back(float(x[k]));
        const std::size_t from = 4 * std::size_t(v.idx());
        for (int k = 0; k < 4; ++k) {
            const std::uint8_t primary = sky.primary[from + std::size_t(k)];
            const std::uint8_t secondary = sky.secondary[from + std::size_t(k)];
            sky.primary.push_back(primary);
            sky.secondary.push_back(secondary);
            if (k < 3) mean_colour[k] += secondary;
        }
        ++ring;
        return b;
    };
    std::vector<std::array<std::uint32_t, 2>> edges;
    for (const auto h : mesh.halfedges()) {
        if (mesh.status(mesh.edge_handle(h)).deleted() || !mesh.is_boundary(h)) continue;
        // The boundary halfedge runs a -> b; the dome's face crosses the edge from b to a.
        const auto a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
        const std::uint32_t a_below = skirt_vertex(a), b_below = skirt_vertex(b);
        const std::uint32_t ia = std::uint32_t(a.idx()), ib = std::uint32_t(b.idx());
        sky.indices.insert(sky.indices.end(), {ia, ib, b_below, ia, b_below, a_below});
        edges.push_back({a_below, b_below});
    }
    if (ring == 0) return;
    const std::uint32_t nadir = next;
    const glm::dvec3 x = eye - radius * sky.up;
    for (int k = 0; k < 3; ++k) sky.draw_positions.push_back(float(x[k]));
    for (int k = 0; k < 3; ++k)
        sky.secondary.push_back(std::uint8_t(mean_colour[k] / double(ring) + 0.5));
    sky.secondary.push_back(255);
    sky.primary.insert(sky.primary.end(), {0, 0, 0, 255});
    for (const auto& e : edges) sky.indices.insert(sky.indices.end(), {e[0], e[1], nadir});
}

void draw_adaptive_sky(AdaptiveSky& sky, const aerial::scene::SkyDrawContext& c) {
    const aerial::scene::FrameSettings& s = *c.settings;
    // The sky depends on the eye's altitude and the sun: shade around (0, 0, altitude).
    aerial::View view;
    view.eye = s.up * glm::dot(c.camera->eye, s.up) * s.meters_per_unit;
    view.sun_dir = s.sun_dir;
    view.up = s.up;
    auto frame = aerial::prepare_frame<float>(s.atmosphere, view, aerial::Model::height);
    if (!frame) {
        sky.stats->error = frame.error().message;
        return;
    }
    const bool display_changed =
        s.display.exposure != sky.display.exposure || s.display.tone != sky.display.tone;
    if (!sky.mesh) {
        aerial::mesh::DomeOptions dome;
        dome.centre = view.eye;
        dome.up = s.up;
        dome.radius_m = kDomeRadiusM;
        auto base = aerial::mesh::geodesic_dome(4, dome);
        if (!base) {
            sky.stats->error = base.error().message;
            return;
        }
        aerial::mesh::AdaptiveSettings settings;
        settings.colour.texel = glm::vec3(0.0f);
        settings.colour.display = s.display;
        settings.lock_boundary = false;
        settings.morph_updates = kMorphUpdates;
        settings.max_vertices = 20000;
        settings.time_slice_ms = 4.0;
        auto made = aerial::mesh::AdaptiveMesh::create(
            std::move(base.value()), aerial::mesh::Surface::sphere(dome), settings);
        if (!made) {
            sky.stats->error = made.error().message;
            return;
        }
        sky.mesh.emplace(std::move(made.value()));
        sky.centre = dome.centre;
        sky.up = dome.up;
    } else if (display_changed) {
        // The exposure follows the sun: the colours the refinement measured are stale.
        sky.mesh->invalidate();
    }
    sky.display = s.display;
    const auto start = std::chrono::steady_clock::now();
    sky.mesh->update(*frame);
    sky.stats->update_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const aerial::mesh::Mesh& mesh = sky.mesh->mesh();
    sky.stats->vertices = aerial::mesh::live_vertices(mesh);

    // Shade every vertex (deleted ones too: their slots keep the arrays indexed by handle),
    // morph, and draw around the real eye at half the far plane.
    const std::size_t n = mesh.n_vertices();
    const double scale = 0.5 * c.camera->far_units / kDomeRadiusM;
    sky.shade_positions.resize(3 * n);
    sky.draw_positions.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& p = mesh.point(aerial::mesh::Mesh::VertexHandle(int(i)));
        const glm::dvec3 d = glm::dvec3(p[0], p[1], p[2]) - sky.centre;
        for (int k = 0; k < 3; ++k) {
            sky.shade_positions[3 * i + std::size_t(k)] = float(p[k]);
            sky.draw_positions[3 * i + std::size_t(k)] = float(c.camera->eye[k] + scale * d[k]);
        }
    }
    sky.primary.assign(4 * n, 0);
    for (std::size_t i = 0; i < n; ++i) sky.primary[4 * i + 3] = 255;
    sky.secondary.assign(4 * n, 0);
    aerial::BatchOutputs out;
    out.in_scattering_rgba8 = sky.secondary.data();
    aerial::BatchSettings settings;
    settings.display = s.display;
    if (auto shaded = aerial::shade_into(
            *frame, aerial::Positions::aos(sky.shade_positions.data(), n), out, settings);
        !shaded) {
        sky.stats->error = shaded.error().message;
        return;
    }
    sky.mesh->morph_into(sky.secondary.data(), 3, 4);
    sky.indices.clear();
    for (const auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        for (const auto v : mesh.fv_range(f)) sky.indices.push_back(std::uint32_t(v.idx()));
    }
    add_skirt(sky, mesh, c.camera->eye, scale * kDomeRadiusM);
    const std::size_t drawn_vertices = sky.draw_positions.size() / 3;
    aerial::gl::VertexColours colours;
    colours.primary = sky.primary.data();
    colours.secondary = sky.secondary.data();
    colours.vertex_count = drawn_vertices;
    const aerial::gl::Api& api = *c.api;
    aerial::gl::ApplyOptions apply = *c.apply;
    apply.textured = false;  // the colour is the black primary plus L_in
    auto drawn = aerial::gl::draw_with_colours(api, apply, colours, [&] {
        api.VertexPointer(3, GL_FLOAT, 0, sky.draw_positions.data());
        api.DrawElements(GL_TRIANGLES, GLsizei(sky.indices.size()), GL_UNSIGNED_INT,
                         sky.indices.data());
    });
    if (!drawn) sky.stats->error = drawn.error().message;
}

}  // namespace

aerial::scene::SkyDrawer adaptive_sky_drawer(std::shared_ptr<AdaptiveSkyStats> stats) {
    auto sky = std::make_shared<AdaptiveSky>();
    sky->stats = std::move(stats);
    return [sky](const aerial::scene::SkyDrawContext& c) { draw_adaptive_sky(*sky, c); };
}

}  // namespace sample
