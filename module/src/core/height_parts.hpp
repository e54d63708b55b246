// The `height` model's result before its phase functions are applied (not installed): what the
// sky-view table (sky_view_table.hpp) interpolates over directions, so that the Mie peak is
// evaluated exactly per texel instead of interpolated.
#pragma once

#include <glm/vec3.hpp>

#include "aerial/scattering.hpp"

namespace aerial::detail {

/// L_in = P_R(theta) rayleigh + P_HG(theta, g) mie + multiple, theta the angle between the view
/// ray and the sun.
template <class T>
struct HeightParts {
    glm::vec<3, T> extinction{1, 1, 1};
    glm::vec<3, T> rayleigh{0, 0, 0};  ///< single scattering by air, without its phase
    glm::vec<3, T> mie{0, 0, 0};       ///< single scattering by haze, without its phase
    glm::vec<3, T> multiple{0, 0, 0};  ///< the higher orders (their angular shape included)
    glm::vec<3, T> sun_irradiance{0, 0, 0};

    glm::vec<3, T> in_scattering(T phase_rayleigh, T phase_mie) const {
        return phase_rayleigh * rayleigh + phase_mie * mie + multiple;
    }
};

/// The `height` model from the frame's eye to a point (metres), in parts. scatter() is this
/// with the phases applied (and the distance checks before it).
template <class T>
HeightParts<T> height_parts(const Frame<T>& frame, const glm::vec<3, T>& p_m);

/// frame_with_eye in place: the frame's eye moved to eye_m (metres), nothing copied (the sky's
/// chained segments move one frame along the ray).
template <class T>
void move_frame_eye(Frame<T>& frame, const glm::dvec3& eye_m);

}  // namespace aerial::detail
