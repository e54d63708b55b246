// Atmosphere validation, presets and the constructors from turbidity, visibility, ground haze and
// air pollution.
#include "aerial/atmosphere.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "../common/error_text.hpp"
#include "aerial/phase.hpp"

namespace aerial {
namespace {

using detail::invalid;
using detail::number;

/// Largest coefficient accepted, 1/m: a 4 m visibility, denser than any fog. Keeps every optical
/// depth finite in float for distances up to 1e7 m.
constexpr double kMaxCoefficientPerM = 1.0;
constexpr double kMinScaleHeightM = 1.0;
constexpr double kMaxScaleHeightM = 1e6;
constexpr double kMaxRadiusM = 1e9;
/// The ozone layer's centre and width are checked on their own (JSON may give them before the
/// radii), within bounds that keep every altitude and density finite.
constexpr double kMaxOzoneAltitudeM = 1e6;
constexpr double kMinOzoneWidthM = 1.0;
constexpr double kMaxOzoneWidthM = 1e6;
constexpr double kMaxSunIrradiance = 1e6;
constexpr const char* kChannel[3] = {"[0]", "[1]", "[2]"};
constexpr const char* kValidate = "validate";

std::optional<Error> check_coefficients(const char* field, const glm::dvec3& value) {
    for (int c = 0; c < 3; ++c) {
        const double v = value[c];
        if (!(v >= 0.0 && v <= kMaxCoefficientPerM)) {  // NaN too
            return invalid(kValidate, std::string(field) + kChannel[c],
                           "a coefficient in [0, " + number(kMaxCoefficientPerM) + "] 1/m",
                           number(v));
        }
    }
    return std::nullopt;
}

std::optional<Error> check_range(std::string field, double value, double lo, double hi,
                                 const char* unit) {
    if (!(value >= lo && value <= hi)) {  // NaN too
        return invalid(kValidate, std::move(field),
                       "a value in [" + number(lo) + ", " + number(hi) + "] " + unit,
                       number(value));
    }
    return std::nullopt;
}

}  // namespace

bool operator==(const Atmosphere& a, const Atmosphere& b) {
    return a.rayleigh_scattering == b.rayleigh_scattering && a.mie_scattering == b.mie_scattering &&
           a.mie_absorption == b.mie_absorption && a.mie_g == b.mie_g &&
           a.rayleigh_scale_height_m == b.rayleigh_scale_height_m &&
           a.mie_scale_height_m == b.mie_scale_height_m &&
           a.ozone_absorption == b.ozone_absorption &&
           a.ozone_center_altitude_m == b.ozone_center_altitude_m &&
           a.ozone_width_m == b.ozone_width_m && a.planet_radius_m == b.planet_radius_m &&
           a.atmosphere_radius_m == b.atmosphere_radius_m && a.ground_albedo == b.ground_albedo &&
           a.sun_irradiance == b.sun_irradiance;
}

std::optional<Error> validate(const Atmosphere& a) {
    if (auto e = check_coefficients("rayleigh_scattering", a.rayleigh_scattering)) return e;
    if (auto e = check_coefficients("mie_scattering", a.mie_scattering)) return e;
    if (auto e = check_coefficients("mie_absorption", a.mie_absorption)) return e;
    if (!(std::abs(a.mie_g) < 1.0)) {  // NaN too
        return invalid(kValidate, "mie_g", "|g| < 1 (g > 0 scatters forwards)", number(a.mie_g));
    }
    if (auto e = check_range("rayleigh_scale_height_m", a.rayleigh_scale_height_m, kMinScaleHeightM,
                             kMaxScaleHeightM, "m")) {
        return e;
    }
    if (auto e = check_range("mie_scale_height_m", a.mie_scale_height_m, kMinScaleHeightM,
                             kMaxScaleHeightM, "m")) {
        return e;
    }
    if (auto e = check_coefficients("ozone_absorption", a.ozone_absorption)) return e;
    if (auto e = check_range("ozone_center_altitude_m", a.ozone_center_altitude_m, 0.0,
                             kMaxOzoneAltitudeM, "m")) {
        return e;
    }
    if (auto e =
            check_range("ozone_width_m", a.ozone_width_m, kMinOzoneWidthM, kMaxOzoneWidthM, "m")) {
        return e;
    }
    if (auto e = check_range("planet_radius_m", a.planet_radius_m, 1.0, kMaxRadiusM, "m")) {
        return e;
    }
    if (!(a.atmosphere_radius_m > a.planet_radius_m && a.atmosphere_radius_m <= kMaxRadiusM)) {
        return invalid(kValidate, "atmosphere_radius_m",
                       "a value above planet_radius_m (" + number(a.planet_radius_m) +
                           " m) and <= " + number(kMaxRadiusM) + " m",
                       number(a.atmosphere_radius_m));
    }
    for (int c = 0; c < 3; ++c) {
        if (auto e = check_range(std::string("ground_albedo") + kChannel[c], a.ground_albedo[c],
                                 0.0, 1.0, "(Lambertian albedo)")) {
            return e;
        }
    }
    for (int c = 0; c < 3; ++c) {
        if (auto e = check_range(std::string("sun_irradiance") + kChannel[c], a.sun_irradiance[c],
                                 0.0, kMaxSunIrradiance, "(linear RGB)")) {
            return e;
        }
    }
    return std::nullopt;
}

// ---- The 2002 formulas -----------------------------------------------------------------------

double rayleigh_scattering_from_wavelength(double wavelength_m) {
    constexpr double n = 1.0003;    // refractive index of air
    constexpr double N = 2.545e25;  // molecules per m^3 at sea level
    constexpr double p_n = 0.035;   // depolarisation factor
    const double n2m1 = n * n - 1.0;
    const double lambda4 = wavelength_m * wavelength_m * wavelength_m * wavelength_m;
    return 8.0 * kPi * kPi * kPi * n2m1 * n2m1 * (6.0 + 3.0 * p_n) /
           (3.0 * N * lambda4 * (6.0 - 7.0 * p_n));
}

Result<glm::dvec3> mie_scattering_from_turbidity(double turbidity) {
    if (!std::isfinite(turbidity) || turbidity < kMinTurbidity || turbidity > kMaxTurbidity) {
        return invalid("mie_scattering_from_turbidity", "turbidity",
                       "a value in [" + number(kMinTurbidity) + ", " + number(kMaxTurbidity) +
                           "] (Preetham's aerosol fit is not physical below 1.3: its "
                           "concentration turns negative at 0.995)",
                       number(turbidity));
    }
    constexpr double K[3] = {0.685, 0.679, 0.670};
    constexpr double v = 4.0;  // Junge exponent
    const double c = (0.6544 * turbidity - 0.6510) * 1e-16;
    glm::dvec3 beta;
    for (int i = 0; i < 3; ++i) {
        const double lambda_cm = kHp2002WavelengthsM[i] * 100.0;
        const double beta_per_cm =
            0.434 * c * kPi * std::pow(2.0 * kPi / lambda_cm, v - 2.0) * K[i];
        beta[i] = beta_per_cm * 100.0;
    }
    return beta;
}

// ---- Constructors ----------------------------------------------------------------------------

Result<Atmosphere> atmosphere_from_turbidity(double turbidity, const Atmosphere& base) {
    constexpr const char* kFunction = "atmosphere_from_turbidity";
    auto mie = mie_scattering_from_turbidity(turbidity);
    if (!mie) return detail::from(kFunction, mie.error());
    Atmosphere a = base;
    a.mie_scattering = *mie;
    a.mie_absorption = glm::dvec3(0.0);
    if (auto e = validate(a)) return detail::from(kFunction, *e);
    return a;
}

namespace {

std::optional<Error> check_albedo(const char* function, const char* field, double albedo) {
    if (!(albedo > 0.0 && albedo <= 1.0)) {  // NaN too
        return invalid(function, field, "a value in (0, 1]", number(albedo));
    }
    return std::nullopt;
}

std::optional<Error> check_positive_length(const char* function, const char* field,
                                           double value_m) {
    if (!std::isfinite(value_m) || value_m <= 0.0) {
        return invalid(function, field, "a finite length > 0 m", number(value_m));
    }
    return std::nullopt;
}

/// Grey Mie extinction (1/m) that, added to the Rayleigh coefficient of the G channel (550 nm)
/// scaled by `rayleigh_density`, gives `visibility_m` by Koschmieder. Negative when clean air
/// alone is already hazier than that.
double mie_extinction_for_visibility(const Atmosphere& base, double visibility_m,
                                     double rayleigh_density) {
    return kKoschmiederConstant / visibility_m - base.rayleigh_scattering.y * rayleigh_density;
}

void set_grey_mie(Atmosphere& a, double extinction, double albedo) {
    a.mie_scattering = glm::dvec3(extinction * albedo);
    a.mie_absorption = glm::dvec3(extinction * (1.0 - albedo));
}

}  // namespace

Result<Atmosphere> atmosphere_from_visibility(double visibility_m, const Atmosphere& base,
                                              double mie_albedo) {
    constexpr const char* kFunction = "atmosphere_from_visibility";
    if (auto e = check_positive_length(kFunction, "visibility_m", visibility_m)) return *e;
    if (auto e = check_albedo(kFunction, "mie_albedo", mie_albedo)) return *e;
    const double mie = mie_extinction_for_visibility(base, visibility_m, 1.0);
    if (!(mie >= 0.0)) {
        return invalid(kFunction, "visibility_m",
                       "at most " + number(kKoschmiederConstant / base.rayleigh_scattering.y) +
                           " m (clean air alone limits it)",
                       number(visibility_m));
    }
    Atmosphere a = base;
    set_grey_mie(a, mie, mie_albedo);
    if (auto e = validate(a)) return detail::from(kFunction, *e);
    return a;
}

Result<Atmosphere> atmosphere_with_ground_haze(const GroundHaze& haze, const Atmosphere& base) {
    constexpr const char* kFunction = "atmosphere_with_ground_haze";
    if (auto e =
            check_positive_length(kFunction, "visibility_in_layer_m", haze.visibility_in_layer_m)) {
        return *e;
    }
    if (auto e = check_positive_length(kFunction, "layer_thickness_m", haze.layer_thickness_m))
        return *e;
    if (auto e = check_positive_length(kFunction, "visibility_aloft_m", haze.visibility_aloft_m))
        return *e;
    if (auto e = check_albedo(kFunction, "mie_albedo", haze.mie_albedo)) return *e;
    if (haze.visibility_aloft_m <= haze.visibility_in_layer_m) {
        return invalid(
            kFunction, "visibility_aloft_m",
            "more than visibility_in_layer_m (" + number(haze.visibility_in_layer_m) + " m)",
            number(haze.visibility_aloft_m));
    }
    const double ground = mie_extinction_for_visibility(base, haze.visibility_in_layer_m, 1.0);
    if (!(ground > 0.0)) {
        return invalid(kFunction, "visibility_in_layer_m",
                       "less than " + number(kKoschmiederConstant / base.rayleigh_scattering.y) +
                           " m (clean air alone limits it)",
                       number(haze.visibility_in_layer_m));
    }
    const double top_rayleigh_density =
        std::exp(-haze.layer_thickness_m / base.rayleigh_scale_height_m);
    const double top =
        mie_extinction_for_visibility(base, haze.visibility_aloft_m, top_rayleigh_density);
    if (!(top > 0.0)) {
        return invalid(
            kFunction, "visibility_aloft_m",
            "less than " +
                number(kKoschmiederConstant / (base.rayleigh_scattering.y * top_rayleigh_density)) +
                " m at the layer top (clean air alone limits it)",
            number(haze.visibility_aloft_m));
    }
    Atmosphere a = base;
    set_grey_mie(a, ground, haze.mie_albedo);
    a.mie_scale_height_m = haze.layer_thickness_m / std::log(ground / top);
    if (auto e = validate(a)) return detail::from(kFunction, *e);
    return a;
}

Result<Atmosphere> atmosphere_with_air_pollution(double pollution, const Atmosphere& base) {
    if (!std::isfinite(pollution) || pollution < 0.0 || pollution > 1.0) {
        return invalid("atmosphere_with_air_pollution", "pollution", "a value in [0, 1]",
                       number(pollution));
    }
    // Urban aerosol: grey extinction up to kMaxPollutionExtinction at sea level, with a
    // single-scattering albedo that drops towards blue.
    constexpr double kMaxPollutionExtinction = 4e-5;  // 1/m
    const glm::dvec3 albedo{0.8, 0.7, 0.55};
    const double added = pollution * kMaxPollutionExtinction;
    Atmosphere a = base;
    a.mie_scattering += added * albedo;
    a.mie_absorption += added * (glm::dvec3(1.0) - albedo);
    if (auto e = validate(a)) return detail::from("atmosphere_with_air_pollution", *e);
    return a;
}

// ---- Presets ---------------------------------------------------------------------------------

const std::vector<std::string>& atmosphere_preset_names() {
    static const std::vector<std::string> names{"earth", "hp2002", "hazy", "foggy", "mars"};
    return names;
}

namespace {

/// Turbidity of the `hp2002` preset: the clear-day value of the 2002 demo.
constexpr double kHp2002Turbidity = 2.0;

Result<Atmosphere> hp2002() {
    Atmosphere base;
    for (int i = 0; i < 3; ++i) {
        base.rayleigh_scattering[i] = rayleigh_scattering_from_wavelength(kHp2002WavelengthsM[i]);
    }
    return atmosphere_from_turbidity(kHp2002Turbidity, base);
}

Result<Atmosphere> hazy() {
    Atmosphere base;
    base.mie_g = 0.76;
    return atmosphere_from_visibility(12000.0, base, 0.9);
}

Result<Atmosphere> foggy() {
    Atmosphere base;
    base.mie_g = 0.85;  // water droplets scatter strongly forwards
    GroundHaze haze;
    haze.visibility_in_layer_m = 1000.0;
    haze.layer_thickness_m = 500.0;
    haze.visibility_aloft_m = 20000.0;
    return atmosphere_with_ground_haze(haze, base);
}

/// Mars: CO2 Rayleigh (Earth's coefficients times 0.0192 = the surface number density ratio
/// 2.07e23 / 2.55e25 times CO2's (n-1)^2 per molecule, 2.36x air's) and suspended dust with an
/// optical depth of about 0.5, absorbing in blue (the butterscotch sky, blue sunsets), g = 0.63.
/// Surface radius 3389.5 km, scale height 11.1 km, sun 1/1.52^2 of Earth's. No ozone (the
/// layer's centre and width stay earth's, unused); ground albedo 0.25, Mars's mean albedo.
Atmosphere mars() {
    Atmosphere a;
    a.rayleigh_scattering = Atmosphere{}.rayleigh_scattering * 0.0192;
    const double dust_extinction = 4.5e-5;  // 1/m at the datum: tau = 0.5 over 11.1 km
    const glm::dvec3 dust_albedo{0.97, 0.90, 0.70};
    a.mie_scattering = dust_extinction * dust_albedo;
    a.mie_absorption = dust_extinction * (glm::dvec3(1.0) - dust_albedo);
    a.mie_g = 0.63;
    a.rayleigh_scale_height_m = 11100.0;
    a.mie_scale_height_m = 11100.0;
    a.planet_radius_m = 3389.5e3;
    a.atmosphere_radius_m = 3389.5e3 + 100e3;
    a.sun_irradiance = glm::dvec3(1.0 / (1.52 * 1.52));
    a.ozone_absorption = glm::dvec3(0.0);
    a.ground_albedo = glm::dvec3(0.25);
    return a;
}

}  // namespace

Result<Atmosphere> atmosphere_preset(std::string_view name) {
    // The built presets cannot fail; if one did, its error would still be this function's.
    const auto built = [](const Result<Atmosphere>& a) -> Result<Atmosphere> {
        if (!a) return detail::from("atmosphere_preset", a.error());
        return a;
    };
    if (name == "earth") return Atmosphere{};
    if (name == "hp2002") return built(hp2002());
    if (name == "hazy") return built(hazy());
    if (name == "foggy") return built(foggy());
    if (name == "mars") return mars();
    std::string known;
    for (const auto& n : atmosphere_preset_names()) known += (known.empty() ? "" : ", ") + n;
    return invalid("atmosphere_preset", "preset", "one of " + known, detail::quoted(name));
}

}  // namespace aerial
