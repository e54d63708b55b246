// sample_game/world.hpp — the sample's world: 16 × 16 km of procedural, textured terrain in
// 1 km tiles with a sky dome and a sun (aerial::scene), and the scripted flight over it.
//
// How to use this:
//   1. `auto world = build_world(options);` once.
//   2. `auto sun = make_sun_schedule(2026, 6, 21, latitude_rad, longitude_rad);` once: the day
//      from solar noon to just after sunset (aerial::solar_events).
//   3. Per frame: `FlightState state = flight_at(world, t, *sun);` for t in [0, 1] (the scripted
//      flythrough: noon to dusk, a ground-fog segment in the middle), or steer `state` yourself
//      and `place_sun(state, *sun, day)` (the sun from aerial::sun_position).
//   4. `camera_for(world, state, aspect)` and `settings_for(world, state, ...)` give what
//      aerial::scene::SceneRenderer::render takes.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "aerial/scene_renderer.hpp"
#include "aerial/sun.hpp"

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

/// The day of the flight: where and when, and the times the script runs between.
struct SunSchedule {
    int year = 2026, month = 6, day = 21;  ///< UTC date
    double latitude_rad = 0.0;             ///< north positive
    double longitude_rad = 0.0;            ///< east positive
    double noon_utc_min = 720.0;           ///< solar noon, minutes after 00:00 UTC of the date
    double end_utc_min = 1200.0;           ///< where the script ends: the end of civil twilight
};

/// Minutes after sea-level sunset at which the scripted day ends where the sun never sinks 6 deg
/// below the horizon (white nights): about as long as civil twilight lasts at mid-latitudes.
inline constexpr double kWhiteNightMinutesAfterSunset = 40.0;

/// The schedule of a UTC date and place (radians). Errors name the field: "date" (no such
/// day), "latitude" / "longitude" (out of range, or polar night: the sun does not rise). The
/// script ends at the end of civil twilight (the sun's centre 6 deg down); in white nights
/// kWhiteNightMinutesAfterSunset after sunset, in polar day 10 hours after noon.
aerial::Result<SunSchedule> make_sun_schedule(int year, int month, int day, double latitude_rad,
                                              double longitude_rad);

/// The sample's default day: the summer solstice of 2026 over the Swiss Alps' latitude.
inline constexpr int kDefaultYear = 2026, kDefaultMonth = 6, kDefaultDay = 21;
inline constexpr double kDefaultLatitudeDeg = 46.5, kDefaultLongitudeDeg = 8.0;
/// make_sun_schedule of the defaults above.
SunSchedule default_sun_schedule();

/// Where the flight is and what the sky is like.
struct FlightState {
    double x = 0.0, y = 0.0, altitude_agl = 250.0;  ///< m; altitude above the ground below
    double heading_rad = 0.0;                       ///< clockwise from +y (north)
    double pitch_rad = -0.08;                       ///< negative looks down
    double sun_elevation_rad = 1.0;    ///< geometric (aerial::SunPosition::elevation_rad)
    double sun_azimuth_rad = 3.14159;  ///< clockwise from +y (north); +x is east
    bool fog = false;                  ///< the ground-fog layer is on
    double clock_hours = 12.0;         ///< local apparent solar time shown in the readout
    double utc_min = 720.0;            ///< minutes after 00:00 UTC of the schedule's date
};

/// Sets the sun of `state` for `day` in [0, 1] of the schedule (0 solar noon, 1 its end; the
/// clock runs slowly at first so that most of the script is in the afternoon and dusk): position
/// from aerial::sun_position, the local apparent solar time from the equation of time.
void place_sun(FlightState& state, const SunSchedule& schedule, double day);

/// The scripted flythrough at t in [0, 1]: 12 km northwards turning west (over the default
/// 16 km world; the path scales with WorldOptions::size_m), 250 m above the ground; the sun from
/// solar noon to just after sunset (place_sun with day = t); fog for 0.4 < t < 0.6.
FlightState flight_at(const World& world, double t, const SunSchedule& schedule);

aerial::scene::Camera camera_for(const World& world, const FlightState& state, double aspect);

/// The atmosphere of `preset`, with a ground-fog layer (visibility 1.2 km in a 500 m layer,
/// Mie g 0.5 standing in for multiple scattering) added when state.fog; the terrain's skylight
/// from aerial::sky_ambient and the exposure from aerial::auto_exposure (sun and sky on level
/// ground at 300 m), for the tone curve `tone` (the arb backend has only clamp; exponential
/// never clips the sun's halo).
aerial::Result<aerial::scene::FrameSettings> settings_for(const FlightState& state,
                                                          const std::string& preset,
                                                          aerial::Model model,
                                                          aerial::ToneCurve tone);

}  // namespace sample
