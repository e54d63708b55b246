#include "game.hpp"

#include <algorithm>
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
    if (config.sky == SkyKind::cubemap) {
        aerial::scene::CubemapSkyOptions options;
        options.cache.size = config.cube_size;
        auto stats = aerial::scene::install_cubemap_sky(renderer, api, options);
        if (stats) {
            setup.used = SkyKind::cubemap;
            setup.stats = *stats;
        } else if (stats.error().field != "cube_map") {  // GL 1.1: the dome
            return stats.error();
        }
    }
    setup.night = install_night_sky(renderer);
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

namespace {

/// The on-screen readout: timings, sun and moon, shading, method.
void draw_readout(const aerial::gl::Api& api, const FrameOutcome& outcome, const FlightState& state,
                  const GameConfig& config) {
    constexpr double kDeg = 180.0 / 3.14159265358979323846;
    const aerial::scene::FrameReport& report = outcome.report;
    const int scale = std::max(1, config.height / 270);
    const double ms = outcome.milliseconds;
    int row = 0;
    const auto print = [&](const char* line) {
        draw_text(api, config.width, config.height, 4 * scale, (4 + 10 * row++) * scale, scale,
                  line);
    };
    char line[160];
    std::snprintf(line, sizeof line, "FPS %.1f (%.0f MS, SHADING %.1f MS)  %s", 1000.0 / ms, ms,
                  report.shading_milliseconds,
                  upper(state.fog ? config.preset + "+FOG" : config.preset).c_str());
    print(line);
    char speed[32] = "";  // the window's clock speed
    if (config.time_factor >= 0.0) std::snprintf(speed, sizeof speed, " (%gX)", config.time_factor);
    std::snprintf(line, sizeof line, "SOLAR TIME %s%s  SUN %.1f DEG  AZIMUTH %.0f DEG",
                  clock_text(state.clock_hours).c_str(), speed, state.sun_elevation_rad * kDeg,
                  state.sun_azimuth_rad * kDeg);
    print(line);
    if (state.moon) {
        std::snprintf(line, sizeof line, "MOON %.1f DEG  PHASE %.0f DEG  STARS %zu  LIGHTS %s",
                      state.moon->elevation_rad * kDeg, state.moon->phase_angle_rad * kDeg,
                      outcome.stars_drawn,
                      upper(aerial::scene::lights_name(report.lights)).c_str());
        print(line);
    }
    std::snprintf(line, sizeof line, "SHADED %zu / %zu VERTS  CACHED %zu  CULLED %zu",
                  report.vertices_shaded, report.vertices_drawn, report.cache_hits, report.culled);
    print(line);
    const bool cpu = config.backend == aerial::scene::Backend::cpu;
    std::snprintf(line, sizeof line, "METHOD %s  %s %s  SKY %s%s",
                  upper(report.main_method()).c_str(), cpu ? "CPU" : "ARB",
                  cpu ? upper(aerial::gl::path_name(report.path)).c_str() : "PROGRAM",
                  upper(sky_name(config.sky)).c_str(), config.policy ? "" : "  NO POLICY");
    print(line);
    api.Finish();
}

}  // namespace

aerial::Result<FrameOutcome> render_frame(const aerial::gl::Api& api, GameRenderer& game,
                                          const World& world, const FlightState& state,
                                          const GameConfig& config) {
    const aerial::scene::Camera camera =
        camera_for(world, state, double(config.width) / double(config.height));
    auto light = frame_light(state, config.preset);
    if (!light) return light.error();
    aerial::scene::FrameSettings settings =
        settings_for(*light, config.model,
                     config.backend == aerial::scene::Backend::cpu ? aerial::ToneCurve::exponential
                                                                   : aerial::ToneCurve::clamp);
    settings.policy = config.policy;
    settings.error_target_lsb = config.error_target_lsb;
    NightSkyState* night = game.sky.night.get();
    if (night) {
        if (auto e = update_night_sky(*night, state, config.sun, *light, settings.display,
                                      camera.fov_y_rad / config.height)) {
            return *e;
        }
    }

    api.Viewport(0, 0, config.width, config.height);
    api.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const auto start = std::chrono::steady_clock::now();
    auto report = game.renderer.render(*world.root, camera, settings);
    if (!report) return report.error();
    api.Finish();
    FrameOutcome outcome;
    outcome.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    outcome.report = *report;
    outcome.settings = settings;
    outcome.stars_drawn = night ? night->stats->stars_drawn : 0;
    if (config.readout) draw_readout(api, outcome, state, config);
    return outcome;
}

}  // namespace sample
