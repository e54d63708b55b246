// aerial/sun.hpp — where the sun is, how much of it reaches each altitude, the skylight, and
// an exposure that makes noon and dawn both read well.
//
// How to use this:
//   1. `auto sun = aerial::sun_position({2026, 6, 21, 12, 0, 0.0}, lat_rad, lon_rad);` gives
//      the elevation and azimuth (NOAA solar calculator, after Meeus, *Astronomical Algorithms*);
//      `aerial::sun_direction_enu(*sun)` is the unit vector towards it in an east-north-up frame
//      (map it to your world axes; View::sun_dir wants it there).
//   2. `aerial::solar_events(2026, 6, 21, lat_rad, lon_rad)` gives sunrise, solar noon, sunset.
//   3. Per frame: `SunIrradianceProfile::build(atmosphere, sun_elevation_rad, 0, 4000)` once,
//      then `profile.at(vertex_altitude_m)` per vertex: the sun colour there (mountain tops stay
//      lit at dawn while the valleys are already in the planet's shadow).
//   4. `sky_ambient(atmosphere, altitude_m, sun_elevation_rad)` is the diffuse skylight on an
//      upward-facing surface: the fixed-function ambient term of lit surfaces.
//   5. `auto_exposure(...)` once per frame, then `tone_map(linear, exposure, curve)` per colour.
//
// Irradiances are linear RGB in the units of Atmosphere::sun_irradiance (E_sun0).
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/error.hpp"

namespace aerial {

// ---- Sun position ----------------------------------------------------------------------------

/// A moment in Coordinated Universal Time (the algorithm does not distinguish UT1, UTC and TT:
/// their difference moves the sun by less than 0.001 deg).
struct UtcDateTime {
    int year = 2000;    ///< Gregorian, 1901 .. 2099 (the NOAA fit's documented range is wider)
    int month = 1;      ///< 1 .. 12
    int day = 1;        ///< 1 .. days in the month
    int hour = 12;      ///< 0 .. 23
    int minute = 0;     ///< 0 .. 59
    double second = 0;  ///< [0, 61)
};

/// The first bad field ("year", "month", "day", "hour", "minute", "second").
std::optional<Error> validate(const UtcDateTime& time);

/// Where the sun stands for an observer, from the NOAA solar calculator (the low-precision
/// solar coordinates of Meeus, *Astronomical Algorithms*, ch. 25, and his equation of time,
/// ch. 28). About 0.01 deg in position and a few seconds in the equation of time for 1901-2099.
struct SunPosition {
    double elevation_rad = 0;           ///< geometric, above the horizon (no refraction)
    double apparent_elevation_rad = 0;  ///< with NOAA's atmospheric refraction correction
    double azimuth_rad = 0;             ///< clockwise from north, [0, 2 pi)
    double declination_rad = 0;         ///< apparent declination
    double equation_of_time_min = 0;    ///< apparent minus mean solar time, minutes
};

/// The sun for a time and place. latitude in [-pi/2, pi/2] (north positive), longitude in
/// [-pi, pi] (east positive), radians. Errors name the field.
Result<SunPosition> sun_position(const UtcDateTime& time, double latitude_rad,
                                 double longitude_rad);

/// Unit vector towards the sun in an east (x), north (y), up (z) frame, from the geometric
/// elevation (what lights the scene; refraction only lifts the image).
glm::dvec3 sun_direction_enu(const SunPosition& sun);

/// Sunrise, solar noon and sunset of one UTC date, in minutes after 00:00 UTC of that date
/// (they may fall outside [0, 1440) far from Greenwich). Sunrise and sunset are when the upper
/// limb touches the horizon with standard refraction: a geometric centre 0.833 deg below it.
struct SolarEvents {
    double solar_noon_utc_min = 0;
    std::optional<double> sunrise_utc_min;  ///< empty during polar day and polar night
    std::optional<double> sunset_utc_min;
    /// When the sun's centre is kCivilTwilightDepressionRad below the horizon, morning and
    /// evening: the ends of civil twilight; empty where it never sinks that far (white nights)
    /// or never rises that high.
    std::optional<double> civil_dawn_utc_min;
    std::optional<double> civil_dusk_utc_min;
    bool polar_day = false;    ///< the sun stays up all day
    bool polar_night = false;  ///< the sun stays down all day
};

/// Sunrise, noon, sunset and civil twilight's ends, each found by iterating the NOAA formulas at
/// the event's own time (not at noon, as the NOAA spreadsheet does), so they agree with
/// sun_position to seconds.
Result<SolarEvents> solar_events(int year, int month, int day, double latitude_rad,
                                 double longitude_rad);

/// The depression of the sun's centre at sunrise and sunset: 50 arc minutes (16' of radius
/// and 34' of refraction), radians.
inline constexpr double kSunriseDepressionRad = 0.833 * 3.14159265358979323846 / 180.0;
/// The depression of the sun's centre that ends civil twilight: 6 degrees, radians.
inline constexpr double kCivilTwilightDepressionRad = 6.0 * 3.14159265358979323846 / 180.0;

// ---- Sunlight by altitude --------------------------------------------------------------------

/// The sun irradiance reaching a point at `altitude_m` when the sun stands at
/// `sun_elevation_rad` above that point's horizon: E_sun0 times the reference model's sun
/// transmittance (numerical, exponential profiles, zero in the planet's shadow).
glm::dvec3 sun_irradiance_at_altitude(const Atmosphere& atmosphere, double altitude_m,
                                      double sun_elevation_rad);

/// sun_irradiance_at_altitude tabulated once per frame for cheap per-vertex lookups. The sun
/// elevation is taken at the origin's horizon for every altitude (over a few km of terrain the
/// horizon tilts by well under the table's error). Interpolates the optical depth linearly.
class SunIrradianceProfile {
  public:
    /// Samples in [min_altitude_m, max_altitude_m]; `samples` >= 2, max > min, finite values.
    static Result<SunIrradianceProfile> build(const Atmosphere& atmosphere,
                                              double sun_elevation_rad, double min_altitude_m,
                                              double max_altitude_m, int samples = 65);

