// The night sky's sources: the moon (libnova), the bright stars and their visibility. See
// aerial/night.hpp.
#include "aerial/night.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include <libnova/julian_day.h>
#include <libnova/lunar.h>
#include <libnova/nutation.h>
#include <libnova/parallax.h>
#include <libnova/precession.h>
#include <libnova/sidereal_time.h>
#include <libnova/transform.h>
#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/scattering.hpp"
#include "aerial/sky.hpp"
#include "place.hpp"

namespace aerial {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;
constexpr double kKmPerAu = 149597870.7;
constexpr double kMeanMoonDistanceKm = 384400.0;

double julian_day(const UtcDateTime& t) {
    ln_date date{t.year, t.month, t.day, t.hour, t.minute, t.second};
    return ln_get_julian_day(&date);
}

/// A mean place of the date made apparent by nutation (Meeus eq. 23.1; libnova gives the
/// nutation, not this step).
ln_equ_posn nutated(const ln_equ_posn& mean, double jd) {
    ln_nutation n{};
    ln_get_nutation(jd, &n);
    const double a = mean.ra * kDegree, d = mean.dec * kDegree, e = n.ecliptic * kDegree;
    const double dpsi = n.longitude, deps = n.obliquity;  // degrees
    ln_equ_posn out = mean;
    out.ra += (std::cos(e) + std::sin(e) * std::sin(a) * std::tan(d)) * dpsi -
              std::cos(a) * std::tan(d) * deps;
    out.dec += std::sin(e) * std::cos(a) * dpsi + std::sin(a) * deps;
    return out;
}

/// Radiance in units of E_sun0 of `atmosphere` to luminance, cd/m2: its Rec. 709 luminance over
/// E_sun0's, times kSunIlluminanceLux (0 without a sun).
double luminance_scale(const Atmosphere& atmosphere) {
    const double top = luminance(atmosphere.sun_irradiance);
    return top > 0.0 ? kSunIlluminanceLux / top : 0.0;
}

}  // namespace

Result<MoonPosition> moon_position(const UtcDateTime& time, double latitude_rad,
                                   double longitude_rad) {
    constexpr const char* kFunction = "moon_position";
    if (auto e = validate(time)) return aerial::detail::from(kFunction, *e);
    if (auto e = detail::validate_place(kFunction, latitude_rad, longitude_rad)) return *e;
    const double jd = julian_day(time);
    MoonPosition m;
    // libnova's lunar theory gives the mean equator and equinox of J2000: precessed to the date
    // (0.37 deg by 2026), then nutation, for the apparent place that sidereal time goes with.
    ln_equ_posn j2000{}, mean{}, equ{};
    ln_get_lunar_equ_coords(jd, &j2000);
    ln_get_equ_prec2(&j2000, JD2000, jd, &mean);
    equ = nutated(mean, jd);
    m.right_ascension_rad = equ.ra * kDegree;
    m.declination_rad = equ.dec * kDegree;
    m.distance_km = ln_get_lunar_earth_dist(jd);
    m.phase_angle_rad = ln_get_lunar_phase(jd) * kDegree;
    m.illuminated_fraction = ln_get_lunar_disk(jd);
    // Topocentric: the moon's parallax (up to a degree) for an observer at sea level.
    ln_lnlat_posn observer{longitude_rad / kDegree, latitude_rad / kDegree};
    ln_equ_posn shift{};
    ln_get_parallax(&equ, m.distance_km / kKmPerAu, &observer, 0.0, jd, &shift);
    ln_equ_posn topocentric{equ.ra + shift.ra, equ.dec + shift.dec};
    ln_hrz_posn hrz{};
    ln_get_hrz_from_equ(&topocentric, &observer, jd, &hrz);
    m.elevation_rad = hrz.alt * kDegree;
    // libnova counts azimuth from the south, westwards.
    m.azimuth_rad = std::fmod((hrz.az + 180.0) * kDegree, 2.0 * kPi);
    return m;
}

