// Internal: what sun.cpp and night.cpp share about an observer's place and the directions they
// give: one check of latitude and longitude, one rule from elevation and azimuth to east-north-up.
#pragma once

#include <cmath>
#include <optional>

#include <glm/vec3.hpp>

#include "aerial/error.hpp"

namespace aerial::detail {

/// latitude in [-pi/2, pi/2], longitude in [-pi, pi], radians; the error names "latitude" or
/// "longitude" and is attributed to `function`.
std::optional<Error> validate_place(const char* function, double latitude_rad,
                                    double longitude_rad);

/// Unit vector east (x), north (y), up (z) of an elevation and an azimuth clockwise from north.
inline glm::dvec3 enu_direction(double elevation_rad, double azimuth_rad) {
    const double c = std::cos(elevation_rad);
    return {c * std::sin(azimuth_rad), c * std::cos(azimuth_rad), std::sin(elevation_rad)};
}

}  // namespace aerial::detail
