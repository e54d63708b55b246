// The sky around the eye as a table of elevation x azimuth from the sun (not installed): what the
// cubemap's texels are interpolated from. The sky of a spherical planet seen from one eye depends
// on the view's elevation and its azimuth from the sun's vertical plane only, so a few hundred
// evaluations of the sky method stand for every texel; the table holds the parts before the
// phase functions (height_parts.hpp), which each texel applies at its own angle to the sun, so
// the Mie peak is exact and not interpolated.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/sky.hpp"
#include "height_parts.hpp"

namespace aerial::detail {

/// Any unit vector perpendicular to the unit vector `up`.
glm::dvec3 any_horizontal(const glm::dvec3& up);

/// The sky radiance along a unit direction in parts: for dome_height and height_chained the
/// `height` model's parts (chained like sky_radiance); for the other methods all of it in
/// `multiple` (their phase is interpolated with the rest).
HeightParts<double> sky_radiance_parts(const SkyContext& sky, const glm::dvec3& direction);

/// Where a direction falls in the table: row and column coordinates (fractional node indices),
/// and the cosine of its angle to the sun. Below the horizon a direction stands for the
/// horizon under it (the cubemap repeats the horizon there).
struct SkyViewCoordinates {
    double row = 0, column = 0, cos_theta = 1;
};

class SkyViewTable {
  public:
    /// Nodes: rows at elevation (i / (kRows - 1))^2 * 90 deg (dense at the horizon, where the
    /// sky changes fastest), columns at azimuth j / (kColumns - 1) * 180 deg from the sun's side.
    static constexpr int kRows = 32;
    static constexpr int kColumns = 16;
    static constexpr int kNodes = kRows * kColumns;

    /// Starts a table for this sky (no node computed yet).
    explicit SkyViewTable(const SkyContext& sky);

    const SkyContext& sky() const { return sky_; }
    /// The world direction of a node.
    glm::dvec3 node_direction(int row, int column) const;
    /// Computes rows [first, first + count) (clamped to the table).
    void compute_rows(int first, int count);
    int rows_done() const { return rows_done_; }
    bool complete() const { return rows_done_ >= kRows; }

    /// Turns the table with the sun about the up axis: coordinates() then map directions for a
    /// sun of this azimuth (and take their angle to this sun); the nodes stay as computed.
    void set_sun_direction(const glm::dvec3& unit_sun);
    SkyViewCoordinates coordinates(const glm::dvec3& unit_direction) const;
    /// The parts at table coordinates (bilinear in log form), phases not applied.
    HeightParts<double> parts(const SkyViewCoordinates& c) const;
    /// The radiance of parts seen at an angle to the sun of cosine cos_theta.
    glm::dvec3 radiance(const HeightParts<double>& parts, double cos_theta) const;
    glm::dvec3 radiance(const SkyViewCoordinates& c) const {
        return radiance(parts(c), c.cos_theta);
    }
    glm::dvec3 radiance(const glm::dvec3& unit_direction) const {
        return radiance(coordinates(unit_direction));
    }

  private:
    SkyContext sky_;
    std::optional<Frame<float>> float_frame_;  ///< height_chained: the chain in float
    glm::dvec3 toward_sun_{1, 0, 0};           ///< horizontal, towards the sun's azimuth
    glm::dvec3 across_{0, 1, 0};               ///< up x toward_sun_
    std::vector<HeightParts<double>> nodes_;
    int rows_done_ = 0;
};

/// The radiance of a cubemap from a complete table (the texels as compute_sky_cubemap defines
/// them).
SkyCubemap cubemap_from_table(const SkyViewTable& table, int size);

}  // namespace aerial::detail
