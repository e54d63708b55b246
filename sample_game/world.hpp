// sample_game/world.hpp — the sample's world: 16 × 16 km of procedural, textured terrain in
// 1 km tiles with a sky dome and a sun (aerial::scene), and the scripted flight over it.
//
// How to use this:
//   1. `auto world = build_world(options);` once.
//   2. Per frame: `FlightState state = flight_at(world, t);` for t in [0, 1] (the scripted
//      flythrough: noon to dusk, a ground-fog segment in the middle), or steer `state` yourself.
//   3. `camera_for(world, state, aspect)` and `settings_for(world, state, ...)` give what
//      aerial::scene::SceneRenderer::render takes.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "aerial/scene_renderer.hpp"

namespace sample {

struct WorldOptions {
    std::uint32_t seed = 7;
    double size_m = 16000.0;   ///< side of the terrain square, centred on the origin
    double tile_m = 1000.0;    ///< side of a tile
    int tile_resolution = 33;  ///< vertices a tile side
};

struct World {
    WorldOptions options;
    aerial::scene::ProceduralTerrain terrain;
    std::unique_ptr<aerial::scene::Node> root;
    std::size_t tiles = 0;
    std::size_t vertices = 0;
};

/// Builds the terrain tiles (heights from aerial::scene::procedural_height, a noise texture
/// of grass, rock and earth), the sky dome and the sun.
World build_world(const WorldOptions& options);

/// Ground height under (x, y), m.
double ground_height(const World& world, double x, double y);

/// Where the flight is and what the sky is like.
struct FlightState {
    double x = 0.0, y = 0.0, altitude_agl = 250.0;  ///< m; altitude above the ground below
    double heading_rad = 0.0;                       ///< clockwise from +y (north)
    double pitch_rad = -0.08;                       ///< negative looks down
    double sun_elevation_rad = 1.0;
    double sun_azimuth_rad = 3.14159;  ///< clockwise from +y
    bool fog = false;                  ///< the ground-fog layer is on
    double clock_hours = 12.0;         ///< local solar time shown in the readout
};

/// The scripted flythrough at t in [0, 1]: 12 km northwards turning west, 250 m above the
/// ground; the sun from 60° (noon) down to 2° (dusk) in the west; fog for 0.4 < t < 0.6.
FlightState flight_at(const World& world, double t);

aerial::scene::Camera camera_for(const World& world, const FlightState& state, double aspect);

/// The atmosphere of `preset`, with a ground-fog layer (visibility 1.2 km in a 500 m layer,
/// Mie g 0.5 standing in for multiple scattering) added when state.fog; an exposure that keeps the
/// lit ground readable from noon to dusk, for the tone curve `tone` (the arb backend has only
/// clamp; exponential never clips the sun's halo).
aerial::Result<aerial::scene::FrameSettings> settings_for(const FlightState& state,
                                                          const std::string& preset,
                                                          aerial::Model model,
                                                          aerial::ToneCurve tone);

}  // namespace sample
