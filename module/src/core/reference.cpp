// The `single_scattering` and `reference` models: single scattering integrated numerically along
// the eye->vertex segment in a spherical planet with exponential Rayleigh and Mie profiles and the
// ozone layer, truncated at the atmosphere top, sun transmittance integrated per sample and zero
// where the planet shadows the sample; `reference` adds, at the same samples, the scattering
// density of every higher order from its table (multiple_scattering.hpp).
//
// Integration: the segment is cut into steps short enough that neither the density (one step per
// 1/steps_per_efold of a scale height of altitude change, with the curvature term near tangent
// points) nor the optical depth (1/steps_per_efold per step) changes by more than a fraction of
// an e-fold; each step uses 4-point Gauss–Legendre. The optical depth from the eye to each node
// is integrated the same way, so the only error is quadrature error, which falls like the 8th
// power of the step.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "aerial/phase.hpp"
#include "aerial/scattering.hpp"
#include "multiple_scattering.hpp"

namespace aerial {
namespace {

using glm::dvec3;

constexpr std::array<double, 4> kGaussNodes{-0.86113631159405257522, -0.33998104358485626480,
                                            0.33998104358485626480, 0.86113631159405257522};
constexpr std::array<double, 4> kGaussWeights{0.34785484513745385737, 0.65214515486254614263,
                                              0.65214515486254614263, 0.34785484513745385737};
/// A component whose local extinction is below this fraction of the other's does not set the
/// step length (it cannot change the result by more than that fraction).
constexpr double kNegligibleFraction = 1e-10;
/// Cap on steps along one ray: a guard against pathological input only (scale heights of metres
/// over paths of thousands of kilometres); ordinary atmospheres need a few hundred.
constexpr double kMaxSteps = 1024.0;
/// Optical depth beyond which a ray counts as opaque: exp(-60) = 9e-27.
constexpr double kOpaqueDepth = 60.0;
/// Remaining optical depth below which an outward-going ray is done.
constexpr double kNegligibleDepth = 1e-12;

/// The medium seen by the integrator, in a frame centred on the planet.
struct Medium {
    const Atmosphere& atmosphere;
    bool constant_density;
    double steps_per_efold;
    double min_altitude_m;
    dvec3 rayleigh;
    dvec3 mie_extinction;
    dvec3 mie_scattering;

    Medium(const Atmosphere& a, bool constant, double steps)
        : atmosphere(a),
          constant_density(constant),
          steps_per_efold(std::max(steps, 0.25)),
          min_altitude_m(min_density_altitude_m(a)),
          rayleigh(a.rayleigh_scattering),
          mie_extinction(a.mie_extinction()),
          mie_scattering(a.mie_scattering) {}

    /// Relative densities (1 at sea level) at a point.
    void density(const dvec3& x, double& rho_r, double& rho_m) const {
        if (constant_density) {
            rho_r = rho_m = 1.0;
            return;
        }
        const double r = glm::length(x);
        if (r > atmosphere.atmosphere_radius_m) {
            rho_r = rho_m = 0.0;
            return;
        }
        const double h = std::max(r - atmosphere.planet_radius_m, min_altitude_m);
        rho_r = std::exp(-h / atmosphere.rayleigh_scale_height_m);
        rho_m = std::exp(-h / atmosphere.mie_scale_height_m);
    }

    /// Rayleigh and Mie extinction (integrated numerically; ozone's is in closed form).
    dvec3 extinction(const dvec3& x) const {
        double rho_r, rho_m;
        density(x, rho_r, rho_m);
        return rayleigh * rho_r + mie_extinction * rho_m;
    }

    /// Ozone's optical depth along origin + t dir for t in [a, b], in closed form: the column
    /// from a point to the top minus the column from b on (ozone_column_m). With
    /// constant_density, the sea-level ozone density over the length.
    dvec3 ozone_depth(const dvec3& origin, const dvec3& dir, double a, double b) const {
        const dvec3& k = atmosphere.ozone_absorption;
        if (k == dvec3(0.0) || !(b > a)) return dvec3(0.0);
        if (constant_density) return k * (atmosphere.ozone_density(0.0) * (b - a));
        auto column_from = [&](double t) {
            const dvec3 x = origin + dir * t;
            const double r = glm::length(x);
            return ozone_column_m(atmosphere, r - atmosphere.planet_radius_m,
                                  r > 0.0 ? glm::dot(x, dir) / r : 1.0);
        };
        return k * std::max(0.0, column_from(a) - column_from(b));
    }

    /// Whether an optical depth hides everything behind it: every channel that has any
    /// extinction at all is beyond kOpaqueDepth.
    bool opaque(const dvec3& tau) const {
        for (int c = 0; c < 3; ++c) {
            if (tau[c] <= kOpaqueDepth && rayleigh[c] + mie_extinction[c] > 0.0) return false;
        }
        return true;
    }

