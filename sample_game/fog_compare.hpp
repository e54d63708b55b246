// sample_game/fog_compare.hpp — the sample's flythrough against the same flight with GL fog only
// (aerial-scene-bench --flythrough): the whole frame's cost of aerial against what an engine
// without it pays, side by side in one run.
//
// How to use this:
//   `run_fog_compare(api, world, config, frames, rounds, csv_path)` with a current headless context
//   of config.width x config.height: per frame of the scripted flight it renders the game's frame
//   (render_frame, config as given) and the fog-only frame (the same terrain, texture and
//   lighting through a SceneRenderer with Backend::none, GL_FOG from the atmosphere at the eye,
//   the sky cleared to the fog colour), then both again at the same state ("still": nothing
//   moved, so no code can change), and writes one CSV row a frame.
#pragma once

#include <string>

#include "aerial/gl_api.hpp"
#include "game.hpp"

namespace sample {

/// Means over the frames after the first (which builds textures, tables and caches) of each
/// frame's fastest time over the rounds (each round flies with fresh renderers).
struct FogCompareSummary {
    int frames = 0, rounds = 0;
    double aerial_ms = 0, fog_ms = 0, still_aerial_ms = 0, still_fog_ms = 0;
    double ratio() const { return fog_ms > 0 ? aerial_ms / fog_ms : 0; }
    double still_ratio() const { return still_fog_ms > 0 ? still_aerial_ms / still_fog_ms : 0; }
};

aerial::Result<FogCompareSummary> run_fog_compare(const aerial::gl::Api& api, const World& world,
                                                  const GameConfig& config, int frames, int rounds,
                                                  const std::string& csv_path);

}  // namespace sample
