// aerial/validation/sky_measure.hpp — how a sky compares with the `reference` model, by
// direction, in relative error and in 8-bit steps after exposure (the figures of the table in
// docs/sky.md). For tests and tools (aerial::validation; engines do not link it).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"
#include "aerial/sky.hpp"
#include "aerial/sun.hpp"

namespace aerial::validation {

/// Directions above the horizon (elevation 0 .. 90 deg, `elevation_steps` + 1 rows including
/// both ends; `azimuth_steps` columns, offset so none lies on a dome seam) and the `reference`
/// radiance and display value along each.
struct SkyProbe {
    std::vector<glm::dvec3> directions;
    std::vector<double> elevations_rad;
    std::vector<glm::dvec3> reference;
    std::vector<glm::dvec3> reference_display;  ///< 0..255 after exposure and tone curve
    double exposure = 1;
    ToneCurve curve = ToneCurve::exponential;
};
/// exposure: auto_exposure for the sun and skylight at the eye.
Result<SkyProbe> make_sky_probe(const Atmosphere& atmosphere, const View& view,
                                int elevation_steps = 18, int azimuth_steps = 24,
                                ToneCurve curve = ToneCurve::exponential);

struct SkyError {
    double max_relative = 0;  ///< max over directions and channels of |L - L_ref| / L_ref
    double max_lsb = 0;       ///< max display difference, 8-bit steps
    double mean_lsb = 0;
};

/// Each probe direction evaluated by `sky` (its exact value per direction).
SkyError measure_sky_method(const SkyProbe& probe, const SkyContext& sky);
/// A dome shaded per vertex by `sky`, its display colours interpolated across each triangle as
/// the fixed pipeline does (perspective-correct: barycentric on the flat triangle).
SkyError measure_sky_dome(const SkyProbe& probe, const SkyContext& sky, const SkyDomeMesh& mesh);
/// An RGBA8 cubemap sampled bilinearly (sample_cubemap_rgba8). No relative error (8-bit data).
SkyError measure_sky_cubemap(const SkyProbe& probe,
                             const std::array<std::vector<std::uint8_t>, 6>& faces, int size);

}  // namespace aerial::validation
