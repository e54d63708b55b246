#include "game.hpp"

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "font.hpp"

namespace sample {
namespace {

std::string upper(std::string s) {
    for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace

const char* sky_name(SkyKind sky) { return sky == SkyKind::dome ? "dome" : "cubemap"; }

aerial::Result<SkySetup> install_sky(aerial::scene::SceneRenderer& renderer,
                                     const aerial::gl::Api& api, const GameConfig& config) {
    SkySetup setup;
    if (config.sky == SkyKind::dome) return setup;
    aerial::scene::CubemapSkyOptions options;
    options.cache.size = config.cube_size;
    auto stats = aerial::scene::install_cubemap_sky(renderer, api, options);
    if (!stats) {
        if (stats.error().field == "cube_map") return setup;  // GL 1.1: the dome
        return stats.error();
    }
    setup.used = SkyKind::cubemap;
    setup.stats = *stats;
    return setup;
}

aerial::Result<GameRenderer> make_game_renderer(const aerial::gl::Api& api,
                                                const GameConfig& config) {
    aerial::scene::RendererOptions options;
    options.backend = config.backend;
    options.path = config.path;
    auto renderer = aerial::scene::SceneRenderer::create(api, options);
    if (!renderer) return renderer.error();
    auto sky = install_sky(renderer.value(), api, config);
    if (!sky) return sky.error();
    return GameRenderer{std::move(renderer).value(), *sky};
}

std::string clock_text(double hours) {
    const int minutes = int(std::lround(hours * 60.0));
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "%02d:%02d", (minutes / 60) % 24, minutes % 60);
    return buffer;
}

aerial::Result<FrameOutcome> render_frame(const aerial::gl::Api& api,
                                          aerial::scene::SceneRenderer& renderer,
                                          const World& world, const FlightState& state,
                                          const GameConfig& config) {
    const aerial::scene::Camera camera =
        camera_for(world, state, double(config.width) / double(config.height));
    auto settings =
        settings_for(state, config.preset, config.model,
                     config.backend == aerial::scene::Backend::cpu ? aerial::ToneCurve::exponential
                                                                   : aerial::ToneCurve::clamp);
    if (!settings) return settings.error();
    settings.value().policy = config.policy;
    settings.value().error_target_lsb = config.error_target_lsb;

    api.Viewport(0, 0, config.width, config.height);
    api.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const auto start = std::chrono::steady_clock::now();
    auto report = renderer.render(*world.root, camera, *settings);
    if (!report) return report.error();
    api.Finish();
    FrameOutcome outcome;
    outcome.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    outcome.report = *report;
    outcome.settings = *settings;
    if (config.readout) {
        const int scale = std::max(1, config.height / 270);
        const double ms = outcome.milliseconds;
        char line[160];
        std::snprintf(line, sizeof line, "FPS %.1f (%.0f MS, SHADING %.1f MS)  %s", 1000.0 / ms, ms,
                      report->shading_milliseconds,
                      upper(state.fog ? config.preset + "+FOG" : config.preset).c_str());
        draw_text(api, config.width, config.height, 4 * scale, 4 * scale, scale, line);
        std::snprintf(line, sizeof line, "SOLAR TIME %s  SUN %.1f DEG  AZIMUTH %.0f DEG",
                      clock_text(state.clock_hours).c_str(),
                      state.sun_elevation_rad * 180.0 / 3.14159265358979323846,
                      state.sun_azimuth_rad * 180.0 / 3.14159265358979323846);
        draw_text(api, config.width, config.height, 4 * scale, 14 * scale, scale, line);
        std::snprintf(line, sizeof line, "SHADED %zu / %zu VERTS  CACHED %zu  CULLED %zu",
                      report->vertices_shaded, report->vertices_drawn, report->cache_hits,
                      report->culled);
        draw_text(api, config.width, config.height, 4 * scale, 24 * scale, scale, line);
        const bool cpu = config.backend == aerial::scene::Backend::cpu;
        std::snprintf(line, sizeof line, "METHOD %s  %s %s  SKY %s%s",
                      upper(report->main_method()).c_str(), cpu ? "CPU" : "ARB",
                      cpu ? upper(aerial::gl::path_name(report->path)).c_str() : "PROGRAM",
                      upper(sky_name(config.sky)).c_str(), config.policy ? "" : "  NO POLICY");
        draw_text(api, config.width, config.height, 4 * scale, 34 * scale, scale, line);
        api.Finish();
    }
    return outcome;
}

}  // namespace sample
