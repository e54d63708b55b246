// sample_game/game.hpp — one frame of the sample (scene, sky, readout) and the interactive window.
//
// How to use this:
//   1. Fill a GameConfig from the command line.
//   2. Per frame, with a current context: `render_frame(api, renderer, world, state, config)`
//      clears, draws the world through aerial::scene::SceneRenderer and the readout (fps, vertices
//      shaded, method), and says what the frame did.
//   3. `run_window(...)` flies interactively in a GLFW window (builds with GLFW only).
#pragma once

#include <memory>
#include <string>

#include "aerial/scene_renderer.hpp"
#include "aerial/scene_sky.hpp"
#include "world.hpp"

namespace sample {

/// The sky: the renderer's per-vertex dome and flat sun, or the CPU cubemap and the sun sprite
/// (aerial::scene::install_cubemap_sky).
enum class SkyKind { dome, cubemap };
const char* sky_name(SkyKind sky);

struct GameConfig {
    std::string preset = "earth";
    aerial::Model model = aerial::Model::height;
    aerial::scene::Backend backend = aerial::scene::Backend::cpu;
    aerial::gl::Path path = aerial::gl::Path::automatic;
    bool policy = true;
    double error_target_lsb = 2.0;
    bool readout = true;
    SkyKind sky = SkyKind::cubemap;
    int cube_size = 32;  ///< texels along a cubemap face's side (the cubemap sky), 1 .. 512
    SunSchedule sun;     ///< the day: date, place, noon and dusk
    int width = 480;
    int height = 270;
};

struct FrameOutcome {
    aerial::scene::FrameReport report;
    aerial::scene::FrameSettings settings;
    double milliseconds = 0.0;  ///< render() and glFinish, without the readout
};

/// Installs config.sky on the renderer. The cubemap needs cube maps: without them the renderer
/// keeps its dome and `used` says dome. Returns the cubemap's statistics (null for the dome).
struct SkySetup {
    SkyKind used = SkyKind::dome;
    std::shared_ptr<const aerial::scene::CubemapSkyStats> stats;
};
aerial::Result<SkySetup> install_sky(aerial::scene::SceneRenderer& renderer,
                                     const aerial::gl::Api& api, const GameConfig& config);

/// A renderer of config.backend and config.path with config.sky installed: what the game,
/// its soak and its comparison with fog draw through.
struct GameRenderer {
    aerial::scene::SceneRenderer renderer;
    SkySetup sky;
};
aerial::Result<GameRenderer> make_game_renderer(const aerial::gl::Api& api,
                                                const GameConfig& config);

aerial::Result<FrameOutcome> render_frame(const aerial::gl::Api& api,
                                          aerial::scene::SceneRenderer& renderer,
                                          const World& world, const FlightState& state,
                                          const GameConfig& config);

/// "HH:MM" of a clock time in hours.
std::string clock_text(double hours);

/// True when this build has the interactive window (GLFW).
bool window_available();

/// Flies in a window until it is closed (or for `frames` frames when > 0, then writes the last
/// one to `screenshot` when not empty). Keys: arrows turn and climb, W/S speed, T/G time of day,
/// F fog, P policy, 1-5 presets, Esc quits. Returns the exit status; errors go to stderr.
int run_window(const World& world, GameConfig config, int frames, const std::string& screenshot);

}  // namespace sample