glm::dvec3 moon_direction_enu(const MoonPosition& moon) {
    return detail::enu_direction(moon.elevation_rad, moon.azimuth_rad);
}

double moon_illuminance_lux(double phase_angle_rad, double distance_km) {
    const double alpha = std::abs(phase_angle_rad) / kDegree;
    const double magnitude = -12.73 + 0.026 * alpha + 4e-9 * std::pow(alpha, 4.0);
    // Krisciunas & Schaefer eq. 8: I* = 10^(-0.4 (m + 16.57)) foot-candles; 1 fc = 10.764 lux.
    const double lux = 10.7639 * std::pow(10.0, -0.4 * (magnitude + 16.57));
    const double r = distance_km > 0.0 ? kMeanMoonDistanceKm / distance_km : 1.0;
    return lux * r * r;
}

double moonlight_fraction(const MoonPosition& moon) {
    return moon_illuminance_lux(moon.phase_angle_rad, moon.distance_km) / kSunIlluminanceLux;
}

glm::dvec3 moon_irradiance(const Atmosphere& atmosphere, const MoonPosition& moon) {
    return moonlit(atmosphere, moon).sun_irradiance;
}

Atmosphere moonlit(const Atmosphere& atmosphere, const MoonPosition& moon) {
    return moonlit(atmosphere, moonlight_fraction(moon));
}

Atmosphere moonlit(const Atmosphere& atmosphere, double fraction) {
    Atmosphere out = atmosphere;
    out.sun_irradiance = atmosphere.sun_irradiance * fraction;
    return out;
}

double moon_bright_limb_angle_rad(const glm::dvec3& moon_dir, const glm::dvec3& sun_dir,
                                  const glm::dvec3& up) {
    const glm::dvec3 v = glm::normalize(moon_dir);
    const auto across = [&](const glm::dvec3& d) { return d - glm::dot(d, v) * v; };
    const glm::dvec3 top = across(up), sun = across(sun_dir);
    if (glm::length(top) < 1e-12 || glm::length(sun) < 1e-12) return 0.0;
    const glm::dvec3 y = glm::normalize(top);
    const glm::dvec3 x = glm::cross(v, y);  // the observer's right, looking along v
    // Counterclockwise from the top as seen by the observer: towards -x (the left).
    return std::atan2(-glm::dot(sun, x), glm::dot(sun, y));
}

