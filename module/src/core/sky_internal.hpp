// Helpers of the sky shared with aerial::validation's sky measurement (not installed).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "aerial/sky.hpp"
#include "aerial/sun.hpp"

namespace aerial::detail {

/// Elevation (radians) of a unit direction above the sky's horizon.
inline double elevation_of(const SkyContext& sky, const glm::dvec3& dir) {
    return std::asin(std::clamp(glm::dot(dir, sky.view.up), -1.0, 1.0));
}

/// The display value 0 .. 255 of a radiance after exposure and tone curve.
inline glm::dvec3 display_8bit(const glm::dvec3& radiance, double exposure, ToneCurve curve) {
    return tone_map(radiance, exposure, curve) * 255.0;
}

/// Rounded 8-bit display value (what a texel or a vertex colour holds).
inline glm::dvec3 quantised(const glm::dvec3& display) {
    return glm::dvec3(std::round(display.x), std::round(display.y), std::round(display.z));
}

}  // namespace aerial::detail
