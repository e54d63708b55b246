// The successive-orders solver that fills the `reference` model's table of higher orders
// (method: multiple_scattering.hpp). Everything is double precision; the work is split over
// the machine's cores by altitude row.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "aerial/phase.hpp"
#include "math.hpp"
#include "multiple_scattering.hpp"
#include "worker_pool.hpp"

namespace aerial::detail {
namespace {

using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
/// Optical depth beyond which the rest of a ray is hidden (e^-40 = 4e-18).
constexpr double kOpaqueDepth = 40.0;
/// Most steps along one ray (a guard; ordinary atmospheres need well under a hundred).
constexpr int kMaxRaySteps = 400;

/// Runs body(row) for row in [0, rows) on every core, through the batch shading's worker pool.
template <class Body>
void parallel_rows(int rows, const Body& body) {
    static const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    WorkerPool::instance().run(hardware, std::size_t(rows), 1,
                               [&](std::size_t first, std::size_t last) {
                                   for (std::size_t row = first; row < last; ++row) body(int(row));
                               });
}

/// The air: densities and the Rayleigh and Mie extinction at an altitude (ozone's optical depth
/// comes from its closed-form column, as in the integrator).
struct Air {
    const Atmosphere& a;
    dvec3 mie_extinction;
    double min_altitude_m;

    explicit Air(const Atmosphere& atmosphere)
        : a(atmosphere),
          mie_extinction(atmosphere.mie_extinction()),
          min_altitude_m(min_density_altitude_m(atmosphere)) {}

    double rayleigh_density(double h) const {
        return std::exp(-std::max(h, min_altitude_m) / a.rayleigh_scale_height_m);
    }
    double mie_density(double h) const {
        return std::exp(-std::max(h, min_altitude_m) / a.mie_scale_height_m);
    }
    dvec3 extinction(double h) const {
        return a.rayleigh_scattering * rayleigh_density(h) + mie_extinction * mie_density(h);
    }
    /// Scale height (m) of the fastest-changing part of the extinction that matters at h.
    double changing_scale_m(double h) const {
        const double k_r =
            std::max({a.rayleigh_scattering.x, a.rayleigh_scattering.y, a.rayleigh_scattering.z}) *
            rayleigh_density(h);
        const double k_m =
            std::max({mie_extinction.x, mie_extinction.y, mie_extinction.z}) * mie_density(h);
        double scale = std::max(a.rayleigh_scale_height_m, a.mie_scale_height_m);
        if (k_r > 1e-6 * k_m) scale = std::min(scale, a.rayleigh_scale_height_m);
        if (k_m > 1e-6 * k_r) scale = std::min(scale, a.mie_scale_height_m);
        return scale;
    }
};

/// Sun transmittance from space, tabulated over altitude and the sun's zenith cosine above the
/// planet's horizon (dense near it), zero below it.
class SunTable {
  public:
    /// Twice the table's altitude rows and four times its sun rows (the sun's transmittance
    /// changes faster than the scattering it lights).
    SunTable(const Atmosphere& atmosphere, const MultipleScatteringSettings& settings)
        : a_(atmosphere),
          altitudes_(2 * settings.altitudes),
          cosines_(4 * settings.sun_zenith_angles) {
        depth_.resize(altitudes_ * cosines_);
        parallel_rows(altitudes_, [&](int i) {
            const double h = altitude(i);
            const double horizon = horizon_cosine(h);
            for (int c = 0; c < cosines_; ++c) {
                const double x = double(c) / (cosines_ - 1);
                const double mu = horizon + (1.0 - horizon) * x * x;
                const dvec3 t = sun_transmittance(a_, h, std::min(1.0, mu + 1e-12));
                depth_[i * cosines_ + c] = -glm::log(glm::max(t, dvec3(1e-300)));
            }
        });
    }

    dvec3 transmittance(double h, double mu_s) const {
        h = std::clamp(h, 0.0, top());
        const double horizon = horizon_cosine(h);
        if (mu_s < horizon) return dvec3(0.0);
        const double u = std::sqrt(h / top()) * (altitudes_ - 1);
        const double v = std::sqrt((mu_s - horizon) / (1.0 - horizon)) * (cosines_ - 1);
        const int i = std::min(int(u), altitudes_ - 2);
        const int c = std::min(int(v), cosines_ - 2);
        const double fi = std::min(u - i, 1.0), fc = std::min(v - c, 1.0);
        const dvec3 d =
            (1 - fi) * ((1 - fc) * depth_[i * cosines_ + c] + fc * depth_[i * cosines_ + c + 1]) +
            fi * ((1 - fc) * depth_[(i + 1) * cosines_ + c] +
                  fc * depth_[(i + 1) * cosines_ + c + 1]);
        return glm::exp(-d);
    }

