// Internal: the `reference` model's light scattered more than once (or reflected by the ground
// and scattered), as a table of its scattering density per atmosphere.
//
// What is tabulated: J_ms(x, v), the radiance per metre that air at x scatters towards an eye
// looking along v, from every order n >= 2 (per unit sun irradiance E_sun0). The first order is
// not in the table: the reference integrates it exactly per vertex. The table's axes are the
// point's altitude, the sun's zenith angle there, the view's zenith angle and the view's azimuth
// from the sun's (a spherically symmetric atmosphere lit by one sun has no other freedom).
//
// How it is computed (successive orders, as Bruneton 2017 does, in double precision):
//   1. At each table altitude and sun zenith angle, the radiance L_n arriving from a fixed set of
//      directions (Gauss–Legendre in the zenith cosine above and below the horizon, midpoints in
//      azimuth, mirrored about the sun's vertical plane) is integrated along each direction's ray
//      through the table of J_n, plus the ground's Lambertian reflection of the order-(n-1)
//      ground irradiance E_{n-1} where the ray meets the ground (E_0: the direct sun).
//   2. J_{n+1} = beta_s(x) * sum over the directions of phase(v . w) * L_n(w) * weight: one
//      matrix per altitude and species, its rows scaled to sum to 1 so that scattering conserves
//      energy exactly (a uniform radiance L gives J = beta_s L, the closed form of the tests).
//   3. J_ms = sum of J_n for n >= 2 until the geometric bound on the orders left is below
//      MultipleScatteringSettings::max_remainder of the sum.
// Order 1 in step 1 uses the exact single-scattering density (phase and sun transmittance) rather
// than a table, so the sun's aureole is not smeared into the higher orders.
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/scattering.hpp"

namespace aerial::detail {

/// The table of J_ms for one atmosphere (see the file comment).
class MultipleScatteringTable {
  public:
    MultipleScatteringTable(const Atmosphere& atmosphere,
                            const MultipleScatteringSettings& settings);

    /// J_ms at x (planet-centred, m) for an eye looking along the unit vector `view`, with the
    /// unit vector `sun` towards the sun: radiance per metre per unit E_sun0 (multiply by the
    /// atmosphere's sun_irradiance). Zero above the atmosphere.
    glm::dvec3 density(const glm::dvec3& x, const glm::dvec3& view, const glm::dvec3& sun) const;

    const MultipleScatteringReport& report() const { return report_; }

    /// Table coordinates (in cells) of an altitude and of the three angles; public for the solver.
    /// Rows: altitudes evenly spaced in the distance to the horizon, sun and view zenith angles
    /// evenly spaced in angle, azimuths evenly spaced in sin(azimuth / 2).
    double altitude_coordinate(double altitude_m) const;
    double sun_zenith_coordinate(double cos_sun_zenith) const;
    double view_zenith_coordinate(double cos_view_zenith) const;
    double azimuth_coordinate(double cos_azimuth) const;

    /// The grid's values along each axis.
    double altitude_m(int i) const;
    double sun_zenith_rad(int j) const;
    double view_zenith_rad(int a) const;
    double azimuth_rad(int b) const;

    /// Interpolates a table laid out like this one's at the given cell coordinates.
    glm::dvec3 interpolate(const std::vector<glm::dvec3>& table, double u_r, double u_s, double u_a,
                           double u_b) const;
    std::size_t index(int i, int j, int a, int b) const;
    std::size_t size() const;

    const MultipleScatteringSettings& settings() const { return settings_; }

  private:
    Atmosphere atmosphere_;
    MultipleScatteringSettings settings_;
    double horizon_distance_m_;  // sqrt(top^2 - ground^2)
    std::vector<glm::dvec3> density_;
    MultipleScatteringReport report_;
};

/// Fills `density` (laid out as `table`) with J_ms by successive orders and `report` with what
/// it found (multiple_scattering_solver.cpp); the table's constructor calls it.
void run_multiple_scattering_solver(const MultipleScatteringTable& table,
                                    const Atmosphere& atmosphere, std::vector<glm::dvec3>& density,
                                    MultipleScatteringReport& report);

/// One incoming direction of a table row's quadrature, in the row's frame (zenith +z, the sun in
/// the x-z half plane with x >= 0). The radiance field is symmetric about that plane, so each
/// direction stands for itself and its mirror image (y -> -y).
struct IncomingDirection {
    glm::dvec3 w;   ///< unit direction the radiance comes from
    double weight;  ///< solid angle of the direction and its mirror image together, sr
    bool sky;       ///< above the horizon (the ray reaches the top; else the ground)
};

/// Gauss–Legendre nodes and weights of order n on [lo, hi], appended to nodes and weights.
void gauss_legendre(int n, double lo, double hi, std::vector<double>& nodes,
                    std::vector<double>& weights);

/// The quadrature of a point at `altitude_m`: Gauss–Legendre in the zenith cosine above and below
/// the horizon, midpoints in azimuth over [0, pi]. The weights sum to 4 pi; the sky part's
/// weights times the zenith cosine sum to pi at the ground.
std::vector<IncomingDirection> incoming_directions(const Atmosphere& atmosphere,
                                                   const MultipleScatteringSettings& settings,
                                                   double altitude_m);

/// Each incoming direction's share of the light scattered towards an eye looking along `view`,
/// for Rayleigh and for Mie: phase(view . w) times the weight (summed over w and its mirror),
/// scaled so that each set sums to 1 (scattering conserves energy exactly).
void scattering_shares(const glm::dvec3& view, const std::vector<IncomingDirection>& directions,
                       double mie_g, double* rayleigh, double* mie);

/// Irradiance on a horizontal surface from radiances given at the sky directions.
glm::dvec3 horizontal_irradiance(const std::vector<IncomingDirection>& directions,
                                 const std::vector<glm::dvec3>& radiance);

/// The table for an atmosphere and settings, computed on first use and kept (the last few
/// atmospheres) for later calls; safe to call from several threads.
std::shared_ptr<const MultipleScatteringTable> multiple_scattering_table(
    const Atmosphere& atmosphere, const MultipleScatteringSettings& settings);

/// Largest sun zenith angle in the table (rad): 108 degrees, the end of astronomical twilight.
/// Beyond it J_ms is taken as at 108 degrees (it is then far below one 8-bit step).
inline constexpr double kMaxTableSunZenithRad = 108.0 * 3.14159265358979323846 / 180.0;

}  // namespace aerial::detail
