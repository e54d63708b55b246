// Internal: the frame's lights, the sun and FrameSettings::moon. Which of them a frame is shaded
// with (the rule of FrameSettings::moon), the moon's one-light settings, and the cpu backend's
// shading of a node by both lights summed before the display.
#pragma once

#include <optional>

#include "aerial/error.hpp"
#include "aerial/scene_renderer.hpp"
#include "frame_plan.hpp"

namespace aerial::scene::detail {

/// The largest FrameSettings::moon fraction accepted: 400 times a full moon's light, far above
/// any moon, far below the sun.
inline constexpr double kMaxMoonFraction = 1e-3;
/// A light is left out of a frame when exposure x (E at the eye + kSkyPeakFactor x its sky
/// ambient) is below half a step: the brightest sky radiance it gives is taken as at most this
/// times its sky's irradiance on level ground (12.6 times a uniform sky's radiance).
inline constexpr double kSkyPeakFactor = 4.0;

/// What the renderer keeps between frames for its lights.
struct LightState {
    SkyAmbientCache sun_ambient, moon_ambient;  ///< each light's sky ambient estimate
    FrameSettings moon;                         ///< the last frame's moon settings
};

/// The frame's lights as render() prepares them.
struct FrameLights {
    Lights lights = Lights::sun;
    /// The settings the frame's inputs are prepared for: the caller's (the sun), or with
    /// Lights::moon the moon's one-light settings (held by the LightState).
    const FrameSettings* first = nullptr;
    const FrameSettings* second = nullptr;  ///< Lights::both: the moon's
    glm::vec3 first_ambient{0.0f};          ///< the terrain's skylight of `first`
    glm::vec3 second_ambient{0.0f};         ///< of `second` (0 when the caller gave an ambient)
};

/// Checks FrameSettings::moon: "moon.dir" (finite, non-zero) and "moon.fraction" (finite, in
/// [0, kMaxMoonFraction]); render()'s errors.
std::optional<Error> validate_moon(const FrameSettings& settings);

/// The moon's one-light settings: `settings` with sun_dir the moon's (normalised), E_sun0 times
/// its fraction and no moon. Requires settings.moon.
FrameSettings moon_settings(const FrameSettings& settings);

/// Chooses the lights of a frame (validate_moon first) and estimates their skylight (cached in
/// `state` until the light turned by a quarter of a degree). With the policy off, every light
/// given is used.
FrameLights choose_lights(LightState& state, const FrameSettings& settings, const glm::dvec3& eye);

/// Prepares `f.second` for `moon` (f prepared for the sun); render()'s errors.
std::optional<Error> prepare_second_light(FrameInputs& f, const FrameSettings& moon,
                                          const glm::vec3& ambient);

/// cpu backend, two lights: the node's colours as the sum of both lights (F_ex, L_in and E of
/// each through shade_into's float outputs), then the display; the 8-bit rule of shade_into.
std::optional<Error> shade_two_lights(const FrameInputs& f, NodeState& st, bool lit,
                                      const glm::vec3& albedo);

}  // namespace aerial::scene::detail