  private:
    double top() const { return a_.atmosphere_radius_m - a_.planet_radius_m; }
    double altitude(int i) const {
        const double u = double(i) / (altitudes_ - 1);
        return top() * u * u;
    }
    double horizon_cosine(double h) const { return detail::horizon_cosine(a_.planet_radius_m, h); }

    const Atmosphere& a_;
    const int altitudes_;  // rows in altitude (squared spacing) and in cosine
    const int cosines_;
    std::vector<dvec3> depth_;
};

/// One sample along a ray: where the table is read and how much it counts.
struct Sample {
    dvec3 up;      // unit zenith at the sample
    dvec3 weight;  // transmittance from the ray's origin times the step, m
    double u_r;    // table coordinates of the altitude and the view zenith
    double u_a;
    double rho_r;  // Rayleigh and Mie densities (order 1's exact scattering density)
    double rho_m;
    double altitude_m;
};

/// A ray from a row's point along one of its directions, to the top or to the ground.
struct Ray {
    std::vector<Sample> samples;
    bool hits_ground = false;
    dvec3 ground_up{0.0};
    dvec3 ground_transmittance{0.0};
};

class Solver {
  public:
    Solver(const MultipleScatteringTable& table, const Atmosphere& atmosphere)
        : t_(table),
          s_(table.settings()),
          a_(atmosphere),
          air_(atmosphere),
          sun_(atmosphere, table.settings()) {
        for (int j = 0; j < s_.sun_zenith_angles; ++j) {
            const double theta = t_.sun_zenith_rad(j);
            suns_.emplace_back(std::sin(theta), 0.0, std::cos(theta));
        }
        rows_.resize(s_.altitudes);
        parallel_rows(s_.altitudes, [&](int i) { build_row(i); });
    }

    void run(std::vector<dvec3>& total, MultipleScatteringReport& report) {
        const int n_sun = s_.sun_zenith_angles;
        std::vector<dvec3> ground_previous(n_sun, dvec3(0.0));  // unused for order 1
        std::vector<dvec3> density;                             // J_n, n >= 2
        std::vector<dvec3> next(t_.size());
        dvec3 sum_all(0.0), previous_sum(0.0);
        // Stopped by max_orders before two orders could be compared: the bound is unknown.
        report.remainder_bound = dvec3(std::numeric_limits<double>::infinity());
        for (int order = 1; order < s_.max_orders; ++order) {
            // Radiance of this order along every direction of every row and sun row.
            std::vector<dvec3> ground(n_sun, dvec3(0.0));
            parallel_rows(s_.altitudes, [&](int i) {
                Row& row = rows_[i];
                row.radiance.assign(row.rays.size() * n_sun, dvec3(0.0));
                for (std::size_t k = 0; k < row.rays.size(); ++k) {
                    for (int j = 0; j < n_sun; ++j) {
                        row.radiance[k * n_sun + j] = radiance(row.rays[k], row.directions[k].w, j,
                                                               order, density, ground_previous);
                    }
                }
            });
            std::vector<dvec3> at_ground(rows_[0].directions.size());
            for (int j = 0; j < n_sun; ++j) {
                for (std::size_t k = 0; k < at_ground.size(); ++k)
                    at_ground[k] = rows_[0].radiance[k * n_sun + j];
                ground[j] = horizontal_irradiance(rows_[0].directions, at_ground);
            }
            // The next order's scattering density.
            parallel_rows(s_.altitudes, [&](int i) { scatter_row(i, next); });
            dvec3 sum(0.0);
            for (const dvec3& v : next) sum += v;
            report.order_sums.push_back(sum);
            if (total.empty()) total.assign(next.size(), dvec3(0.0));
            for (std::size_t c = 0; c < next.size(); ++c) total[c] += next[c];
            sum_all += sum;
            report.orders = order + 1;
            density.swap(next);
            next.assign(t_.size(), dvec3(0.0));
            ground_previous.swap(ground);
            if (order >= 2 && converged(sum, previous_sum, sum_all, report)) break;
            previous_sum = sum;
        }
    }

  private:
    struct Row {
        std::vector<IncomingDirection> directions;
        std::vector<Ray> rays;
        // Scattering matrices (views x directions), rows summing to 1.
        std::vector<double> rayleigh, mie;
        std::vector<dvec3> radiance;  // per direction, per sun row
    };