Result<MoonSprite> make_moon_sprite(double phase_angle_rad, double bright_limb_angle_rad,
                                    int size) {
    constexpr const char* kFunction = "make_moon_sprite";
    if (size < 8 || size > 1024)
        return aerial::detail::invalid(kFunction, "size", "8 .. 1024",
                                       aerial::detail::number(size));
    if (!(phase_angle_rad >= 0.0 && phase_angle_rad <= kPi))
        return aerial::detail::invalid(kFunction, "phase_angle_rad", "a value in [0, pi]",
                                       aerial::detail::number(phase_angle_rad));
    if (!std::isfinite(bright_limb_angle_rad))
        return aerial::detail::invalid(kFunction, "bright_limb_angle_rad", "a finite angle",
                                       aerial::detail::number(bright_limb_angle_rad));
    // The sun as seen from the moon, in the image's frame: x right, y up, z towards the eye.
    const double s_xy = std::sin(phase_angle_rad);
    const glm::dvec3 sun{-s_xy * std::sin(bright_limb_angle_rad),
                         s_xy * std::cos(bright_limb_angle_rad), std::cos(phase_angle_rad)};
    MoonSprite out;
    out.size = size;
    out.rgba.assign(std::size_t(size) * std::size_t(size) * 4, 0);
    std::vector<double> shade(std::size_t(size) * std::size_t(size), 0.0);
    constexpr int kSamples = 4;  // per axis, for the antialiased edge
    double brightest = 0.0;
    std::size_t disc = 0, lit = 0;
    for (int row = 0; row < size; ++row) {
        for (int col = 0; col < size; ++col) {
            int inside = 0;
            double sum = 0.0;
            for (int a = 0; a < kSamples; ++a) {
                for (int b = 0; b < kSamples; ++b) {
                    const double x = 2.0 * (col + (b + 0.5) / kSamples) / size - 1.0;
                    const double y = 1.0 - 2.0 * (row + (a + 0.5) / kSamples) / size;
                    const double r2 = x * x + y * y;
                    if (r2 >= 1.0) continue;
                    ++inside;
                    const glm::dvec3 n{x, y, std::sqrt(1.0 - r2)};
                    const double mu0 = glm::dot(n, sun), mu = n.z;
                    if (mu0 > 0.0) sum += mu0 / (mu0 + mu);
                }
            }
            const std::size_t i = std::size_t(row) * std::size_t(size) + std::size_t(col);
            out.rgba[4 * i + 3] = std::uint8_t(std::lround(255.0 * inside / (kSamples * kSamples)));
            if (inside == 0) continue;
            shade[i] = sum / inside;
            brightest = std::max(brightest, shade[i]);
            if (inside == kSamples * kSamples) {
                ++disc;
                lit += shade[i] > 0.0;
            }
        }
    }
    for (std::size_t i = 0; i < shade.size(); ++i) {
        const auto v = std::uint8_t(
            std::lround(255.0 * (brightest > 0.0 ? std::min(shade[i] / brightest, 1.0) : 0.0)));
        out.rgba[4 * i] = out.rgba[4 * i + 1] = out.rgba[4 * i + 2] = v;
    }
    out.lit_fraction = disc ? double(lit) / double(disc) : 0.0;
    return out;
}

double card_luminance_cd_m2(const Atmosphere& atmosphere, const glm::dvec3& irradiance,
                            double albedo) {
    return albedo / kPi * luminance(irradiance) * luminance_scale(atmosphere);
}

double night_exposure(const Atmosphere& atmosphere, const glm::dvec3& irradiance,
                      const ExposureOptions& exposure, const NightOptions& night) {
    const double card = card_luminance_cd_m2(atmosphere, irradiance, exposure.albedo);
    const double radiance = exposure.albedo / kPi * luminance(irradiance);
    if (!(radiance > 0.0) || !(card > 0.0)) return 0.0;
    const double key =
        card >= night.photopic_cd_m2
            ? exposure.key
            : exposure.key * std::pow(card / night.photopic_cd_m2, night.key_exponent);
    return key / radiance;
}

double night_exposure(const Atmosphere& atmosphere, const glm::dvec3& irradiance,
                      const glm::dvec3& sky_irradiance, const ExposureOptions& exposure,
                      const NightOptions& night) {
    const double value = night_exposure(atmosphere, irradiance, exposure, night);
    const double sky_radiance = luminance(sky_irradiance) / kPi;
    if (!(value > 0.0) || !(sky_radiance > 0.0) || !(night.max_sky_value > 0.0)) return value;
    const double glare = night.max_sky_value / sky_radiance;
    if (value <= glare) return value;
    const double sky_share =
        std::clamp(luminance(sky_irradiance) / luminance(irradiance), 0.0, 1.0);
    return std::exp(std::log(value) - sky_share * (std::log(value) - std::log(glare)));
}

double rod_share(double adaptation_cd_m2, const NightOptions& night) {
    if (!(adaptation_cd_m2 > night.scotopic_cd_m2)) return 1.0;
    if (adaptation_cd_m2 >= night.photopic_cd_m2) return 0.0;
    return std::log(night.photopic_cd_m2 / adaptation_cd_m2) /
           std::log(night.photopic_cd_m2 / night.scotopic_cd_m2);
}