    /// Whether the rest of a ray from x, of length `remaining`, adds a negligible optical depth:
    /// it goes outwards (so density only falls) and the local extinction times the length is tiny.
    bool negligible_beyond(const dvec3& x, const dvec3& dir, double remaining) const {
        if (constant_density || glm::dot(x, dir) < 0.0) return false;
        const dvec3 k = extinction(x);
        return std::max({k.x, k.y, k.z}) * remaining < kNegligibleDepth;
    }

    /// Length of the next integration step from x along unit direction dir; at least min_step.
    double step(const dvec3& x, const dvec3& dir, double remaining, double min_step) const {
        double rho_r, rho_m;
        density(x, rho_r, rho_m);
        const dvec3 k = rayleigh * rho_r + mie_extinction * rho_m;
        const double k_max = std::max({k.x, k.y, k.z});
        double dt = remaining;
        if (k_max > 0.0) dt = std::min(dt, 1.0 / (steps_per_efold * k_max));
        if (!constant_density) {
            const double k_r = std::max({rayleigh.x, rayleigh.y, rayleigh.z}) * rho_r;
            const double k_m =
                std::max({mie_extinction.x, mie_extinction.y, mie_extinction.z}) * rho_m;
            double h = 0.0;  // scale height of the fastest-varying component that matters
            if (k_r > kNegligibleFraction * k_m) h = atmosphere.rayleigh_scale_height_m;
            if (k_m > kNegligibleFraction * k_r) {
                h = h > 0.0 ? std::min(h, atmosphere.mie_scale_height_m)
                            : atmosphere.mie_scale_height_m;
            }
            if (h > 0.0) {
                const double r = glm::length(x);
                const double radial_speed = std::abs(glm::dot(x, dir)) / std::max(r, 1.0);
                const double dh = h / steps_per_efold;
                dt = std::min(dt, std::sqrt(2.0 * r * dh));
                if (radial_speed > 0.0) dt = std::min(dt, dh / radial_speed);
            }
        }
        return std::min(remaining, std::max(dt, min_step));
    }

    /// Optical depth along origin + t dir for t in [a, b] (one Gauss step, no subdivision).
    dvec3 optical_depth_step(const dvec3& origin, const dvec3& dir, double a, double b) const {
        const double half = 0.5 * (b - a);
        const double mid = 0.5 * (a + b);
        dvec3 sum(0.0);
        for (size_t j = 0; j < kGaussNodes.size(); ++j) {
            sum += kGaussWeights[j] * extinction(origin + dir * (mid + half * kGaussNodes[j]));
        }
        return sum * half;
    }

