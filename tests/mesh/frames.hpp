// Shared by the mesh tests: sun directions and the float frames of the height model they shade
// their meshes with.
#pragma once

#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"

namespace aerial_test {

/// The unit vector ELEVATION degrees above the horizon, AZIMUTH degrees from +x towards +y.
inline glm::dvec3 sun_at(double elevation_deg, double azimuth_deg = 0.0) {
    constexpr double kDegree = 3.14159265358979323846 / 180.0;
    const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

/// The height model's float frame for PRESET with its Mie asymmetry set to MIE_G, seen from EYE
/// with the sun along SUN; the test fails if the preset or the frame is refused.
inline aerial::Frame<float> make_frame(const glm::dvec3& eye, const glm::dvec3& sun, double mie_g,
                                       const char* preset = "earth") {
    auto atmosphere = aerial::atmosphere_preset(preset);
    EXPECT_TRUE(atmosphere.ok());
    aerial::Atmosphere a = atmosphere.value();
    a.mie_g = mie_g;
    aerial::View view;
    view.eye = eye;
    view.sun_dir = glm::normalize(sun);
    auto frame = aerial::prepare_frame<float>(a, view, aerial::Model::height);
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    return frame.value();
}

}  // namespace aerial_test
