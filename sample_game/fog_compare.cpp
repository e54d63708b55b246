// The flythrough against GL fog only: see fog_compare.hpp.
#include "fog_compare.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <vector>

#include "aerial/validation/scene_render.hpp"

namespace sample {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// What an engine without aerial draws: the terrain with its texture and lighting, GL_FOG (EXP)
/// of the atmosphere's extinction at the eye in the haze colour, the sky cleared to that colour.
/// Returns its milliseconds from the fog's set-up to glFinish.
aerial::Result<double> render_fog_frame(const aerial::gl::Api& api,
                                        aerial::scene::SceneRenderer& renderer, const World& world,
                                        const FlightState& state, const GameConfig& config) {
    const aerial::scene::Camera camera =
        camera_for(world, state, double(config.width) / double(config.height));
    auto settings =
        settings_for(state, config.preset, config.model, aerial::ToneCurve::exponential);
    if (!settings) return settings.error();
    api.Viewport(0, 0, config.width, config.height);
    const auto start = Clock::now();
    aerial::View view;
    view.eye = camera.eye;
    view.sun_dir = settings->sun_dir;
    auto frame = aerial::prepare_frame<float>(settings->atmosphere, view, aerial::Model::height,
                                              aerial::FrameOptions{false});
    if (!frame) return frame.error();
    const auto fog = aerial::validation::fog_parameters(*frame, settings->display);
    api.ClearColor(fog.colour[0], fog.colour[1], fog.colour[2], 1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    api.Fogi(GL_FOG_MODE, GL_EXP);
    api.Fogf(GL_FOG_DENSITY, fog.density);
    api.Fogfv(GL_FOG_COLOR, fog.colour);
    api.Enable(GL_FOG);
    auto report = renderer.render(*world.root, camera, *settings);
    api.Disable(GL_FOG);
    if (!report) return report.error();
    api.Finish();
    return ms_since(start);
}

/// One frame's figures; times are the fastest over the rounds.
struct Row {
    double t = 0, sun_deg = 0;
    bool fog_layer = false;
    double aerial_ms = 1e300, fog_ms = 1e300, still_aerial_ms = 1e300, still_fog_ms = 1e300;
    std::size_t drawn = 0, shaded = 0, still_shaded = 0;
    int directions = 0, still_directions = 0;
    double shading_ms = 1e300, sky_ms = 1e300;  ///< of the moving aerial frame
};

/// One flight with fresh renderers (nothing cached from an earlier round).
std::optional<aerial::Error> fly_round(const aerial::gl::Api& api, const World& world,
                                       const GameConfig& config, std::vector<Row>& rows) {
    auto made = make_game_renderer(api, config);
    if (!made) return made.error();
    GameRenderer& game = made.value();
    const SkySetup* sky = &game.sky;
    aerial::scene::RendererOptions fog_options;
    fog_options.backend = aerial::scene::Backend::none;
    auto fog = aerial::scene::SceneRenderer::create(api, fog_options);
    if (!fog) return fog.error();
    fog.value().set_sky_drawer([](const aerial::scene::SkyDrawContext&) {});
    fog.value().set_sun_drawer([](const aerial::scene::SkyDrawContext&) {});
    const auto directions = [&] { return sky->stats ? sky->stats->directions_last_frame : 0; };
    const int frames = int(rows.size());
    for (int i = 0; i < frames; ++i) {
        Row& row = rows[std::size_t(i)];
        row.t = frames == 1 ? 0.0 : double(i) / double(frames - 1);
        const FlightState state = flight_at(world, row.t, config.sun);
        auto moving = render_frame(api, game, world, state, config);
        if (!moving) return moving.error();
        row.directions = directions();
        const double sky_ms = sky->stats ? sky->stats->last_refresh_ms : 0.0;
        auto fog_moving = render_fog_frame(api, fog.value(), world, state, config);
        if (!fog_moving) return fog_moving.error();
        auto still = render_frame(api, game, world, state, config);
        if (!still) return still.error();
        row.still_directions = directions();
        auto fog_still = render_fog_frame(api, fog.value(), world, state, config);
        if (!fog_still) return fog_still.error();
        if (sky->stats && !sky->stats->error.empty())
            return aerial::Error{"sky", "run_fog_compare(): " + sky->stats->error};
        row.sun_deg = state.sun_elevation_rad * 180.0 / 3.14159265358979323846;
        row.fog_layer = state.fog;
        if (moving->milliseconds < row.aerial_ms) {
            row.shading_ms = moving->report.shading_milliseconds;
            row.sky_ms = sky_ms;
        }
        row.aerial_ms = std::min(row.aerial_ms, moving->milliseconds);
        row.fog_ms = std::min(row.fog_ms, *fog_moving);
        row.still_aerial_ms = std::min(row.still_aerial_ms, still->milliseconds);
        row.still_fog_ms = std::min(row.still_fog_ms, *fog_still);
        row.drawn = moving->report.vertices_drawn;
        row.shaded = moving->report.vertices_shaded;
        row.still_shaded = still->report.vertices_shaded;
    }
    return std::nullopt;
}

}  // namespace

aerial::Result<FogCompareSummary> run_fog_compare(const aerial::gl::Api& api, const World& world,
                                                  const GameConfig& config, int frames, int rounds,
                                                  const std::string& csv_path) {
    std::ofstream csv(csv_path);
    if (!csv) return aerial::Error{"csv_path", "run_fog_compare(): cannot write " + csv_path};
    std::vector<Row> rows(std::size_t(std::max(frames, 1)));
    for (int r = 0; r < rounds; ++r) {
        if (auto e = fly_round(api, world, config, rows)) return *e;
    }
    csv << "frame,t,sun_elevation_deg,fog_layer,aerial_ms,fog_ms,ratio,still_aerial_ms,"
           "still_fog_ms,still_ratio,vertices_drawn,vertices_shaded,still_vertices_shaded,"
           "sky_directions,still_sky_directions,shading_ms,sky_ms\n";
    FogCompareSummary sum;
    sum.rounds = rounds;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        char line[512];
        std::snprintf(
            line, sizeof line,
            "%zu,%.4f,%.2f,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%zu,%zu,%zu,%d,%d,%.3f,%.3f\n", i, r.t,
            r.sun_deg, r.fog_layer ? 1 : 0, r.aerial_ms, r.fog_ms, r.aerial_ms / r.fog_ms,
            r.still_aerial_ms, r.still_fog_ms, r.still_aerial_ms / r.still_fog_ms, r.drawn,
            r.shaded, r.still_shaded, r.directions, r.still_directions, r.shading_ms, r.sky_ms);
        csv << line;
        if (i == 0) continue;
        ++sum.frames;
        sum.aerial_ms += r.aerial_ms;
        sum.fog_ms += r.fog_ms;
        sum.still_aerial_ms += r.still_aerial_ms;
        sum.still_fog_ms += r.still_fog_ms;
    }
    if (sum.frames > 0) {
        const double n = sum.frames;
        sum.aerial_ms /= n;
        sum.fog_ms /= n;
        sum.still_aerial_ms /= n;
        sum.still_fog_ms /= n;
    }
    return sum;
}

}  // namespace sample
