// The table of the `reference` model's higher orders of scattering: its grid, its lookup and
// the cache of tables per atmosphere. The successive-orders solver that fills it is in
// multiple_scattering_solver.cpp; the method is described in multiple_scattering.hpp.
#include "multiple_scattering.hpp"

#include <algorithm>
#include <cmath>
#include <list>
#include <mutex>
#include <utility>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "table_cache.hpp"

namespace aerial {

bool operator==(const MultipleScatteringSettings& a, const MultipleScatteringSettings& b) {
    return a.altitudes == b.altitudes && a.sun_zenith_angles == b.sun_zenith_angles &&
           a.view_zenith_angles == b.view_zenith_angles && a.azimuths == b.azimuths &&
           a.sky_directions == b.sky_directions && a.ground_directions == b.ground_directions &&
           a.half_azimuths == b.half_azimuths && a.steps_per_efold == b.steps_per_efold &&
           a.max_remainder == b.max_remainder && a.max_orders == b.max_orders;
}

namespace {

/// One row per field: its range. The one source of the limits for validate and clamped.
struct CountField {
    const char* name;
    int MultipleScatteringSettings::*field;
    int min, max;
};
constexpr CountField kCountFields[] = {
    {"altitudes", &MultipleScatteringSettings::altitudes, 4, 256},
    {"sun_zenith_angles", &MultipleScatteringSettings::sun_zenith_angles, 4, 256},
    {"view_zenith_angles", &MultipleScatteringSettings::view_zenith_angles, 5, 257},
    {"azimuths", &MultipleScatteringSettings::azimuths, 3, 256},
    {"sky_directions", &MultipleScatteringSettings::sky_directions, 2, 128},
    {"ground_directions", &MultipleScatteringSettings::ground_directions, 2, 128},
    {"half_azimuths", &MultipleScatteringSettings::half_azimuths, 2, 128},
    {"max_orders", &MultipleScatteringSettings::max_orders, 2, 1000},
};
constexpr double kMinStepsPerEfold = 0.5, kMaxStepsPerEfold = 64.0;
constexpr double kMaxRemainder = 0.5;
constexpr const char* kValidateSettings = "validate";

}  // namespace

std::optional<Error> validate(const MultipleScatteringSettings& s) {
    using detail::invalid;
    using detail::number;
    for (const CountField& f : kCountFields) {
        const int v = s.*(f.field);
        if (v < f.min || v > f.max) {
            return invalid(kValidateSettings, f.name,
                           "a count in [" + number(f.min) + ", " + number(f.max) + "]", number(v));
        }
    }
    if (!(s.steps_per_efold >= kMinStepsPerEfold && s.steps_per_efold <= kMaxStepsPerEfold)) {
        return invalid(
            kValidateSettings, "steps_per_efold",
            "a value in [" + number(kMinStepsPerEfold) + ", " + number(kMaxStepsPerEfold) + "]",
            number(s.steps_per_efold));
    }
    if (!(s.max_remainder > 0.0 && s.max_remainder <= kMaxRemainder)) {
        return invalid(kValidateSettings, "max_remainder",
                       "a fraction in (0, " + number(kMaxRemainder) + "]", number(s.max_remainder));
    }
    return std::nullopt;
}

namespace detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

MultipleScatteringSettings clamped(MultipleScatteringSettings s) {
    for (const CountField& f : kCountFields) s.*(f.field) = std::clamp(s.*(f.field), f.min, f.max);
    s.steps_per_efold = std::isnan(s.steps_per_efold)
                            ? MultipleScatteringSettings{}.steps_per_efold
                            : std::clamp(s.steps_per_efold, kMinStepsPerEfold, kMaxStepsPerEfold);
    if (!(s.max_remainder > 0.0 && s.max_remainder <= kMaxRemainder))
        s.max_remainder = MultipleScatteringSettings{}.max_remainder;
    return s;
}

/// Splits a cell coordinate u in [0, n-1] into a cell and a fraction.
void split(double u, int n, int& cell, double& fraction) {
    u = std::clamp(u, 0.0, double(n - 1));
    cell = std::min(int(u), n - 2);
    fraction = u - cell;
}

}  // namespace

MultipleScatteringTable::MultipleScatteringTable(const Atmosphere& atmosphere,
                                                 const MultipleScatteringSettings& settings)
    : atmosphere_(atmosphere), settings_(clamped(settings)) {
    const double top = atmosphere.atmosphere_radius_m;
    const double ground = atmosphere.planet_radius_m;
    horizon_distance_m_ = std::sqrt((top - ground) * (top + ground));
    const std::string key = table_cache_key(atmosphere_, settings_);
    if (load_cached_table(key, size(), density_, report_)) return;
    density_.assign(size(), glm::dvec3(0.0));
    run_multiple_scattering_solver(*this, atmosphere_, density_, report_);
    store_cached_table(key, density_, report_);
}

std::size_t MultipleScatteringTable::size() const {
    return std::size_t(settings_.altitudes) * settings_.sun_zenith_angles *
           settings_.view_zenith_angles * settings_.azimuths;
}

std::size_t MultipleScatteringTable::index(int i, int j, int a, int b) const {
    return ((std::size_t(i) * settings_.sun_zenith_angles + j) * settings_.view_zenith_angles + a) *
               settings_.azimuths +
           b;
}

// Altitude rows are evenly spaced in rho = sqrt(r^2 - R^2), the distance to the horizon: dense
// near the ground where the density and its changes are.
double MultipleScatteringTable::altitude_coordinate(double altitude_m) const {
    const double h = std::max(altitude_m, 0.0);
    const double rho = std::sqrt(h * (2.0 * atmosphere_.planet_radius_m + h));
    return rho / horizon_distance_m_ * (settings_.altitudes - 1);
}

