// The sun: NOAA solar calculator (Meeus' low-precision solar coordinates), sunlight by altitude,
// skylight, exposure and tone curves.
#include "aerial/sun.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "aerial/phase.hpp"
#include "aerial/scattering.hpp"
#include "aerial/sky.hpp"
#include "place.hpp"

namespace aerial {
namespace {

using detail::invalid;
using detail::number;

constexpr double kDeg = kPi / 180.0;
/// Optical depth standing for "shadowed" in the altitude table: exp(-80) is 0 in any 8-bit step.
constexpr double kOpaqueDepth = 80.0;

bool leap_year(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

int days_in_month(int year, int month) {
    static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    return month == 2 && leap_year(year) ? 29 : kDays[month - 1];
}

/// Julian day of 00:00 UTC of a Gregorian date (Meeus ch. 7).
double julian_day_at_midnight(int year, int month, int day) {
    if (month <= 2) {
        year -= 1;
        month += 12;
    }
    const int a = year / 100;
    const int b = 2 - a + a / 4;
    return std::floor(365.25 * (year + 4716)) + std::floor(30.6001 * (month + 1)) + day + b -
           1524.5;
}

/// Solar coordinates at Julian day jd (NOAA's implementation of Meeus ch. 25 and 28).
struct SolarCoordinates {
    double declination_rad;
    double equation_of_time_min;
};

SolarCoordinates solar_coordinates(double jd) {
    const double t = (jd - 2451545.0) / 36525.0;  // Julian centuries since J2000.0
    const double l0 = std::fmod(280.46646 + t * (36000.76983 + t * 0.0003032), 360.0) * kDeg;
    const double m = (357.52911 + t * (35999.05029 - 0.0001537 * t)) * kDeg;
    const double e = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);
    const double c = (std::sin(m) * (1.914602 - t * (0.004817 + 0.000014 * t)) +
                      std::sin(2 * m) * (0.019993 - 0.000101 * t) + std::sin(3 * m) * 0.000289) *
                     kDeg;
    const double true_longitude = l0 + c;
    const double omega = (125.04 - 1934.136 * t) * kDeg;
    const double apparent_longitude = true_longitude - (0.00569 + 0.00478 * std::sin(omega)) * kDeg;
    const double mean_obliquity =
        (23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0) *
        kDeg;
    const double obliquity = mean_obliquity + 0.00256 * std::cos(omega) * kDeg;
    const double declination = std::asin(std::sin(obliquity) * std::sin(apparent_longitude));
    const double y = std::tan(obliquity / 2) * std::tan(obliquity / 2);
    const double eot = y * std::sin(2 * l0) - 2 * e * std::sin(m) +
                       4 * e * y * std::sin(m) * std::cos(2 * l0) - 0.5 * y * y * std::sin(4 * l0) -
                       1.25 * e * e * std::sin(2 * m);
    return {declination, 4.0 * eot / kDeg};
}

/// NOAA's refraction correction (radians) for a geometric elevation (radians).
double refraction_rad(double elevation_rad) {
    const double e = elevation_rad / kDeg;
    double arcsec = 0;
    if (e > 85.0) {
        arcsec = 0;
    } else if (e > 5.0) {
        const double t = std::tan(elevation_rad);
        arcsec = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / std::pow(t, 5);
    } else if (e > -0.575) {
        arcsec = 1735.0 + e * (-518.2 + e * (103.4 + e * (-12.79 + e * 0.711)));
    } else {
        arcsec = -20.772 / std::tan(elevation_rad);
    }
    return arcsec / 3600.0 * kDeg;
}

std::optional<Error> validate_date(const char* function, int year, int month, int day) {
    if (year < 1901 || year > 2099) return invalid(function, "year", "1901 .. 2099", number(year));
    if (month < 1 || month > 12) return invalid(function, "month", "1 .. 12", number(month));
    if (day < 1 || day > days_in_month(year, month)) {
        return invalid(function, "day",
                       "1 .. " + number(days_in_month(year, month)) + " for " + number(year) + "-" +
                           number(month),
                       number(day));
    }
    return std::nullopt;
}

/// Geometric elevation and azimuth from declination, hour angle and latitude (radians).
void horizontal(double declination, double hour_angle, double latitude, double& elevation,
                double& azimuth) {
    const double sin_el = std::sin(latitude) * std::sin(declination) +
                          std::cos(latitude) * std::cos(declination) * std::cos(hour_angle);
    elevation = std::asin(std::clamp(sin_el, -1.0, 1.0));
    // Azimuth clockwise from north: atan2 of the east and north components.
    const double east = -std::cos(declination) * std::sin(hour_angle);
    const double north = std::sin(declination) * std::cos(latitude) -
                         std::cos(declination) * std::sin(latitude) * std::cos(hour_angle);
    azimuth = std::atan2(east, north);
    if (azimuth < 0) azimuth += 2 * kPi;
}

}  // namespace

std::optional<Error> validate(const UtcDateTime& t) {
    constexpr const char* kFunction = "validate";
    if (auto e = validate_date(kFunction, t.year, t.month, t.day)) return e;
    if (t.hour < 0 || t.hour > 23) return invalid(kFunction, "hour", "0 .. 23", number(t.hour));
    if (t.minute < 0 || t.minute > 59)
        return invalid(kFunction, "minute", "0 .. 59", number(t.minute));
    if (!std::isfinite(t.second) || t.second < 0 || t.second >= 61)
        return invalid(kFunction, "second", "a value in [0, 61)", number(t.second));
    return std::nullopt;
}

Result<SunPosition> sun_position(const UtcDateTime& time, double latitude_rad,
                                 double longitude_rad) {
    if (auto e = validate(time)) return detail::from("sun_position", *e);
    if (auto e = detail::validate_place("sun_position", latitude_rad, longitude_rad)) return *e;
    const double minutes = time.hour * 60.0 + time.minute + time.second / 60.0;
    const double jd = julian_day_at_midnight(time.year, time.month, time.day) + minutes / 1440.0;
    const SolarCoordinates sc = solar_coordinates(jd);
    const double true_solar_time_min =
        minutes + sc.equation_of_time_min + 4.0 * longitude_rad / kDeg;
    const double hour_angle = (true_solar_time_min / 4.0 - 180.0) * kDeg;
    SunPosition out;
    out.declination_rad = sc.declination_rad;
    out.equation_of_time_min = sc.equation_of_time_min;
    horizontal(sc.declination_rad, hour_angle, latitude_rad, out.elevation_rad, out.azimuth_rad);
    out.apparent_elevation_rad = out.elevation_rad + refraction_rad(out.elevation_rad);
    return out;
}

glm::dvec3 sun_direction_enu(const SunPosition& sun) {
    return detail::enu_direction(sun.elevation_rad, sun.azimuth_rad);
}

namespace {

/// When the sun's centre crosses `depression_rad` below the horizon before (sign -1) or after
/// (+1) solar noon `noon` (UTC minutes of the day whose midnight is jd0): fixed-point iteration
/// with the declination and the equation of time taken at the event itself. Empty, with the
/// reason, where the sun stays on one side of that depression all day.
struct HourAngleCrossing {
    std::optional<double> utc_min;
    bool never_up = false;    ///< below it all day
    bool never_down = false;  ///< above it all day
};
HourAngleCrossing crossing(double jd0, double noon, double longitude_deg, double latitude_rad,
                           double depression_rad, int sign) {
    const double target = std::cos(kPi / 2 + depression_rad);
    HourAngleCrossing out;
    double when = noon + sign * 360.0;
    for (int i = 0; i < 6; ++i) {
        const SolarCoordinates sc = solar_coordinates(jd0 + when / 1440.0);
        const double cos_ha = (target - std::sin(latitude_rad) * std::sin(sc.declination_rad)) /
                              (std::cos(latitude_rad) * std::cos(sc.declination_rad));
        if (cos_ha > 1.0) {
            out.never_up = true;
            return out;
        }
        if (cos_ha < -1.0) {
            out.never_down = true;
            return out;
        }
        const double ha_deg = std::acos(cos_ha) / kDeg;
        when = 720.0 - 4.0 * longitude_deg - sc.equation_of_time_min + sign * 4.0 * ha_deg;
    }
    out.utc_min = when;
    return out;
}

}  // namespace

Result<SolarEvents> solar_events(int year, int month, int day, double latitude_rad,
                                 double longitude_rad) {
    if (auto e = validate_date("solar_events", year, month, day)) return *e;
    if (auto e = detail::validate_place("solar_events", latitude_rad, longitude_rad)) return *e;
    const double jd0 = julian_day_at_midnight(year, month, day);
    const double longitude_deg = longitude_rad / kDeg;
    SolarEvents out;
    // Solar noon: the hour angle is zero when UTC + EoT + 4 lon = 720 min. Iterate on EoT.
    double noon = 720.0 - 4.0 * longitude_deg;
    for (int i = 0; i < 4; ++i) {
        noon = 720.0 - 4.0 * longitude_deg -
               solar_coordinates(jd0 + noon / 1440.0).equation_of_time_min;
    }
    out.solar_noon_utc_min = noon;
    // Sunrise and sunset: the hour angle where the centre is kSunriseDepressionRad below the
    // horizon, with the declination and EoT taken at the event itself.
    for (int sign : {-1, 1}) {
        const HourAngleCrossing c =
            crossing(jd0, noon, longitude_deg, latitude_rad, kSunriseDepressionRad, sign);
        out.polar_night = out.polar_night || c.never_up;
        out.polar_day = out.polar_day || c.never_down;
        if (c.utc_min) (sign < 0 ? out.sunrise_utc_min : out.sunset_utc_min) = c.utc_min;
        const HourAngleCrossing civil =
            crossing(jd0, noon, longitude_deg, latitude_rad, kCivilTwilightDepressionRad, sign);
        if (civil.utc_min)
            (sign < 0 ? out.civil_dawn_utc_min : out.civil_dusk_utc_min) = civil.utc_min;
    }
    if (!out.civil_dawn_utc_min || !out.civil_dusk_utc_min) {
        out.civil_dawn_utc_min.reset();
        out.civil_dusk_utc_min.reset();
    }
    if (out.polar_day && out.polar_night) out.polar_night = false;  // cannot both hold
    if (!out.sunrise_utc_min || !out.sunset_utc_min) {
        out.sunrise_utc_min.reset();
        out.sunset_utc_min.reset();
    } else {
        out.polar_day = out.polar_night = false;
    }
    return out;
}

glm::dvec3 sun_irradiance_at_altitude(const Atmosphere& atmosphere, double altitude_m,
                                      double sun_elevation_rad) {
    return atmosphere.sun_irradiance *
           sun_transmittance(atmosphere, altitude_m, std::sin(sun_elevation_rad));
}

Result<SunIrradianceProfile> SunIrradianceProfile::build(const Atmosphere& atmosphere,
                                                         double sun_elevation_rad,
                                                         double min_altitude_m,
                                                         double max_altitude_m, int samples) {
    constexpr const char* kFunction = "SunIrradianceProfile::build";
    if (auto e = validate(atmosphere)) return detail::from(kFunction, *e);
    if (!std::isfinite(sun_elevation_rad))
        return invalid(kFunction, "sun_elevation_rad", "a finite value", number(sun_elevation_rad));
    if (!std::isfinite(min_altitude_m) || !std::isfinite(max_altitude_m) ||
        !(max_altitude_m > min_altitude_m)) {
        return invalid(kFunction, "max_altitude_m",
                       "a finite value > min_altitude_m (" + number(min_altitude_m) + ")",
                       number(max_altitude_m));
    }
    if (samples < 2) return invalid(kFunction, "samples", ">= 2", number(samples));
    SunIrradianceProfile p;
    p.min_ = min_altitude_m;
    p.max_ = max_altitude_m;
    p.top_ = atmosphere.sun_irradiance;
    p.depth_.resize(std::size_t(samples));
    for (int i = 0; i < samples; ++i) {
        const double h = min_altitude_m + (max_altitude_m - min_altitude_m) * i / (samples - 1);
        const glm::dvec3 t = sun_transmittance(atmosphere, h, std::sin(sun_elevation_rad));
        for (int c = 0; c < 3; ++c) {
            p.depth_[std::size_t(i)][c] =
                t[c] > 0 ? std::min(-std::log(t[c]), kOpaqueDepth) : kOpaqueDepth;
        }
    }
    return p;
}

glm::dvec3 SunIrradianceProfile::at(double altitude_m) const {
    if (depth_.size() < 2) return glm::dvec3(0.0);  // default-constructed: not built
    const double n = double(depth_.size() - 1);
    const double x = std::clamp((altitude_m - min_) / (max_ - min_), 0.0, 1.0) * n;
    const std::size_t i = std::min(std::size_t(x), depth_.size() - 2);
    const double f = x - double(i);
    const glm::dvec3 d = depth_[i] * (1.0 - f) + depth_[i + 1] * f;
    glm::dvec3 out;
    for (int c = 0; c < 3; ++c) out[c] = d[c] >= kOpaqueDepth ? 0.0 : top_[c] * std::exp(-d[c]);
    return out;
}

Result<glm::dvec3> sky_ambient(const Atmosphere& atmosphere, double altitude_m,
                               double sun_elevation_rad, const SkyAmbientOptions& options) {
    constexpr const char* kFunction = "sky_ambient";
    if (options.elevation_steps < 2) {
        return invalid(kFunction, "elevation_steps", ">= 2", number(options.elevation_steps));
    }
    if (options.azimuth_steps < 4)
        return invalid(kFunction, "azimuth_steps", ">= 4", number(options.azimuth_steps));
    if (!std::isfinite(altitude_m))
        return invalid(kFunction, "altitude_m", "a finite value", number(altitude_m));
    if (!std::isfinite(sun_elevation_rad))
        return invalid(kFunction, "sun_elevation_rad", "a finite value", number(sun_elevation_rad));
    View view;
    view.eye = {0.0, 0.0, altitude_m};
    view.up = {0.0, 0.0, 1.0};
    view.sun_dir = {std::cos(sun_elevation_rad), 0.0, std::sin(sun_elevation_rad)};
    auto sky = prepare_sky(
        atmosphere, view, options.use_reference ? SkyMethod::reference : SkyMethod::height_chained);
    if (!sky) return detail::from(kFunction, sky.error());
    // E = integral of L(mu, phi) mu dmu dphi over mu in [0, 1]: midpoint rule in mu^2 (so the
    // cosine weight is flat: mu dmu = d(mu^2) / 2), midpoint in azimuth.
    glm::dvec3 sum(0.0);
    const int ne = options.elevation_steps, na = options.azimuth_steps;
    for (int i = 0; i < ne; ++i) {
        const double mu = std::sqrt((i + 0.5) / ne);
        const double sin_zenith = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        for (int j = 0; j < na; ++j) {
            const double phi = 2 * kPi * (j + 0.5) / na;
            sum += sky_radiance(*sky, {sin_zenith * std::cos(phi), sin_zenith * std::sin(phi), mu});
        }
    }
    return sum * (kPi / (ne * na));  // 2 pi / na (azimuth) * 1 / ne (mu^2) * 1/2
}

constexpr detail::NameTable<ToneCurve, 2> kToneCurveNames{
    {{ToneCurve::clamp, "clamp"}, {ToneCurve::exponential, "exponential"}}};

std::string_view tone_curve_name(ToneCurve curve) {
    return detail::name_in(kToneCurveNames, curve);
}

Result<ToneCurve> parse_tone_curve(std::string_view name) {
    return detail::parse_in("parse_tone_curve", kToneCurveNames, "tone_curve", name);
}

glm::dvec3 tone_map(const glm::dvec3& linear, double exposure, ToneCurve curve) {
    glm::dvec3 out;
    for (int c = 0; c < 3; ++c) {
        const double x = std::isfinite(linear[c]) ? std::max(0.0, linear[c] * exposure) : 0.0;
        switch (curve) {
            case ToneCurve::clamp:
                out[c] = std::min(x, 1.0);
                break;
            case ToneCurve::exponential:
                out[c] = -std::expm1(-x);
                break;
        }
    }
    return out;
}

double auto_exposure(const glm::dvec3& sun_irradiance, double sun_elevation_rad,
                     const glm::dvec3& sky_irradiance, const glm::dvec3& sun_irradiance_top,
                     const ExposureOptions& options) {
    const double card = options.albedo / kPi;
    const double reference = options.key / std::max(card * luminance(sun_irradiance_top), 1e-30);
    const double lit =
        card *
        luminance(sun_irradiance * std::max(std::sin(sun_elevation_rad), 0.0) + sky_irradiance);
    const double exposure = lit > 0 ? options.key / lit : reference * options.max_gain;
    return std::clamp(exposure, reference * options.min_gain, reference * options.max_gain);
}

std::optional<Error> detail::validate_place(const char* function, double latitude_rad,
                                            double longitude_rad) {
    if (!std::isfinite(latitude_rad) || std::abs(latitude_rad) > kPi / 2) {
        return invalid(function, "latitude", "a value in [-pi/2, pi/2] rad", number(latitude_rad));
    }
    if (!std::isfinite(longitude_rad) || std::abs(longitude_rad) > kPi) {
        return invalid(function, "longitude", "a value in [-pi, pi] rad", number(longitude_rad));
    }
    return std::nullopt;
}

}  // namespace aerial