    /// Whether the orders not summed are below the bound; fills report.remainder_bound.
    bool converged(const dvec3& last, const dvec3& previous, const dvec3& all,
                   MultipleScatteringReport& report) const {
        bool done = true;
        for (int c = 0; c < 3; ++c) {
            if (!(last[c] > 0.0) || !(all[c] > 0.0)) {
                report.remainder_bound[c] = 0.0;
                continue;
            }
            const double q = previous[c] > 0.0 ? last[c] / previous[c] : 1.0;
            report.remainder_bound[c] = q < 1.0 ? q / (1.0 - q) * last[c] / all[c]
                                                : std::numeric_limits<double>::infinity();
            if (!(report.remainder_bound[c] < s_.max_remainder)) done = false;
        }
        return done;
    }

    void build_row(int i) {
        Row& row = rows_[i];
        const double r = a_.planet_radius_m + t_.altitude_m(i);
        row.directions = incoming_directions(a_, s_, t_.altitude_m(i));
        for (const IncomingDirection& d : row.directions) row.rays.push_back(trace(r, d.w));
        build_matrices(row);
    }

    /// Samples the ray from (0, 0, r) along w: midpoints of steps short enough for the density
    /// and the optical depth to change by 1/steps_per_efold of an e-fold.
    Ray trace(double r, const dvec3& w) const {
        Ray ray;
        const dvec3 x(0.0, 0.0, r);
        const double top = a_.atmosphere_radius_m, ground = a_.planet_radius_m;
        const double across2 = r * r * (1.0 - w.z * w.z);
        double length = -r * w.z + std::sqrt(std::max(0.0, top * top - across2));
        if (w.z < 0.0 && across2 < ground * ground) {
            length = std::max(0.0, -r * w.z - std::sqrt(ground * ground - across2));
            ray.hits_ground = true;
        }
        const double spe = s_.steps_per_efold;
        // Ozone's optical depth from the origin to t: the column to the top from the origin
        // minus the column from there on (ozone_column_m).
        const double column_from_origin = ozone_column_m(a_, r - ground, w.z);
        auto ozone_to = [&](double t) {
            const dvec3 y = x + w * t;
            const double ry = glm::length(y);
            return a_.ozone_absorption *
                   std::max(0.0, column_from_origin -
                                     ozone_column_m(a_, ry - ground, glm::dot(y, w) / ry));
        };
        dvec3 tau(0.0);  // Rayleigh and Mie
        double t = 0.0;
        while (t < length && int(ray.samples.size()) < kMaxRaySteps) {
            const dvec3 y = x + w * t;
            const double ry = glm::length(y);
            const double hy = ry - ground;
            const dvec3 k = air_.extinction(hy);
            const double k_max = std::max({k.x, k.y, k.z});
            double dt = length - t;
            if (k_max > 0.0) dt = std::min(dt, 1.0 / (spe * k_max));
            const double dh = air_.changing_scale_m(hy) / spe;
            dt = std::min(dt, std::sqrt(2.0 * ry * dh));
            const double radial = std::abs(glm::dot(y, w)) / ry;
            if (radial > 0.0) dt = std::min(dt, dh / radial);
            dt = std::min(length - t, std::max(dt, length / kMaxRaySteps));
            const dvec3 ym = x + w * (t + 0.5 * dt);
            const double rm = glm::length(ym);
            const double hm = rm - ground;
            const dvec3 km = air_.extinction(hm);
            Sample sample;
            sample.up = ym / rm;
            sample.weight = glm::exp(-(tau + 0.5 * dt * km + ozone_to(t + 0.5 * dt))) * dt;
            sample.u_r = t_.altitude_coordinate(hm);
            sample.u_a = t_.view_zenith_coordinate(glm::dot(w, sample.up));
            sample.rho_r = air_.rayleigh_density(hm);
            sample.rho_m = air_.mie_density(hm);
            sample.altitude_m = hm;
            ray.samples.push_back(sample);
            tau += dt * km;
            t += dt;
            if (std::min({tau.x, tau.y, tau.z}) > kOpaqueDepth) {
                ray.hits_ground = false;  // nothing from beyond reaches the origin
                return ray;
            }
        }
        if (ray.hits_ground) {
            ray.ground_up = glm::normalize(x + w * length);
            ray.ground_transmittance = glm::exp(-tau - ozone_to(length));
        }
        return ray;
    }

