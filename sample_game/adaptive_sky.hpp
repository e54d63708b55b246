// sample_game/adaptive_sky.hpp — `--tessellation adaptive`: the per-vertex sky dome refined where
// its colour needs vertices (aerial::mesh::AdaptiveMesh), with new vertices morphed in.
//
// How to use this:
//   1. `auto stats = std::make_shared<sample::AdaptiveSkyStats>();`
//   2. `renderer.set_sky_drawer(sample::adaptive_sky_drawer(stats));` once.
//   3. After each frame, `stats` holds the dome's live vertices and its update time.
//
// The dome: a geodesic dome of frequency 4 around the eye, refined to 1 step of colour error
// (aerial-tess's dome setting), of 400 km for shading (past the atmosphere overhead, a long path
// at the horizon), drawn at half the far plane around the eye.
// Each vertex shows L_in of the height model (on a black primary, through the renderer's
// fixed-function path), morphed over 8 updates; vertex budget 20 000, time slice 4 ms.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "aerial/scene_renderer.hpp"

namespace sample {

struct AdaptiveSkyStats {
    std::size_t vertices = 0;  ///< live vertices of the dome after the last frame
    double update_ms = 0.0;    ///< the last frame's refinement and coarsening
    std::string error;         ///< set when the dome could not be built
};

aerial::scene::SkyDrawer adaptive_sky_drawer(std::shared_ptr<AdaptiveSkyStats> stats);

}  // namespace sample
