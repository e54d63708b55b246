// aerial/night.hpp — the night sky's sources: where the moon is and how bright, the bright stars,
// and which of them an observer can see against the sky's own luminance.
//
// How to use this:
//   1. `auto moon = aerial::moon_position({2026, 6, 21, 22, 0, 0.0}, lat_rad, lon_rad);` gives
//      its topocentric elevation and azimuth, distance, phase angle and illuminated fraction
//      (libnova: ELP 2000-82B, Meeus, *Astronomical Algorithms*, ch. 47-48);
//      `aerial::sun_direction_enu`'s convention: `aerial::moon_direction_enu(*moon)`.
//   2. `aerial::moon_illuminance_lux(moon->phase_angle_rad, moon->distance_km)`: its light
//      outside the atmosphere (Krisciunas & Schaefer 1991), and `moon_irradiance(...)` the same
//      as a fraction of the sun's E_sun0 for the models.
//   3. Stars: `auto stars = aerial::read_star_catalogue(aerial::kBrightStarCataloguePath);`
//      (the Yale Bright Star Catalogue as Debian's xplanet ships it), `stars_of_date(...)` once a
//      night, then per frame `aerial::star_direction_enu(star, lat, sidereal)` with
//      `local_sidereal_time_rad(time, lon)`.
//   4. Visibility: `aerial::limiting_magnitude(background_cd_m2)` (Schaefer's threshold for the
//      naked eye), with the background the model's sky luminance in the star's direction
//      (`sky_luminance_cd_m2`) plus the natural night sky (kNaturalNightSkyCdM2); a star is seen
//      when its magnitude, dimmed by the atmosphere's transmittance along its direction, is
//      below the limit (`visible_stars`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/error.hpp"
#include "aerial/sky.hpp"
#include "aerial/sun.hpp"