    /// Rayleigh and Mie scattering matrices of a row: scattering_shares for each table view.
    void build_matrices(Row& row) const {
        const int views = s_.view_zenith_angles * s_.azimuths;
        const std::size_t n = row.directions.size();
        row.rayleigh.assign(views * n, 0.0);
        row.mie.assign(views * n, 0.0);
        for (int a = 0; a < s_.view_zenith_angles; ++a) {
            const double theta = t_.view_zenith_rad(a);
            for (int b = 0; b < s_.azimuths; ++b) {
                const double phi = t_.azimuth_rad(b);
                const dvec3 v(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                              std::cos(theta));
                const std::size_t base = std::size_t(a * s_.azimuths + b) * n;
                scattering_shares(v, row.directions, a_.mie_g, &row.rayleigh[base], &row.mie[base]);
            }
        }
    }

    /// Ground irradiance of the previous order at a ground point whose sun zenith cosine is
    /// mu_s: the direct sun for order 1, the table's sun rows after.
    dvec3 ground_irradiance(double mu_s, int order, const std::vector<dvec3>& previous) const {
        if (order == 1) return sun_.transmittance(0.0, mu_s) * std::max(mu_s, 0.0);
        int j;
        const double u =
            std::clamp(t_.sun_zenith_coordinate(mu_s), 0.0, double(s_.sun_zenith_angles - 1));
        j = std::min(int(u), s_.sun_zenith_angles - 2);
        const double f = u - j;
        return (1.0 - f) * previous[j] + f * previous[j + 1];
    }

    /// Radiance of one order arriving at a ray's origin along it (per unit E_sun0), for sun row j.
    dvec3 radiance(const Ray& ray, const dvec3& w, int j, int order,
                   const std::vector<dvec3>& density,
                   const std::vector<dvec3>& ground_previous) const {
        const dvec3& sun = suns_[j];
        const double nu = glm::dot(w, sun);
        dvec3 sum(0.0);
        if (order == 1) {
            const dvec3 rayleigh = a_.rayleigh_scattering * rayleigh_phase(nu);
            const dvec3 mie = a_.mie_scattering * henyey_greenstein_phase(nu, a_.mie_g);
            for (const Sample& p : ray.samples) {
                const dvec3 lit = sun_.transmittance(p.altitude_m, glm::dot(sun, p.up));
                sum += (rayleigh * p.rho_r + mie * p.rho_m) * lit * p.weight;
            }
        } else {
            for (const Sample& p : ray.samples) {
                const double mu = glm::dot(w, p.up);
                const double mu_s = glm::dot(sun, p.up);
                const double across =
                    std::sqrt(std::max(0.0, (1.0 - mu * mu) * (1.0 - mu_s * mu_s)));
                const double cos_azimuth = across > 1e-12 ? (nu - mu * mu_s) / across : 1.0;
                sum += t_.interpolate(density, p.u_r, t_.sun_zenith_coordinate(mu_s), p.u_a,
                                      t_.azimuth_coordinate(cos_azimuth)) *
                       p.weight;
            }
        }
        if (ray.hits_ground) {
            const dvec3 e = ground_irradiance(glm::dot(sun, ray.ground_up), order, ground_previous);
            sum += ray.ground_transmittance * a_.ground_albedo / kPi * e;
        }
        return sum;
    }

    /// J_{n+1} of row i at every sun row and view from the row's radiance of order n.
    void scatter_row(int i, std::vector<dvec3>& next) const {
        static_assert(sizeof(dvec3) == 3 * sizeof(double), "radiances are read as doubles");
        const Row& row = rows_[i];
        const double h = t_.altitude_m(i);
        const dvec3 beta_r = a_.rayleigh_scattering * air_.rayleigh_density(h);
        const dvec3 beta_m = a_.mie_scattering * air_.mie_density(h);
        const std::size_t n = row.directions.size();
        const int n_sun = s_.sun_zenith_angles;
        // The row's radiances as a matrix: direction k, then sun row and channel (3 n_sun wide),
        // so that each view's sums run over contiguous memory.
        const std::size_t width = 3 * std::size_t(n_sun);
        const double* radiance = &row.radiance[0].x;
        std::vector<double> sum_r(width), sum_m(width);
        for (int a = 0; a < s_.view_zenith_angles; ++a) {
            for (int b = 0; b < s_.azimuths; ++b) {
                const std::size_t base = std::size_t(a * s_.azimuths + b) * n;
                std::fill(sum_r.begin(), sum_r.end(), 0.0);
                std::fill(sum_m.begin(), sum_m.end(), 0.0);
                for (std::size_t k = 0; k < n; ++k) {
                    const double share_r = row.rayleigh[base + k], share_m = row.mie[base + k];
                    const double* from = radiance + k * width;
                    for (std::size_t x = 0; x < width; ++x) {
                        sum_r[x] += share_r * from[x];
                        sum_m[x] += share_m * from[x];
                    }
                }
                for (int j = 0; j < n_sun; ++j) {
                    const dvec3 r(sum_r[3 * j], sum_r[3 * j + 1], sum_r[3 * j + 2]);
                    const dvec3 m(sum_m[3 * j], sum_m[3 * j + 1], sum_m[3 * j + 2]);
                    next[t_.index(i, j, a, b)] = beta_r * r + beta_m * m;
                }
            }
        }
    }

