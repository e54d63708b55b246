// aerial/atmosphere.hpp — the atmosphere: coefficients, presets, constructors, JSON.
//
// How to use this:
//   1. Start from a preset: `aerial::atmosphere_preset("earth")` (names: earth, hp2002, hazy,
//      foggy, mars), or from JSON: `aerial::atmosphere_from_json(text)`.
//   2. Or build one from what you know about the weather: `atmosphere_from_turbidity(3.0)`,
//      `atmosphere_from_visibility(20000.0)`, `atmosphere_with_ground_haze({...})`,
//      `atmosphere_with_air_pollution(0.5)`.
//   3. Edit fields freely, then call `validate(atmosphere)` once: it names the first bad field.
//      Everything downstream assumes a validated atmosphere.
//
// The Rayleigh and Mie coefficients are per metre at sea level (altitude 0) and fall off
// exponentially with altitude: beta(h) = beta(0) * exp(-h / scale_height). Ozone absorbs in a
// tent-shaped layer aloft instead: ozone_absorption * ozone_density(h).
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/error.hpp"

namespace aerial {

/// Physical description of a planet's atmosphere (docs/conventions.md, Physics). Defaults are the
/// `earth` preset.
/// Channels are R, G, B, taken at 680, 550 and 440 nm for `earth`.
struct Atmosphere {
    /// Rayleigh (molecular) scattering coefficient at sea level, 1/m, each >= 0.
    /// Rayleigh extinction equals scattering (no molecular absorption is modelled).
    glm::dvec3 rayleigh_scattering{5.802e-6, 13.558e-6, 33.1e-6};
    /// Mie (aerosol) scattering coefficient at sea level, 1/m, each >= 0.
    glm::dvec3 mie_scattering{3.996e-6, 3.996e-6, 3.996e-6};
    /// Mie absorption coefficient at sea level, 1/m, each >= 0. Mie extinction is
    /// mie_scattering + mie_absorption.
    glm::dvec3 mie_absorption{0.0, 0.0, 0.0};
    /// Henyey–Greenstein asymmetry, |g| < 1; g > 0 scatters forwards (bright towards the sun).
    /// The 2002 slides use the opposite sign: see `mie_g_from_2002_slides()` in phase.hpp.
    double mie_g = 0.8;
    /// Rayleigh density scale height, m, > 0.
    double rayleigh_scale_height_m = 8000.0;
    /// Mie density scale height, m, > 0.
    double mie_scale_height_m = 1200.0;
    /// Ozone absorption coefficient at the peak of the ozone layer, 1/m, each in [0, 1] (as every
    /// coefficient). Ozone scatters nothing: its extinction is this times ozone_density(h).
    /// `earth`: Bruneton 2017's values (also Hillaire 2020's): ozone's absorption cross sections
    /// at 680, 550 and 440 nm times the peak number density of a 300 Dobson unit column spread
    /// over earth's tent profile (the next two fields).
    glm::dvec3 ozone_absorption{0.650e-6, 1.881e-6, 0.085e-6};
    /// Altitude of the peak of the ozone layer's tent profile, m, in [0, 1e6] (not checked against
    /// the atmosphere top). `earth`: 25000 (Bruneton 2017).
    double ozone_center_altitude_m = 25000.0;
    /// Full width of the ozone layer's tent profile, m, in [1, 1e6]: the density falls linearly
    /// from 1 at ozone_center_altitude_m to 0 at ozone_center_altitude_m +- ozone_width_m / 2.
    /// `earth`: 30000, i.e. ozone from 10 km to 40 km (Bruneton 2017's two linear layers).
    double ozone_width_m = 30000.0;
    /// Radius of the planet (sea level), m, > 0.
    double planet_radius_m = 6360e3;
    /// Radius of the top of the atmosphere, m, > planet_radius_m. The `reference` model has no
    /// air above it; the other models ignore it except when computing sun transmittance.
    double atmosphere_radius_m = 6420e3;
    /// Lambertian albedo of the ground (the sea-level sphere), each in [0, 1]. `earth`: 0.1 on
    /// every channel, the value of Bruneton 2017's demo.
    glm::dvec3 ground_albedo{0.1, 0.1, 0.1};
    /// Sun irradiance at the top of the atmosphere (E_sun0), linear RGB, each >= 0.
    glm::dvec3 sun_irradiance{1.0, 1.0, 1.0};

