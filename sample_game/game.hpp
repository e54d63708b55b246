// sample_game/game.hpp — one frame of the sample (scene, sky, readout) and the interactive window.
//
// How to use this:
//   1. Fill a GameConfig from the command line.
//   2. `auto game = make_game_renderer(api, config);` (or SceneRenderer::create and install_sky):
//      the renderer with the sky, and the stars and the moon after it (night_sky.hpp).
//   3. Per frame, with a current context: `render_frame(api, game, world, state, config)` clears,
//      updates the night sky, draws the world through aerial::scene::SceneRenderer and the readout
//      (fps, sun and moon, vertices shaded, method), and says what the frame did.
//   4. `run_window(...)` flies interactively in a GLFW window (builds with GLFW only).
#pragma once

#include <memory>
#include <string>

#include "aerial/scene_renderer.hpp"
#include "aerial/scene_sky.hpp"
#include "night_sky.hpp"
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
    SunSchedule sun;     ///< the day and night: date, place, noon, sunset, night, the end
    int width = 480;
    int height = 270;
    /// How fast the window's clock runs (times real time), shown in the readout; < 0: not shown.
    double time_factor = -1.0;
};

struct FrameOutcome {
    aerial::scene::FrameReport report;
    aerial::scene::FrameSettings settings;
    double milliseconds = 0.0;    ///< render() and glFinish, without the readout
    std::size_t stars_drawn = 0;  ///< aerial::scene::NightSkyStats::stars_drawn of the frame
};

/// Installs config.sky on the renderer, then the night sky's drawer after its sun
/// (install_night_sky). The cubemap needs cube maps: without them the renderer keeps its dome
/// and `used` says dome. Returns the cubemap's statistics (null for the dome) and the night sky.
struct SkySetup {
    SkyKind used = SkyKind::dome;
    std::shared_ptr<const aerial::scene::CubemapSkyStats> stats;
    std::shared_ptr<NightSkyState> night;
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

/// One frame of `state`. Errors: the settings, the night sky or the renderer failed.
aerial::Result<FrameOutcome> render_frame(const aerial::gl::Api& api, GameRenderer& game,
                                          const World& world, const FlightState& state,
                                          const GameConfig& config);

/// "HH:MM" of a clock time in hours.
std::string clock_text(double hours);

/// True when this build has the interactive window (GLFW).
bool window_available();

/// The window's clock speeds (times real time) that ] and [ step through.
inline constexpr double kTimeFactors[] = {0.0, 1.0, 60.0, 600.0, 3600.0};

/// Flies in a window until it is closed (or for `frames` frames when > 0, then writes the last
/// one to `screenshot` when not empty). Keys: arrows turn and climb, W/S speed, T/G an hour back
/// and on a second held, ] / [ time faster and slower (kTimeFactors; 0x at first: the clock
/// stands at noon), F fog, P policy, 1-5 presets, Esc quits. Returns the exit status; errors go
/// to stderr.
int run_window(const World& world, GameConfig config, int frames, const std::string& screenshot);

}  // namespace sample