namespace aerial {

// ---- The moon ----------------------------------------------------------------------------------

struct MoonPosition {
    double elevation_rad = 0;        ///< topocentric (parallax applied), geometric (no refraction)
    double azimuth_rad = 0;          ///< clockwise from north, [0, 2 pi)
    double right_ascension_rad = 0;  ///< geocentric apparent, [0, 2 pi)
    double declination_rad = 0;      ///< geocentric apparent
    double distance_km = 0;          ///< between the centres of the earth and the moon
    /// The angle sun - moon - earth: 0 at full moon, pi at new moon.
    double phase_angle_rad = 0;
    double illuminated_fraction = 0;  ///< of the disc, 0 .. 1: (1 + cos(phase angle)) / 2
};

/// The moon for a time and place (latitude, longitude as sun_position takes them). The time is
/// taken as terrestrial time (UTC differs by about a minute: 0.01 deg of the moon's motion).
Result<MoonPosition> moon_position(const UtcDateTime& time, double latitude_rad,
                                   double longitude_rad);

/// Unit vector towards the moon in the east (x), north (y), up (z) frame.
glm::dvec3 moon_direction_enu(const MoonPosition& moon);

/// The moon's illuminance on a surface facing it outside the atmosphere, lux, by Krisciunas and
/// Schaefer (1991, PASP 103, 1033), eq. 8-9: V magnitude -12.73 + 0.026 |alpha| + 4e-9 alpha^4
/// (alpha in degrees) at the mean distance 384 400 km, scaled by the inverse square of the
/// distance. Full moon: about 0.27 lux.
double moon_illuminance_lux(double phase_angle_rad, double distance_km);

/// The sun's illuminance outside the atmosphere at one astronomical unit, lux: the scale that
/// turns the models' radiance (in units of E_sun0) into luminance (sky_luminance_cd_m2).
inline constexpr double kSunIlluminanceLux = 128000.0;

/// The moon's light as a fraction of the sun's: moon_illuminance_lux / kSunIlluminanceLux
/// (2.4e-6 at full moon).
double moonlight_fraction(const MoonPosition& moon);

/// The moon as a second light for the models: E_sun0 times moonlight_fraction (the moon's light
/// is the sun's, reflected; its colour is taken as the sun's).
glm::dvec3 moon_irradiance(const Atmosphere& atmosphere, const MoonPosition& moon);

/// The atmosphere with the moon's irradiance in place of the sun's: every model (CPU and ARB
/// programs alike) then gives the moon's light when its View::sun_dir is the moon's direction.
/// Scattering is linear in the light: the night's L_in is the sun's plus the moon's.
Atmosphere moonlit(const Atmosphere& atmosphere, const MoonPosition& moon);
/// The same for a light of `fraction` times the sun's (moonlight_fraction, or a value an
/// application holds, e.g. in steps): E_sun0 times `fraction`.
Atmosphere moonlit(const Atmosphere& atmosphere, double fraction);

/// Where the lit side of the moon's disc faces on the sky: the angle, in the plane across the
/// line of sight, from the projection of `up` towards the projection of the sun, counterclockwise
/// as seen by the observer (radians; 0: the lit limb is the top, pi / 2: the left). Directions in
/// one frame, unit; the moon and the sun not along one line with the eye (then 0).
double moon_bright_limb_angle_rad(const glm::dvec3& moon_dir, const glm::dvec3& sun_dir,
                                  const glm::dvec3& up);

/// The moon's disc as an engine draws it: `size` x `size` RGBA8 texels, top row first; inside
/// the disc (alpha 255, edges antialiased) the sunlit part shaded by Lommel-Seeliger's law
/// mu0 / (mu0 + mu) (a dusty surface: a full moon looks flat, not Lambertian), white at the
/// brightest texel, the night side black. Modulate it by the moon's colour (F_ex towards it
/// times its displayed light) and draw it facing the eye, `up` of the image along the sky's up.
struct MoonSprite {
    int size = 0;
    std::vector<std::uint8_t> rgba;
    double lit_fraction = 0;  ///< of the disc's texels that are lit (the illuminated fraction)
};

/// size in 8 .. 1024; phase angle in [0, pi]. Errors name the field.
Result<MoonSprite> make_moon_sprite(double phase_angle_rad, double bright_limb_angle_rad, int size);

// ---- Night exposure ----------------------------------------------------------------------------

/// How exposure and colour follow the eye into the night. Between the photopic and the scotopic
/// luminance (CIE 191:2010's mesopic range, 5 to 0.005 cd/m2) the eye adapts less and less and
/// the rods take over: a moonlit night is shown dark but readable, not as day, and bluish.
struct NightOptions {
    double photopic_cd_m2 = 5.0;    ///< at and above: the card at ExposureOptions::key (day rule)
    double scotopic_cd_m2 = 0.005;  ///< at and below: rod vision only (full blue shift)
    /// Below photopic_cd_m2 the card's displayed value falls as (L / photopic)^key_exponent.
    double key_exponent = 0.25;
    /// The hue of rod vision (Jensen et al. 2001, "A physically-based night sky model": blue
    /// shift to (1.05, 0.97, 1.27)); Rec. 709 luminance about 1.
    glm::dvec3 scotopic_tint{1.05, 0.97, 1.27};
    /// night_exposure with the sky's irradiance: the sky's mean radiance (its Rec. 709
    /// irradiance on level ground / pi) times the exposure is held at this where the sky lights
    /// the card.
    double max_sky_value = 0.1;
};

/// The luminance (cd/m2) of a grey card of `albedo` lit by `irradiance` (in units of E_sun0 of
/// `atmosphere`, on the card: sun, moon and sky together).
double card_luminance_cd_m2(const Atmosphere& atmosphere, const glm::dvec3& irradiance,
                            double albedo = 0.18);

/// The exposure for a scene whose grey card receives `irradiance` (units of E_sun0: the sun's and
/// the moon's light on it, each times the sine of its elevation, plus the sky's): at day (card
/// at or above photopic_cd_m2) auto_exposure's key / (albedo / pi Y(irradiance)); below, the key
/// times (L / photopic)^key_exponent. No gain limit: the night is dark by the key, not by a
/// clamp. A full moon 45 degrees up: the card (0.012 cd/m2) shows at 0.11 (day: 0.5). 0 where
/// the card gets no light (or a value that is not a finite irradiance).
double night_exposure(const Atmosphere& atmosphere, const glm::dvec3& irradiance,
                      const ExposureOptions& exposure = {}, const NightOptions& night = {});
/// The same, for a view with the sky in it: in twilight the card is lit by the sky alone and
/// the sky itself is several times brighter than the card, so that the card's exposure would
/// show the sky pale white. `sky_irradiance` (part of `irradiance`: the sky's light on level
/// ground) gives the sky's mean radiance; where that times night_exposure exceeds
/// night.max_sky_value, the exposure moves towards the one that holds it there, in log exposure
/// by the sky's share of the card's luminance: fully in twilight (the card lit by the sky),
/// little by day or under a moon high enough to light the card itself.
double night_exposure(const Atmosphere& atmosphere, const glm::dvec3& irradiance,
                      const glm::dvec3& sky_irradiance, const ExposureOptions& exposure = {},
                      const NightOptions& night = {});

/// The share of rod vision at an adaptation luminance: 0 at and above photopic_cd_m2, 1 at and
/// below scotopic_cd_m2, linear in log luminance between.
double rod_share(double adaptation_cd_m2, const NightOptions& night = {});

/// The Purkinje shift of a displayed colour: towards its own Rec. 709 luminance in the
/// scotopic tint by rod_share (luminance kept). A fixed-function engine applies it to the light
/// it hands the pipeline (the tint times the share, e.g. as a colour scale of F_ex and L_in).
glm::dvec3 purkinje_shift(const glm::dvec3& rgb, double adaptation_cd_m2,
                          const NightOptions& night = {});

// ---- Stars -------------------------------------------------------------------------------------

struct Star {
    double right_ascension_rad = 0;  ///< J2000
    double declination_rad = 0;
    double magnitude = 0;  ///< visual
};

/// Where Debian's xplanet package puts the Yale Bright Star Catalogue (5th revised edition,
/// 9 096 stars to about magnitude 6.5).
inline constexpr const char* kBrightStarCataloguePath = "/usr/share/xplanet/stars/BSC";

/// Reads a star list in xplanet's format: one star a line, declination (degrees), right ascension
/// (hours) and visual magnitude first, anything after them ignored; '#' lines and blank lines
/// skipped. Errors name the file and the line ("BSC:12: expected declination, right ascension
/// and magnitude").
Result<std::vector<Star>> read_star_catalogue(const std::string& path);

/// The catalogue's places (J2000) moved to a date's apparent places: precession (0.37 deg from
/// 2000 to 2026) and nutation. Once a night is enough (a day moves them by 0.00004 deg).
std::vector<Star> stars_of_date(const std::vector<Star>& stars, const UtcDateTime& time);

/// The local apparent sidereal time, radians (libnova, Meeus ch. 12).
double local_sidereal_time_rad(const UtcDateTime& time, double longitude_rad);

/// Unit vector towards a star (places of the date: stars_of_date) in the east-north-up frame of
/// an observer at `latitude_rad` whose local sidereal time is `sidereal_rad`.
glm::dvec3 star_direction_enu(const Star& star, double latitude_rad, double sidereal_rad);

// ---- Visibility --------------------------------------------------------------------------------

/// The natural night sky's luminance at the zenith on a moonless night far from towns (airglow,
/// zodiacal light and unresolved stars, 22.0 V magnitudes a square arc second), cd/m2.
inline constexpr double kNaturalNightSkyCdM2 = 1.7e-4;

/// The faintest star (visual magnitude, above the atmosphere's dimming) the naked eye sees
/// against a background of `background_cd_m2`: Schaefer's threshold (Schaefer 1990, PASP 102,
/// 212; after Blackwell 1946) I = c1 (1 + sqrt(c2 B))^2 foot-candles with B in nanolamberts
/// (c1 = 10^-9.8, c2 = 10^-1.9 for rod vision, B < 1479 nL; 10^-8.35 and 10^-5.9 above), and
/// m = -16.57 - 2.5 log10 I.
double limiting_magnitude(double background_cd_m2);

/// The model's sky luminance along `direction` (world frame of `view`), cd/m2, lit from
/// view.sun_dir by a light of `light_fraction` times the sun's illuminance (1: the sun; the moon:
/// moonlight_fraction, with view.sun_dir the moon's direction): the height model's chained sky
/// radiance's Rec. 709 luminance over E_sun0's, times kSunIlluminanceLux and light_fraction.
Result<double> sky_luminance_cd_m2(const Atmosphere& atmosphere, const View& view,
                                   const glm::dvec3& direction, double light_fraction = 1.0);

struct StarVisibilityOptions {
    /// Added to the model's sky: the natural night sky (kNaturalNightSkyCdM2).
    double natural_background_cd_m2 = kNaturalNightSkyCdM2;
    /// The sky's luminance is evaluated on a grid of this many elevation rows (and four times as
    /// many azimuth columns) and interpolated: one evaluation a grid node, not a star.
    int elevation_rows = 16;
    /// The moon lighting the sky too (east-north-up, unit), with its moonlight_fraction; a
    /// fraction of 0 leaves it out.
    glm::dvec3 moon_enu{0.0, 0.0, 1.0};
    double moon_fraction = 0.0;
};

/// A star seen: its catalogue index, direction (east-north-up) and magnitude after the
/// atmosphere's dimming along its direction (-2.5 log10 of the G transmittance to space).
struct VisibleStar {
    std::size_t index = 0;
    glm::dvec3 direction{0.0};
    double apparent_magnitude = 0;
    double limiting_magnitude = 0;  ///< the limit in its direction
};

/// How a visible star is drawn: a small glow whose brightness and size grow with how far it is
/// above the eye's limit. r = 10^(0.4 (limit - apparent)) is its flux over the threshold's;
/// brightness = clamp(0.15 + 0.85 log10(r) / 2, 0.15, 1) (full 5 magnitudes above the limit),
/// half-width = pixel_rad * clamp(0.75 + 0.75 log10(r), 0.75, 2.5).
struct StarAppearance {
    glm::dvec3 direction{0.0, 0.0, 1.0};  ///< east-north-up, unit
    float brightness = 0;                 ///< display value of its centre, 0 .. 1
    float half_width_rad = 0;
};
StarAppearance star_appearance(const VisibleStar& star, double pixel_rad);

/// The glow every star is drawn with: a Gaussian spot (sigma a quarter of the half-width), white,
/// `size` x `size` RGBA8 (8 .. 256), in a SunSprite's layout for aerial::gl's sprite textures.
Result<SunSprite> make_star_glow(int size = 16);

/// The stars above the horizon brighter than the limit in their direction, for an observer at
/// `altitude_m` with the sun along `sun_enu` (east-north-up, unit): the view's eye at that
/// altitude with z up. Errors: a bad atmosphere or altitude, as prepare_sky names them.
Result<std::vector<VisibleStar>> visible_stars(const std::vector<Star>& stars,
                                               const Atmosphere& atmosphere, double altitude_m,
                                               const glm::dvec3& sun_enu, double latitude_rad,
                                               double sidereal_rad,
                                               const StarVisibilityOptions& options = {});

}  // namespace aerial
