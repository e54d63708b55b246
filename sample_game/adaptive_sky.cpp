#include "adaptive_sky.hpp"

#include <chrono>
#include <optional>
#include <vector>

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

struct AdaptiveSky {
    std::optional<aerial::mesh::AdaptiveMesh> mesh;
    glm::dvec3 centre{0.0};
    aerial::Display display;
    std::shared_ptr<AdaptiveSkyStats> stats;
    std::vector<float> shade_positions, draw_positions;
    std::vector<std::uint8_t> primary, secondary;
    std::vector<std::uint32_t> indices;
};

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
    aerial::gl::VertexColours colours;
    colours.primary = sky.primary.data();
    colours.secondary = sky.secondary.data();
    colours.vertex_count = n;
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
