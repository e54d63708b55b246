// sample_game/world.hpp — the sample's world: 16 × 16 km of procedural, textured terrain in
// 1 km tiles with a sky dome and a sun (aerial::scene), and the scripted flight over it.
//
// How to use this:
//   1. `auto world = build_world(options);` once.
//   2. `auto sun = make_sun_schedule(2026, 6, 21, latitude_rad, longitude_rad);` once: the day
//      and night from solar noon to the sun 15 deg below the horizon (aerial::solar_events,
//      aerial::sun_position).
//   3. Per frame: `FlightState state = flight_at(world, t, *sun);` for t in [0, 1] (the scripted
//      flythrough: noon, dusk, twilight and night, a ground-fog segment in the middle), or steer
//      `state` yourself and `place_sky(state, *sun, utc_min)` (the sun from aerial::sun_position,
//      the moon from aerial::moon_position).
//   4. `camera_for(world, state, aspect)` and `settings_for(state, preset, ...)` give what
//      aerial::scene::SceneRenderer::render takes; `frame_light(state, preset)` is the light and
//      exposure settings_for is made of (the night sky's moon colour and stars need it too).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "aerial/night.hpp"
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

/// The day and night of the flight: where and when, and the times the script's clock runs
/// through (script_utc_min). Times in minutes after 00:00 UTC of the date.
struct SunSchedule {
    int year = 2026, month = 6, day = 21;  ///< UTC date
    double latitude_rad = 0.0;             ///< north positive
    double longitude_rad = 0.0;            ///< east positive
    double noon_utc_min = 720.0;           ///< solar noon
    double sunset_utc_min = 1170.0;        ///< sunset; end_utc_min where the sun does not set
    /// Where twilight ends and the night begins: the sun's centre kNightDepressionRad down;
    /// end_utc_min where it never sinks that far.
    double night_utc_min = 1250.0;
    double end_utc_min = 1290.0;  ///< where the script ends (make_sun_schedule)
};

/// The sun's depression where the script's night begins: the end of nautical twilight (12 deg;
/// the stars are out, the afterglow is a band on the horizon), radians.
inline constexpr double kNightDepressionRad = 12.0 * 3.14159265358979323846 / 180.0;
/// The sun's depression where the script ends (15 deg: a dark sky, most stars out), radians.
inline constexpr double kScriptEndDepressionRad = 15.0 * 3.14159265358979323846 / 180.0;
/// Where the sun never sets (polar day) the script ends this long after noon, minutes.
inline constexpr double kPolarDayScriptMinutes = 600.0;

/// The schedule of a UTC date and place (radians). Errors name the field: "date" (no such
/// day), "latitude" / "longitude" (out of range, or polar night: the sun does not rise). The
/// script ends where the sun's centre is kScriptEndDepressionRad below the horizon; where it
/// never sinks that far (white nights: the default date and place reach -20 deg, 60 deg north
/// only -6.6 deg), at its lowest point, solar midnight (12 hours after noon); in polar day
/// kPolarDayScriptMinutes after noon.
aerial::Result<SunSchedule> make_sun_schedule(int year, int month, int day, double latitude_rad,
                                              double longitude_rad);

/// The UTC moment `minutes` after 00:00 of the schedule's date (any sign; days roll over).
aerial::UtcDateTime utc_at(const SunSchedule& schedule, double minutes);

/// The script's clock: the UTC minutes at `day` in [0, 1] (clamped). It stands at noon up to
/// 0.15, runs to sunset by 0.6 (slowly at first and towards sunset), through twilight (sunset
/// to night_utc_min) by 0.82 and through the night to the end by 1: of 24 frames, 4 at noon, 10
/// in the afternoon, 5 in twilight and 5 in the night. A part of no length (no night in white
/// nights, no sunset in polar day) gives its share to the part before it.
double script_utc_min(const SunSchedule& schedule, double day);

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
    /// The moon (aerial::moon_position: place, phase, distance); none: no moon.
    std::optional<aerial::MoonPosition> moon;
    bool fog = false;           ///< the ground-fog layer is on
    double clock_hours = 12.0;  ///< local apparent solar time shown in the readout
    double utc_min = 720.0;     ///< minutes after 00:00 UTC of the schedule's date
};

/// Sets the sky of `state` at `utc_min` (minutes after 00:00 UTC of the schedule's date): the
/// sun from aerial::sun_position, the moon from aerial::moon_position, and the local apparent
/// solar time from the equation of time.
void place_sky(FlightState& state, const SunSchedule& schedule, double utc_min);

/// The scripted flythrough at t in [0, 1]: 12 km northwards turning west (over the default
/// 16 km world; the path scales with WorldOptions::size_m), 250 m above the ground; the sky at
/// script_utc_min(schedule, t), from solar noon into the night; fog for 0.4 < t < 0.6.
FlightState flight_at(const World& world, double t, const SunSchedule& schedule);