    glm::dvec3 mie_extinction() const { return mie_scattering + mie_absorption; }
    /// Extinction at sea level (altitude 0), 1/m: Rayleigh plus Mie. It leaves out ozone, whose
    /// density at sea level is 0 for `earth` (ozone_density(0) = 0 whenever the layer's lower edge,
    /// ozone_center_altitude_m - ozone_width_m / 2, is at or above sea level); an atmosphere whose
    /// ozone layer reaches the ground has ozone_absorption * ozone_density(0) more there.
    glm::dvec3 extinction() const { return rayleigh_scattering + mie_extinction(); }
    /// Relative ozone density at `altitude_m` (m above sea level), in [0, 1]: the tent profile,
    /// 1 at ozone_center_altitude_m falling linearly to 0 at ozone_center_altitude_m +-
    /// ozone_width_m / 2, and 0 beyond (and for a NaN altitude). Multiply by ozone_absorption
    /// for the ozone extinction there.
    double ozone_density(double altitude_m) const {
        const double density =
            1.0 - std::abs(altitude_m - ozone_center_altitude_m) / (0.5 * ozone_width_m);
        return density > 0.0 ? density : 0.0;
    }
};

/// Every field equal (exact floating-point comparison): the one way caches decide whether the
/// atmosphere changed.
bool operator==(const Atmosphere& a, const Atmosphere& b);
inline bool operator!=(const Atmosphere& a, const Atmosphere& b) { return !(a == b); }

/// The first bad field and why: non-finite values, negative coefficients, |g| >= 1,
/// non-positive scale heights or radii, an ozone layer centre outside [0, 1e6] m or width outside
/// [1, 1e6] m, an atmosphere top not above the planet, a ground albedo outside [0, 1].
std::optional<Error> validate(const Atmosphere& atmosphere);

// ---- Presets ---------------------------------------------------------------------------------

/// Names accepted by `atmosphere_preset`, in a fixed order.
const std::vector<std::string>& atmosphere_preset_names();

/// A named preset: `earth`, `hp2002`, `hazy`, `foggy`, `mars`. Unknown names are an error that
/// lists the known ones.
Result<Atmosphere> atmosphere_preset(std::string_view name);

// ---- The 2002 formulas -----------------------------------------------------------------------

/// Wavelengths the 2002 talk uses for R, G, B, m.
inline constexpr double kHp2002WavelengthsM[3] = {650e-9, 570e-9, 475e-9};

/// Rayleigh total scattering coefficient of air, 1/m, from the 2002 talk:
/// beta_R = 8 pi^3 (n^2-1)^2 (6+3 p_n) / (3 N lambda^4 (6-7 p_n)),
/// n = 1.0003 (refractive index), N = 2.545e25 1/m^3 (molecular density), p_n = 0.035
/// (depolarisation). Gives about 6.95e-6, 1.18e-5, 2.44e-5 at 650, 570, 475 nm.
double rayleigh_scattering_from_wavelength(double wavelength_m);

/// Lowest turbidity accepted by the turbidity constructors. Preetham's fit of the aerosol
/// concentration c(T) = (0.6544 T - 0.6510) 1e-16 reaches zero at T = 0.995 and the fitted data
/// start around T = 2; below 1.3 its results are not physical.
inline constexpr double kMinTurbidity = 1.3;
/// Highest turbidity accepted (beyond it the sky is fog, use visibility instead).
inline constexpr double kMaxTurbidity = 64.0;

/// Mie (haze) total scattering coefficient, 1/m, from Preetham's turbidity formula as used in
/// 2002: beta_M = 0.434 c pi (2 pi / lambda)^(v-2) K, c = (0.6544 T - 0.6510) 1e-16, v = 4,
/// K = 0.685, 0.679, 0.670 at 650, 570, 475 nm. The formula is in CGS units (lambda in cm,
/// beta in 1/cm): taken literally in metres it is 100x too large (a 600 m visibility at T = 2);
/// this function converts. At T = 2 it gives 7.9e-5 /m at 570 nm, i.e. an aerosol optical depth
/// of about 0.1 with a 1200 m scale height, matching Rayleigh's as T = 2 means.
/// Rejects T outside [kMinTurbidity, kMaxTurbidity].
Result<glm::dvec3> mie_scattering_from_turbidity(double turbidity);

// ---- Constructors from what users know -------------------------------------------------------

/// `base` with its Mie scattering replaced by Preetham's turbidity formula (absorption cleared).
Result<Atmosphere> atmosphere_from_turbidity(double turbidity, const Atmosphere& base = {});

/// Koschmieder's constant: visibility V (m) and extinction beta (1/m) relate by beta = 3.912 / V
/// (2 % contrast threshold).
inline constexpr double kKoschmiederConstant = 3.912;

/// `base` with its sea-level Mie extinction set so that the total extinction at 550 nm (the G
/// channel) gives `visibility_m` by Koschmieder. Mie stays grey; its single-scattering albedo is
/// `mie_albedo` (1 = no absorption). Rejects visibilities that clean air alone already forbids
/// (beyond 3.912 / rayleigh_scattering.g, about 288 km for earth).
Result<Atmosphere> atmosphere_from_visibility(double visibility_m, const Atmosphere& base = {},
                                              double mie_albedo = 1.0);

/// A ground haze layer in FlightGear's terms.
struct GroundHaze {
    double visibility_in_layer_m = 1000.0;  ///< horizontal visibility at the ground, m, > 0
    double layer_thickness_m = 500.0;       ///< height of the layer top above sea level, m, > 0
    double visibility_aloft_m = 20000.0;    ///< visibility just above the layer, m, > the above
    double mie_albedo = 1.0;                ///< single-scattering albedo of the haze, (0, 1]
};

/// `base` with its Mie profile fitted to a ground haze layer. The module keeps one exponential
/// aerosol profile (so all three models, and the GPU path, handle haze alike): its sea-level
/// coefficient gives `visibility_in_layer_m`, its scale height makes the visibility at the
/// layer top equal `visibility_aloft_m`. Above the layer the haze keeps thinning.
Result<Atmosphere> atmosphere_with_ground_haze(const GroundHaze& haze, const Atmosphere& base = {});

/// `base` with absorbing urban aerosol added, FlightGear's "air pollution" slider in 0..1: up to
/// 4e-5 /m of grey extinction at sea level (an optical depth of 0.05 over the Mie scale height
/// of earth) whose single-scattering albedo drops from 0.8 in red to 0.55 in blue (soot, brown
/// carbon), dimming and yellowing the haze. 0 returns `base` unchanged.
Result<Atmosphere> atmosphere_with_air_pollution(double pollution, const Atmosphere& base = {});

// ---- JSON ------------------------------------------------------------------------------------

/// Parses the atmosphere JSON of docs/conventions.md, Interfaces: an object with any of
/// `rayleigh_scattering` [3], `mie_scattering` [3], `mie_absorption` [3], `mie_g`,
/// `rayleigh_scale_height_m`, `mie_scale_height_m`, `ozone_absorption` [3],
/// `ozone_center_altitude_m`, `ozone_width_m`, `planet_radius_m`, `atmosphere_radius_m`,
/// `ground_albedo` (a number for every channel, or [3]), `sun_irradiance` [3].
/// Missing fields keep the `earth` values, except mie_absorption, ozone_absorption and
/// ground_albedo, which are 0 when missing; unknown fields, malformed JSON and invalid values
/// are errors naming the field. The result is validated.
Result<Atmosphere> atmosphere_from_json(std::string_view json_text);

/// Reads and parses a file; errors name the path.
Result<Atmosphere> load_atmosphere_json(const std::string& path);

/// The JSON form of an atmosphere (every field, round-trips through atmosphere_from_json).
std::string to_json(const Atmosphere& atmosphere);

}  // namespace aerial