glm::dvec3 purkinje_shift(const glm::dvec3& rgb, double adaptation_cd_m2,
                          const NightOptions& night) {
    const double s = rod_share(adaptation_cd_m2, night);
    const glm::dvec3 rods = luminance(rgb) / luminance(night.scotopic_tint) * night.scotopic_tint;
    return (1.0 - s) * rgb + s * rods;
}

Result<std::vector<Star>> read_star_catalogue(const std::string& path) {
    constexpr const char* kFunction = "read_star_catalogue";
    std::ifstream in(path);
    if (!in) return aerial::detail::error(kFunction, path, "cannot open the file");
    std::vector<Star> stars;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const auto first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream fields(line);
        double dec = 0, ra_hours = 0, magnitude = 0;
        if (!(fields >> dec >> ra_hours >> magnitude) || !(std::abs(dec) <= 90.0) ||
            !(ra_hours >= 0.0 && ra_hours < 24.0) || !std::isfinite(magnitude)) {
            return aerial::detail::error(
                kFunction, path + ":" + std::to_string(number),
                "expected declination (degrees, -90 .. 90), right ascension (hours, 0 .. 24) and "
                "magnitude");
        }
        stars.push_back({ra_hours * 15.0 * kDegree, dec * kDegree, magnitude});
    }
    if (stars.empty()) return aerial::detail::error(kFunction, path, "no star in the file");
    return stars;
}

std::vector<Star> stars_of_date(const std::vector<Star>& stars, const UtcDateTime& time) {
    const double jd = julian_day(time);
    std::vector<Star> out = stars;
    for (Star& star : out) {
        ln_equ_posn j2000{star.right_ascension_rad / kDegree, star.declination_rad / kDegree},
            mean{};
        ln_get_equ_prec2(&j2000, JD2000, jd, &mean);
        const ln_equ_posn apparent = nutated(mean, jd);
        star.right_ascension_rad = std::fmod(apparent.ra * kDegree + 2.0 * kPi, 2.0 * kPi);
        star.declination_rad = apparent.dec * kDegree;
    }
    return out;
}

double local_sidereal_time_rad(const UtcDateTime& time, double longitude_rad) {
    const double gast_hours = ln_get_apparent_sidereal_time(julian_day(time));
    const double lst = gast_hours * 15.0 * kDegree + longitude_rad;
    return std::fmod(std::fmod(lst, 2.0 * kPi) + 2.0 * kPi, 2.0 * kPi);
}

glm::dvec3 star_direction_enu(const Star& star, double latitude_rad, double sidereal_rad) {
    const double hour_angle = sidereal_rad - star.right_ascension_rad;
    const double sd = std::sin(star.declination_rad), cd = std::cos(star.declination_rad);
    const double sl = std::sin(latitude_rad), cl = std::cos(latitude_rad);
    const double up = sl * sd + cl * cd * std::cos(hour_angle);
    const double east = -cd * std::sin(hour_angle);
    const double north = cl * sd - sl * cd * std::cos(hour_angle);
    return {east, north, up};
}

double limiting_magnitude(double background_cd_m2) {
    // In nanolamberts: 1 L = 1 / pi cd/cm2 = 1e4 / pi cd/m2, so 1 nL = 1e-5 / pi cd/m2.
    const double b = std::max(background_cd_m2, 0.0) * kPi * 1e5;
    const bool rods = b < 1479.0;
    const double c1 = std::pow(10.0, rods ? -9.8 : -8.35);
    const double c2 = std::pow(10.0, rods ? -1.9 : -5.9);
    const double threshold = c1 * std::pow(1.0 + std::sqrt(c2 * b), 2.0);
    return -16.57 - 2.5 * std::log10(threshold);
}

