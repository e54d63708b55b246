// The adaptive sky dome (aerial/adaptive_scene.hpp): a geodesic dome refined where its colour
// needs vertices, shaded with the height model, morphed, drawn around the eye with a skirt.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/trigonometric.hpp>

#include "aerial/adaptive_scene.hpp"
#include "aerial/batch.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"

namespace aerial::scene {
namespace {

struct AdaptiveSky {
    AdaptiveSkyOptions options;
    std::optional<mesh::AdaptiveMesh> mesh;
    glm::dvec3 centre{0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    Display display;
    std::shared_ptr<AdaptiveSkyStats> stats;
    std::vector<float> shade_positions, draw_positions;
    std::vector<std::uint8_t> primary, secondary;
    std::vector<std::uint32_t> indices;
};

/// Appends the skirt (options.skirt_depression_deg) to the drawn arrays: for every horizon vertex
/// of the dome a vertex straight below it at that depression with the horizon vertex's colour (the
/// renderer's dome shows the horizon's colour below the horizon too), two triangles per horizon
/// edge, and a fan from that ring to the nadir in the mean horizon colour. The triangles follow
/// the dome's winding: each crosses its horizon edge in the direction the dome's face does not.
void add_skirt(AdaptiveSky& sky, const mesh::Mesh& mesh, const glm::dvec3& eye, double radius) {
    const std::size_t n = mesh.n_vertices();
    const double depression = glm::radians(sky.options.skirt_depression_deg);
    std::vector<std::uint32_t> below(n, UINT32_MAX);
    std::uint32_t next = std::uint32_t(n);
    glm::dvec3 mean_colour(0.0);
    std::size_t ring = 0;
    auto skirt_vertex = [&](mesh::Mesh::VertexHandle v) {
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

/// The sky's frame for one light: the sky depends on the eye's altitude and the light, so it is
/// shaded around (0, 0, altitude).
Result<Frame<float>> sky_frame(const SkyDrawContext& c, const FrameSettings& light) {
    View view;
    view.eye = light.up * glm::dot(c.camera->eye, light.up) * light.meters_per_unit;
    view.sun_dir = light.sun_dir;
    view.up = light.up;
    return prepare_frame<float>(light.atmosphere, view, Model::height);
}

/// L_in of the dome's vertices as RGBA8 into sky.secondary: one light's straight from
/// shade_into, or the sum of each light's floats (SkyDrawContext::lights) then the display.
std::optional<Error> shade_sky(AdaptiveSky& sky, const SkyDrawContext& c, const Frame<float>& first,
                               std::size_t n) {
    const Positions positions = Positions::aos(sky.shade_positions.data(), n);
    BatchSettings settings;
    settings.display = c.settings->display;
    BatchOutputs out;
    if (c.lights.size() < 2) {
        out.in_scattering_rgba8 = sky.secondary.data();
        auto shaded = shade_into(first, positions, out, settings);
        return shaded ? std::nullopt : std::optional<Error>(shaded.error());
    }
    std::vector<float> sum(3 * n, 0.0f), light(3 * n);
    out.in_scattering_rgb = light.data();
    for (std::size_t i = 0; i < c.lights.size(); ++i) {
        auto frame = i == 0 ? Result<Frame<float>>(first) : sky_frame(c, *c.lights[i]);
        if (!frame) return frame.error();
        auto shaded = shade_into(*frame, positions, out, settings);
        if (!shaded) return shaded.error();
        for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += light[k];
    }
    for (std::size_t v = 0; v < n; ++v) {
        for (std::size_t k = 0; k < 3; ++k) {
            sky.secondary[4 * v + k] = to_unorm8(display_value(settings.display, sum[3 * v + k]));
        }
        sky.secondary[4 * v + 3] = 255;
    }
    return std::nullopt;
}

void draw_adaptive_sky(AdaptiveSky& sky, const SkyDrawContext& c) {
    const FrameSettings& s = *c.settings;
    // Refined for the frame's first light (the brighter: the moon's at night).
    auto frame = sky_frame(c, c.lights.empty() ? s : *c.lights.front());
    if (!frame) {
        sky.stats->error = frame.error().message;
        return;
    }
    const bool display_changed =
        s.display.exposure != sky.display.exposure || s.display.tone != sky.display.tone;
    if (!sky.mesh) {
        const double skirt = sky.options.skirt_depression_deg;
        if (!(skirt >= 0.0 && skirt <= 90.0)) {
            sky.stats->error =
                "skirt_depression_deg: expected a value in [0, 90], got " + std::to_string(skirt);
            return;
        }
        mesh::DomeOptions dome;
        dome.centre = frame->view.eye;
        dome.up = s.up;
        dome.radius_m = sky.options.radius_m;
        auto base = mesh::geodesic_dome(sky.options.base_frequency, dome);
        if (!base) {
            sky.stats->error = base.error().message;
            return;
        }
        mesh::AdaptiveSettings settings;
        settings.colour.texel = glm::vec3(0.0f);
        settings.colour.display = s.display;
        settings.split_lsb = sky.options.split_lsb;
        settings.lock_boundary = false;
        settings.morph_updates = sky.options.morph_updates;
        settings.max_vertices = sky.options.max_vertices;
        settings.time_slice_ms = sky.options.time_slice_ms;
        auto made = mesh::AdaptiveMesh::create(std::move(base.value()), mesh::Surface::sphere(dome),
                                               settings);
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
    const mesh::Mesh& mesh = sky.mesh->mesh();
    sky.stats->vertices = mesh::live_vertices(mesh);

    // Shade every vertex (deleted ones too: their slots keep the arrays indexed by handle),
    // morph, and draw around the real eye at half the far plane.
    const std::size_t n = mesh.n_vertices();
    const double scale = 0.5 * c.camera->far_units / sky.options.radius_m;
    sky.shade_positions.resize(3 * n);
    sky.draw_positions.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto& p = mesh.point(mesh::Mesh::VertexHandle(int(i)));
        const glm::dvec3 d = glm::dvec3(p[0], p[1], p[2]) - sky.centre;
        for (int k = 0; k < 3; ++k) {
            sky.shade_positions[3 * i + std::size_t(k)] = float(p[k]);
            sky.draw_positions[3 * i + std::size_t(k)] = float(c.camera->eye[k] + scale * d[k]);
        }
    }
    sky.primary.assign(4 * n, 0);
    for (std::size_t i = 0; i < n; ++i) sky.primary[4 * i + 3] = 255;
    sky.secondary.assign(4 * n, 0);
    if (auto e = shade_sky(sky, c, *frame, n)) {
        sky.stats->error = e->message;
        return;
    }
    sky.mesh->morph_into(sky.secondary.data(), 3, 4);
    sky.indices.clear();
    for (const auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        for (const auto v : mesh.fv_range(f)) sky.indices.push_back(std::uint32_t(v.idx()));
    }
    add_skirt(sky, mesh, c.camera->eye, scale * sky.options.radius_m);
    const std::size_t drawn_vertices = sky.draw_positions.size() / 3;
    gl::VertexColours colours;
    colours.primary = sky.primary.data();
    colours.secondary = sky.secondary.data();
    colours.vertex_count = drawn_vertices;
    const gl::Api& api = *c.api;
    gl::ApplyOptions apply = *c.apply;
    apply.textured = false;  // the colour is the black primary plus L_in
    auto drawn = gl::draw_with_colours(api, apply, colours, [&] {
        api.VertexPointer(3, GL_FLOAT, 0, sky.draw_positions.data());
        api.DrawElements(GL_TRIANGLES, GLsizei(sky.indices.size()), GL_UNSIGNED_INT,
                         sky.indices.data());
    });
    if (!drawn) sky.stats->error = drawn.error().message;
}

}  // namespace

SkyDrawer adaptive_sky_drawer(const AdaptiveSkyOptions& options,
                              std::shared_ptr<AdaptiveSkyStats> stats) {
    auto sky = std::make_shared<AdaptiveSky>();
    sky->options = options;
    sky->stats = stats ? std::move(stats) : std::make_shared<AdaptiveSkyStats>();
    return [sky](const SkyDrawContext& c) { draw_adaptive_sky(*sky, c); };
}

}  // namespace aerial::scene