    /// The sun irradiance at an altitude (clamped to the table's range); zero for a profile that
    /// was default-constructed instead of built.
    glm::dvec3 at(double altitude_m) const;

    double min_altitude_m() const { return min_; }
    double max_altitude_m() const { return max_; }

  private:
    double min_ = 0, max_ = 1;
    glm::dvec3 top_{1.0};
    std::vector<glm::dvec3> depth_;  ///< optical depth per sample; kOpaque where shadowed
};

// ---- Skylight --------------------------------------------------------------------------------

struct SkyAmbientOptions {
    bool use_reference = false;  ///< the `reference` sky (slow) instead of `height-chained`
    int elevation_steps = 16;    ///< quadrature over the hemisphere, >= 2
    int azimuth_steps = 32;      ///< >= 4
};

/// Diffuse skylight irradiance on an upward-facing surface at `altitude_m`: the sky radiance
/// (aerial/sky.hpp) integrated over the upper hemisphere with the cosine weight. Fixed-function
/// engines use it as the ambient light of lit surfaces; it keeps shadowed sides blue at noon and
/// everything dim but visible at dusk.
Result<glm::dvec3> sky_ambient(const Atmosphere& atmosphere, double altitude_m,
                               double sun_elevation_rad, const SkyAmbientOptions& options = {});

// ---- Exposure and tone curve -----------------------------------------------------------------

// ToneCurve (clamp, exponential) and Display are batch.hpp's: one definition of the display.
std::string_view tone_curve_name(ToneCurve curve);
Result<ToneCurve> parse_tone_curve(std::string_view name);

/// Display value in [0, 1] of a linear colour times an exposure (batch.hpp's display_value, in
/// double, per channel).
glm::dvec3 tone_map(const glm::dvec3& linear, double exposure, ToneCurve curve);

struct ExposureOptions {
    double albedo = 0.18;  ///< reflectance of the "grey card" the exposure is set for
    /// Exposed radiance of that card before the tone curve (0.5 is 0.39 on the exponential one).
    double key = 0.5;
    /// Exposure limits as multiples of the exposure for a card lit by E_sun0 at the zenith and
    /// no sky: the lower keeps a bright scene from going grey, the upper lets night be night.
    double min_gain = 0.5;
    double max_gain = 64.0;
};

/// The exposure (a multiplier of linear radiance) that maps a grey card lit by the sun and the
/// sky to `key`: key / (albedo / pi * Y(E_sun max(sin elevation, 0) + E_sky)), Y the Rec. 709
/// luminance, clamped to the limits. Noon and dawn then both read well.
double auto_exposure(const glm::dvec3& sun_irradiance, double sun_elevation_rad,
                     const glm::dvec3& sky_irradiance, const glm::dvec3& sun_irradiance_top,
                     const ExposureOptions& options = {});

/// Rec. 709 luminance of a linear colour.
inline double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

}  // namespace aerial