aerial::scene::Camera camera_for(const World& world, const FlightState& state, double aspect);

/// Altitude of the light that sets the exposure, the terrain's skylight and the stars' sky, m
/// (the terrain spans about 20 to 920 m).
inline constexpr double kLightingAltitudeM = 300.0;

/// The grey card's exposed radiance (aerial::ExposureOptions::key): brighter than the default
/// 0.5, since the terrain's texture and albedo make it darker than an 18 % card.
inline constexpr double kExposureKey = 0.8;
/// By day at most this many times the exposure of the sun at the zenith
/// (aerial::ExposureOptions::max_gain): dusk may stay darker than noon instead of turning the
/// bright sky around the low sun white.
inline constexpr double kExposureMaxGain = 3.5;

/// What lights a frame and how it is exposed, before it becomes FrameSettings: the sun and the
/// moon through the atmosphere onto a level grey card at kLightingAltitudeM. Irradiances are
/// linear RGB in units of the preset's E_sun0, untinted.
struct FrameLight {
    aerial::Atmosphere atmosphere;      ///< the preset, with the fog layer when state.fog; untinted
    glm::dvec3 sun_dir{0.0, 0.0, 1.0};  ///< world (east, north, up), unit
    /// The moon as the renderer's second light: its direction and its light as a fraction of
    /// the sun's (aerial::moonlight_fraction in steps of kMoonFractionStep); none: no moon.
    std::optional<aerial::scene::Moonlight> moon;
    glm::dvec3 moon_direct{0.0};  ///< the moon's light through the atmosphere, facing it
    glm::dvec3 skylight{0.0};     ///< both lights' sky on level ground: the terrain's ambient
    /// On the card: each light's direct light times the sine of its elevation, plus skylight.
    glm::dvec3 card{0.0};
    double card_cd_m2 = 0.0;  ///< the card's luminance (aerial::card_luminance_cd_m2)
    double exposure = 1.0;    ///< Display::exposure (see frame_light)
    /// The Purkinje shift as a colour scale of the light handed to the pipeline: white by
    /// day, the rods' blue (aerial::NightOptions::scotopic_tint, luminance 1) at night.
    glm::dvec3 tint{1.0};
};

/// The light of a frame. The atmosphere of `preset`, with a ground-fog layer (visibility
/// 1.2 km in a 500 m layer, Mie g 0.5 standing in for multiple scattering) when state.fog; the
/// skylight of each light from aerial::sky_ambient (the moon's: of aerial::moonlit's
/// atmosphere); the exposure:
///   - day: aerial::auto_exposure with kExposureKey and kExposureMaxGain; after sunset raised as
///     the skylight fades, holding the sky's mean radiance at aerial::NightOptions::
///     max_sky_value, so that civil twilight's afterglow reads;
///   - night: aerial::night_exposure with the skylight, the card shown darker as the light
///     falls (a moonlit night dark but readable), the twilight sky held at the same value;
///   - between them the eye moves from the first to the second in log exposure by
///     aerial::rod_share of the card's luminance: 0 (the day's rule, exactly) at and above the
///     photopic 5 cd/m2 (the sun about 3.5 deg down on the default day), 1 (night_exposure) at
///     and below the scotopic 0.005 cd/m2 (about 10.5 deg down).
/// The tint moves with the same rod share, in steps of kTintStep.
aerial::Result<FrameLight> frame_light(const FlightState& state, const std::string& preset);

/// The rod share of frame_light's tint changes in steps of this much: each new tint is a new
/// E_sun0, which the renderer's colour caches (aerial::ShadingCache) take as a new atmosphere
/// and shade every node again for, so a tint that changed every frame would do that every
/// frame.
inline constexpr double kTintStep = 0.05;

/// The moon's light fraction changes in steps of this much (e-folds, so 2 %: +-1 % in
/// brightness, a few steps a night), for the same reason: the moon's light is the atmosphere's
/// E_sun0 times the fraction to those caches, and the fraction changes every minute.
inline constexpr double kMoonFractionStep = 0.02;

/// The renderer's settings of `light`: its atmosphere with E_sun0 scaled by the tint (so that
/// F_ex times the light and L_in are tinted alike, the moon's too), the sun and the moon, the
/// tinted skylight as the terrain's ambient, the exposure and the tone curve `tone` (the arb
/// backend has only clamp; exponential never clips the sun's halo).
aerial::scene::FrameSettings settings_for(const FrameLight& light, aerial::Model model,
                                          aerial::ToneCurve tone);

/// settings_for(frame_light(state, preset), model, tone).
aerial::Result<aerial::scene::FrameSettings> settings_for(const FlightState& state,
                                                          const std::string& preset,
                                                          aerial::Model model,
                                                          aerial::ToneCurve tone);

}  // namespace sample