Result<double> sky_luminance_cd_m2(const Atmosphere& atmosphere, const View& view,
                                   const glm::dvec3& direction, double light_fraction) {
    constexpr const char* kFunction = "sky_luminance_cd_m2";
    if (!(light_fraction >= 0.0) || !std::isfinite(light_fraction))
        return aerial::detail::invalid(kFunction, "light_fraction", "a finite value >= 0",
                                       aerial::detail::number(light_fraction));
    auto sky = prepare_sky(atmosphere, view, SkyMethod::height_chained);
    if (!sky) return aerial::detail::from(kFunction, sky.error());
    return luminance(sky_radiance(*sky, direction)) * luminance_scale(atmosphere) * light_fraction;
}

StarAppearance star_appearance(const VisibleStar& star, double pixel_rad) {
    const double excess = 0.4 * (star.limiting_magnitude - star.apparent_magnitude);  // log10 r
    StarAppearance a;
    a.direction = star.direction;
    a.brightness = float(std::clamp(0.15 + 0.85 * excess / 2.0, 0.15, 1.0));
    a.half_width_rad = float(pixel_rad * std::clamp(0.75 + 0.75 * excess, 0.75, 2.5));
    return a;
}

Result<SunSprite> make_star_glow(int size) {
    if (size < 8 || size > 256)
        return aerial::detail::invalid("make_star_glow", "size", "8 .. 256",
                                       aerial::detail::number(size));
    SunSprite glow;
    glow.size = size;
    glow.half_width_rad = 0.01;  // the drawer scales each star's quad to its own half-width
    glow.rgba.assign(std::size_t(size) * std::size_t(size) * 4, 0);
    for (int row = 0; row < size; ++row) {
        for (int col = 0; col < size; ++col) {
            const double x = 2.0 * (col + 0.5) / size - 1.0, y = 2.0 * (row + 0.5) / size - 1.0;
            const double v = std::exp(-(x * x + y * y) / (2.0 * 0.25 * 0.25));
            const auto code = std::uint8_t(std::lround(255.0 * v));
            std::uint8_t* p =
                &glow.rgba[4 * (std::size_t(row) * std::size_t(size) + std::size_t(col))];
            p[0] = p[1] = p[2] = code;
            p[3] = 255;
        }
    }
    return glow;
}

namespace {

/// The magnitudes a star loses to the atmosphere (-2.5 log10 of the G transmittance to space)
/// by its elevation: sun_transmittance on kRows elevations evenly from 0 to 90 degrees,
/// interpolated linearly in elevation (within 0.001 magnitudes above 1 degree; the catalogue's
/// 4 500 stars above the horizon took half a second one transmittance each).
class StarDimming {
  public:
    static constexpr int kRows = 512;
    StarDimming(const Atmosphere& atmosphere, double altitude_m) : table_(kRows + 1) {
        for (int r = 0; r <= kRows; ++r) {
            const double t =
                sun_transmittance(atmosphere, altitude_m, std::sin(0.5 * kPi * r / kRows)).y;
            table_[std::size_t(r)] = t > 0.0 ? -2.5 * std::log10(t) : kInfinity;
        }
    }
    /// Infinite where no light gets through.
    double magnitudes(double sin_elevation) const {
        const double x = std::asin(std::clamp(sin_elevation, 0.0, 1.0)) / (0.5 * kPi) * kRows;
        const int r = std::min(int(x), kRows - 1);
        const double a = table_[std::size_t(r)], b = table_[std::size_t(r) + 1];
        if (!std::isfinite(a) || !std::isfinite(b)) return x - r < 0.5 ? a : b;
        return a + (x - r) * (b - a);
    }

  private:
    static constexpr double kInfinity = std::numeric_limits<double>::infinity();
    std::vector<double> table_;
};

}  // namespace