    const MultipleScatteringTable& t_;
    const MultipleScatteringSettings& s_;
    const Atmosphere& a_;
    Air air_;
    SunTable sun_;
    std::vector<dvec3> suns_;
    std::vector<Row> rows_;
};

}  // namespace

/// Newton's iteration on the Legendre polynomial P_n from Chebyshev-like first guesses.
void gauss_legendre(int n, double lo, double hi, std::vector<double>& nodes,
                    std::vector<double>& weights) {
    for (int i = 0; i < n; ++i) {
        double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double derivative = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            derivative = n * (x * p1 - p0) / (x * x - 1.0);
            const double dx = p1 / derivative;
            x -= dx;
            if (std::abs(dx) < 1e-15) break;
        }
        nodes.push_back(0.5 * (lo + hi) + 0.5 * (hi - lo) * x);
        weights.push_back((hi - lo) / ((1.0 - x * x) * derivative * derivative));
    }
}

std::vector<IncomingDirection> incoming_directions(const Atmosphere& atmosphere,
                                                   const MultipleScatteringSettings& settings,
                                                   double altitude_m) {
    const double horizon = horizon_cosine(atmosphere.planet_radius_m, altitude_m);
    std::vector<double> mu, weight;
    gauss_legendre(settings.sky_directions, horizon, 1.0, mu, weight);
    gauss_legendre(settings.ground_directions, -1.0, horizon, mu, weight);
    const double d_phi = kPi / settings.half_azimuths;
    std::vector<IncomingDirection> directions;
    for (std::size_t k = 0; k < mu.size(); ++k) {
        const double sin_theta = std::sqrt(std::max(0.0, 1.0 - mu[k] * mu[k]));
        for (int m = 0; m < settings.half_azimuths; ++m) {
            const double phi = (m + 0.5) * d_phi;
            directions.push_back(
                {dvec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), mu[k]),
                 2.0 * weight[k] * d_phi, int(k) < settings.sky_directions});
        }
    }
    return directions;
}

void scattering_shares(const dvec3& view, const std::vector<IncomingDirection>& directions,
                       double mie_g, double* rayleigh, double* mie) {
    double sum_r = 0.0, sum_m = 0.0;
    for (std::size_t k = 0; k < directions.size(); ++k) {
        const dvec3& w = directions[k].w;
        const double half = 0.5 * directions[k].weight;
        const double c1 = glm::dot(view, w);
        const double c2 = glm::dot(view, dvec3(w.x, -w.y, w.z));
        rayleigh[k] = (rayleigh_phase(c1) + rayleigh_phase(c2)) * half;
        mie[k] = (henyey_greenstein_phase(c1, mie_g) + henyey_greenstein_phase(c2, mie_g)) * half;
        sum_r += rayleigh[k];
        sum_m += mie[k];
    }
    for (std::size_t k = 0; k < directions.size(); ++k) {
        rayleigh[k] /= sum_r;
        mie[k] /= sum_m;
    }
}

dvec3 horizontal_irradiance(const std::vector<IncomingDirection>& directions,
                            const std::vector<dvec3>& radiance) {
    dvec3 sum(0.0);
    for (std::size_t k = 0; k < directions.size(); ++k) {
        if (directions[k].sky) sum += radiance[k] * (directions[k].w.z * directions[k].weight);
    }
    return sum;
}

void run_multiple_scattering_solver(const MultipleScatteringTable& table,
                                    const Atmosphere& atmosphere, std::vector<glm::dvec3>& density,
                                    MultipleScatteringReport& report) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<dvec3> total;
    Solver(table, atmosphere).run(total, report);
    if (!total.empty()) density.swap(total);
    report.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace aerial::detail