    /// Optical depth along origin + t dir for t in [a, b]: Rayleigh and Mie adaptively stepped,
    /// ozone in closed form.
    dvec3 optical_depth(const dvec3& origin, const dvec3& dir, double a, double b) const {
        dvec3 tau = ozone_depth(origin, dir, a, b);
        const double min_step = (b - a) / kMaxSteps;
        double t = a;
        while (t < b && !opaque(tau) && !negligible_beyond(origin + dir * t, dir, b - t)) {
            const double dt = step(origin + dir * t, dir, b - t, min_step);
            tau += optical_depth_step(origin, dir, t, t + dt);
            t += dt;
        }
        return tau;
    }
};

/// Interval [t0, t1] of origin + t dir (t in [0, length], |dir| = 1) inside a sphere of the given
/// radius centred at the origin of the frame. Empty when t0 >= t1.
void clip_to_sphere(const dvec3& origin, const dvec3& dir, double length, double radius, double& t0,
                    double& t1) {
    const double b = glm::dot(origin, dir);
    const double c = glm::dot(origin, origin) - radius * radius;
    const double disc = b * b - c;
    if (disc < 0.0) {
        t0 = t1 = 0.0;
        return;
    }
    const double root = std::sqrt(disc);
    t0 = std::max(0.0, -b - root);
    t1 = std::min(length, -b + root);
}

/// Whether the planet blocks the sun seen from x (frame centred on the planet). Points below sea
/// level are shadowed as if they were on the surface.
bool planet_blocks(const Atmosphere& a, const dvec3& x, const dvec3& sun_dir) {
    const double r = glm::length(x);
    if (r <= 0.0) return true;
    const double mu = glm::dot(x, sun_dir) / r;
    if (mu >= 0.0) return false;
    const double sin_chi = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    return r * sin_chi < std::min(a.planet_radius_m, r);
}

/// Transmittance of sunlight from space to x, through the real (exponential, truncated) profile.
dvec3 sun_transmittance_at(const Medium& real, const dvec3& x, const dvec3& sun_dir) {
    if (planet_blocks(real.atmosphere, x, sun_dir)) return dvec3(0.0);
    double t0, t1;
    clip_to_sphere(x, sun_dir, 1e300, real.atmosphere.atmosphere_radius_m, t0, t1);
    if (t0 >= t1) return dvec3(1.0);
    return glm::exp(-real.optical_depth(x, sun_dir, t0, t1));
}

}  // namespace

glm::dvec3 sun_transmittance(const Atmosphere& atmosphere, double altitude_m, double cos_zenith) {
    const Medium real(atmosphere, false, ReferenceOptions{}.steps_per_efold);
    const double mu = std::clamp(cos_zenith, -1.0, 1.0);
    const dvec3 x(0.0, 0.0, atmosphere.planet_radius_m + altitude_m);
    const dvec3 dir(std::sqrt(std::max(0.0, 1.0 - mu * mu)), 0.0, mu);
    return sun_transmittance_at(real, x, dir);
}

Scattering<double> reference_scattering(const Atmosphere& atmosphere, const View& view,
                                        const glm::dvec3& vertex, const ReferenceOptions& options) {
    const Medium medium(atmosphere, options.constant_density, options.steps_per_efold);
    const Medium real(atmosphere, false, options.steps_per_efold);
    const dvec3 up = glm::normalize(view.up);
    const dvec3 sun = glm::normalize(view.sun_dir);
    const dvec3 centre_offset = up * atmosphere.planet_radius_m;

    const dvec3 eye = view.eye * view.meters_per_unit + centre_offset;
    const dvec3 target = vertex * view.meters_per_unit + centre_offset;

    auto sunlight = [&](const dvec3& x) {
        if (!options.sun_attenuation) return dvec3(1.0);
        return sun_transmittance_at(real, x, sun);
    };

    Scattering<double> out;
    out.sun_irradiance = atmosphere.sun_irradiance * sunlight(target);
    const dvec3 segment = target - eye;
    const double s = glm::length(segment);
    if (!(s > 0.0)) return out;
    const dvec3 dir = segment / s;
    std::shared_ptr<const detail::MultipleScatteringTable> higher_orders;
    if (options.multiple_scattering && options.sun_attenuation && !options.constant_density)
        higher_orders = detail::multiple_scattering_table(atmosphere, options.tables);
    const double cos_theta = glm::dot(dir, sun);
    const double phase_r = rayleigh_phase(cos_theta);
    const double phase_m = henyey_greenstein_phase(cos_theta, atmosphere.mie_g);

    double t0 = 0.0, t1 = s;
    if (!options.constant_density)
        clip_to_sphere(eye, dir, s, atmosphere.atmosphere_radius_m, t0, t1);

    // Split the segment where it crosses the edge of the planet's shadow (a cylinder of radius
    // R around the axis through the centre along the sun): the integrand jumps there.
    std::array<double, 4> breaks{t0, t1, t1, t1};
    if (options.sun_attenuation) {
        const dvec3 e_perp = eye - sun * glm::dot(eye, sun);
        const dvec3 d_perp = dir - sun * glm::dot(dir, sun);
        const double qa = glm::dot(d_perp, d_perp);
        const double qb = glm::dot(e_perp, d_perp);
        const double qc =
            glm::dot(e_perp, e_perp) - atmosphere.planet_radius_m * atmosphere.planet_radius_m;
        const double disc = qb * qb - qa * qc;
        if (qa > 0.0 && disc > 0.0) {
            const double root = std::sqrt(disc);
            breaks[1] = std::clamp((-qb - root) / qa, t0, t1);
            breaks[2] = std::clamp((-qb + root) / qa, t0, t1);
        }
    }

    dvec3 tau(0.0);       // Rayleigh and Mie optical depth from the eye to t
    dvec3 radiance(0.0);  // in-scattered radiance per unit E_sun0
    const double min_step = (t1 - t0) / kMaxSteps;
    double t = t0;
    for (size_t piece = 1; piece < breaks.size(); ++piece) {
        while (t < breaks[piece] && !medium.opaque(tau) &&
               !medium.negligible_beyond(eye + dir * t, dir, t1 - t)) {
            const double dt = medium.step(eye + dir * t, dir, breaks[piece] - t, min_step);
            const double half = 0.5 * dt;
            for (size_t j = 0; j < kGaussNodes.size(); ++j) {
                const double tj = t + half * (1.0 + kGaussNodes[j]);
                const dvec3 xj = eye + dir * tj;
                double rho_r, rho_m;
                medium.density(xj, rho_r, rho_m);
                const dvec3 angular =
                    medium.rayleigh * (rho_r * phase_r) + medium.mie_scattering * (rho_m * phase_m);
                const dvec3 tau_j = tau + medium.optical_depth_step(eye, dir, t, tj) +
                                    medium.ozone_depth(eye, dir, t0, tj);
                dvec3 source = angular * sunlight(xj);
                if (higher_orders) source += higher_orders->density(xj, dir, sun);
                radiance += (kGaussWeights[j] * half) * source * glm::exp(-tau_j);
            }
            tau += medium.optical_depth_step(eye, dir, t, t + dt);
            t += dt;
        }
    }
    out.extinction = glm::exp(-tau - medium.ozone_depth(eye, dir, t0, t1));
    out.in_scattering = radiance * atmosphere.sun_irradiance;
    return out;
}

}  // namespace aerial