Result<std::vector<VisibleStar>> visible_stars(const std::vector<Star>& stars,
                                               const Atmosphere& atmosphere, double altitude_m,
                                               const glm::dvec3& sun_enu, double latitude_rad,
                                               double sidereal_rad,
                                               const StarVisibilityOptions& options) {
    constexpr const char* kFunction = "visible_stars";
    if (options.elevation_rows < 2 || options.elevation_rows > 1024)
        return aerial::detail::invalid(kFunction, "elevation_rows", "2 .. 1024",
                                       aerial::detail::number(options.elevation_rows));
    if (!(options.natural_background_cd_m2 >= 0.0) ||
        !std::isfinite(options.natural_background_cd_m2))
        return aerial::detail::invalid(kFunction, "natural_background_cd_m2", "a finite value >= 0",
                                       aerial::detail::number(options.natural_background_cd_m2));
    if (!(options.moon_fraction >= 0.0) || !std::isfinite(options.moon_fraction))
        return aerial::detail::invalid(kFunction, "moon_fraction", "a finite value >= 0",
                                       aerial::detail::number(options.moon_fraction));
    View view;
    view.eye = {0.0, 0.0, altitude_m};
    view.up = {0.0, 0.0, 1.0};
    view.sun_dir = sun_enu;
    auto sky = prepare_sky(atmosphere, view, SkyMethod::height_chained);
    if (!sky) return aerial::detail::from(kFunction, sky.error());
    std::optional<SkyContext> moon_sky;
    if (options.moon_fraction > 0.0) {
        view.sun_dir = options.moon_enu;
        auto made = prepare_sky(atmosphere, view, SkyMethod::height_chained);
        if (!made) return aerial::detail::from(kFunction, made.error());
        moon_sky = std::move(made).value();
    }
    const double scale = luminance_scale(atmosphere);
    // The sky's luminance on a grid of elevation (0 .. 90 deg) x azimuth (from east, 0 .. 360).
    const int rows = options.elevation_rows, columns = 4 * rows;
    std::vector<double> grid(std::size_t(rows + 1) * std::size_t(columns + 1));
    for (int r = 0; r <= rows; ++r) {
        const double e = 0.5 * kPi * r / rows;
        for (int c = 0; c <= columns; ++c) {
            const double a = 2.0 * kPi * c / columns;
            const glm::dvec3 d{std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
            double l = luminance(sky_radiance(*sky, d));
            if (moon_sky) l += options.moon_fraction * luminance(sky_radiance(*moon_sky, d));
            grid[std::size_t(r) * std::size_t(columns + 1) + std::size_t(c)] = l * scale;
        }
    }
    const auto sky_at = [&](const glm::dvec3& d) {
        const double e = std::asin(std::clamp(d.z, 0.0, 1.0)) / (0.5 * kPi) * rows;
        double a = std::atan2(d.y, d.x);
        if (a < 0.0) a += 2.0 * kPi;
        a = a / (2.0 * kPi) * columns;
        const int r = std::min(int(e), rows - 1), c = std::min(int(a), columns - 1);
        const double fr = e - r, fc = a - c;
        const auto at = [&](int i, int j) {
            return grid[std::size_t(i) * std::size_t(columns + 1) + std::size_t(j)];
        };
        return (1 - fr) * ((1 - fc) * at(r, c) + fc * at(r, c + 1)) +
               fr * ((1 - fc) * at(r + 1, c) + fc * at(r + 1, c + 1));
    };
    const StarDimming dimming(atmosphere, altitude_m);
    std::vector<VisibleStar> seen;
    for (std::size_t i = 0; i < stars.size(); ++i) {
        const glm::dvec3 d = star_direction_enu(stars[i], latitude_rad, sidereal_rad);
        if (d.z <= 0.0) continue;
        const double dimmed = dimming.magnitudes(d.z);
        if (!std::isfinite(dimmed)) continue;
        VisibleStar v;
        v.index = i;
        v.direction = d;
        v.apparent_magnitude = stars[i].magnitude + dimmed;
        v.limiting_magnitude = limiting_magnitude(sky_at(d) + options.natural_background_cd_m2);
        if (v.apparent_magnitude < v.limiting_magnitude) seen.push_back(v);
    }
    return seen;
}

}  // namespace aerial