double MultipleScatteringTable::altitude_m(int i) const {
    const double rho = horizon_distance_m_ * i / (settings_.altitudes - 1);
    const double r =
        std::sqrt(atmosphere_.planet_radius_m * atmosphere_.planet_radius_m + rho * rho);
    return r - atmosphere_.planet_radius_m;
}

double MultipleScatteringTable::sun_zenith_coordinate(double cos_sun_zenith) const {
    return std::acos(std::clamp(cos_sun_zenith, -1.0, 1.0)) / kMaxTableSunZenithRad *
           (settings_.sun_zenith_angles - 1);
}

double MultipleScatteringTable::sun_zenith_rad(int j) const {
    return kMaxTableSunZenithRad * j / (settings_.sun_zenith_angles - 1);
}

double MultipleScatteringTable::view_zenith_coordinate(double cos_view_zenith) const {
    return std::acos(std::clamp(cos_view_zenith, -1.0, 1.0)) / kPi *
           (settings_.view_zenith_angles - 1);
}

double MultipleScatteringTable::view_zenith_rad(int a) const {
    return kPi * a / (settings_.view_zenith_angles - 1);
}

// Azimuth rows are evenly spaced in sin(phi / 2): as fine as evenly spaced angles would be twice
// over near the sun's azimuth, where the Mie lobe of the second order sits, coarser behind.
double MultipleScatteringTable::azimuth_coordinate(double cos_azimuth) const {
    return std::sqrt(0.5 * (1.0 - std::clamp(cos_azimuth, -1.0, 1.0))) * (settings_.azimuths - 1);
}

double MultipleScatteringTable::azimuth_rad(int b) const {
    return 2.0 * std::asin(double(b) / (settings_.azimuths - 1));
}

glm::dvec3 MultipleScatteringTable::interpolate(const std::vector<glm::dvec3>& table, double u_r,
                                                double u_s, double u_a, double u_b) const {
    int i, j, a, b;
    double fi, fj, fa, fb;
    split(u_r, settings_.altitudes, i, fi);
    split(u_s, settings_.sun_zenith_angles, j, fj);
    split(u_a, settings_.view_zenith_angles, a, fa);
    split(u_b, settings_.azimuths, b, fb);
    glm::dvec3 sum(0.0);
    for (int di = 0; di < 2; ++di) {
        const double wi = di ? fi : 1.0 - fi;
        for (int dj = 0; dj < 2; ++dj) {
            const double wj = wi * (dj ? fj : 1.0 - fj);
            for (int da = 0; da < 2; ++da) {
                const double wa = wj * (da ? fa : 1.0 - fa);
                const std::size_t k = index(i + di, j + dj, a + da, b);
                sum += wa * ((1.0 - fb) * table[k] + fb * table[k + 1]);
            }
        }
    }
    return sum;
}

glm::dvec3 MultipleScatteringTable::density(const glm::dvec3& x, const glm::dvec3& view,
                                            const glm::dvec3& sun) const {
    const double r = glm::length(x);
    if (!(r > 0.0) || r > atmosphere_.atmosphere_radius_m) return glm::dvec3(0.0);
    const glm::dvec3 up = x / r;
    const double mu = glm::dot(view, up);
    const double mu_s = glm::dot(sun, up);
    const double nu = glm::dot(view, sun);
    const double across = std::sqrt(std::max(0.0, (1.0 - mu * mu) * (1.0 - mu_s * mu_s)));
    const double cos_azimuth = across > 1e-12 ? (nu - mu * mu_s) / across : 1.0;
    return interpolate(density_, altitude_coordinate(r - atmosphere_.planet_radius_m),
                       sun_zenith_coordinate(mu_s), view_zenith_coordinate(mu),
                       azimuth_coordinate(cos_azimuth));
}

std::shared_ptr<const MultipleScatteringTable> multiple_scattering_table(
    const Atmosphere& lit_atmosphere, const MultipleScatteringSettings& settings) {
    // The tables are per unit E_sun0: atmospheres that differ in it alone share one.
    Atmosphere atmosphere = lit_atmosphere;
    atmosphere.sun_irradiance = glm::dvec3(1.0);
    // The last few tables: a tool or a test alternates between a handful of atmospheres.
    constexpr std::size_t kKept = 6;
    using Entry = std::pair<std::pair<Atmosphere, MultipleScatteringSettings>,
                            std::shared_ptr<const MultipleScatteringTable>>;
    static std::mutex mutex;
    static std::list<Entry> kept;
    // One computation at a time: a second thread asking for the same atmosphere waits for it
    // instead of computing it again (the solver uses every core itself).
    static std::mutex computing;
    std::lock_guard<std::mutex> one_at_a_time(computing);
    {
        std::lock_guard<std::mutex> lock(mutex);
        for (auto it = kept.begin(); it != kept.end(); ++it) {
            if (it->first.first == atmosphere && it->first.second == settings) {
                kept.splice(kept.begin(), kept, it);
                return kept.front().second;
            }
        }
    }
    auto table = std::make_shared<const MultipleScatteringTable>(atmosphere, settings);
    std::lock_guard<std::mutex> lock(mutex);
    kept.emplace_front(std::make_pair(atmosphere, settings), table);
    if (kept.size() > kKept) kept.pop_back();
    return table;
}

}  // namespace detail

Result<MultipleScatteringReport> reference_multiple_scattering(
    const Atmosphere& atmosphere, const MultipleScatteringSettings& settings) {
    if (auto e = validate(atmosphere)) return detail::from("reference_multiple_scattering", *e);
    if (auto e = validate(settings)) return detail::from("reference_multiple_scattering", *e);
    return detail::multiple_scattering_table(atmosphere, settings)->report();
}

}  // namespace aerial
