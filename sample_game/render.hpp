// sample_game/render.hpp — renders the landscape of terrain.hpp per pixel with the physics core,
// the way an engine would per vertex: one aerial::Frame per frame, one aerial::scatter per point.
//
// How to use this:
//   1. Fill a RenderSettings (zero-effort defaults: earth, height model, a camera 300 m above
//      the hills looking north, a low sun ahead and to the right).
//   2. `auto image = render(settings);` casts one ray per pixel to the terrain or, if it hits
//      nothing within kSkyDistanceM, to a point of the sky that far away, and shades it:
//      colour = albedo / pi * (E_sun max(N.L, 0) + E_sky) * F_ex + L_in (raw linear radiance).
//   3. Expose and encode the radiance for display with output.hpp.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "aerial/aerial.hpp"
#include "terrain.hpp"

namespace sample {

/// Rays that reach this far (m, horizontally for terrain) without hitting ground see the sky;
/// sky pixels take F_ex and L_in of the segment from the eye to the point this far along the
/// ray. 200 km holds nearly all the air seen along a horizontal ray from low altitude.
inline constexpr double kSkyDistanceM = 200e3;

/// A pinhole camera whose rays are level at one chosen image row (a shifted lens, so that image
/// columns are vertical planes and a column can be ray-marched in one sweep).
struct Camera {
    /// Horizontal position of the eye, m (z is taken from the terrain plus height_above_ground_m).
    double x_m = 0.0;
    double y_m = 0.0;
    double height_above_ground_m = 300.0;
    /// Direction of view, clockwise from +y (north) towards +x (east), rad.
    double heading_rad = 0.0;
    /// Full horizontal field of view, rad, in (0, pi).
    double horizontal_fov_rad = 1.0471975511965976;  // 60 deg
    /// Image row, as a fraction of the height from the top, where rays are level.
    double horizon_row_fraction = 0.4;
};

struct RenderSettings {
    int width = 640;   ///< pixels, >= 1
    int height = 360;  ///< pixels, >= 1
    Camera camera;
    /// Unit vector towards the sun, world frame (z up).
    glm::dvec3 sun_dir{0.0, 0.0, 1.0};
    aerial::Atmosphere atmosphere;
    aerial::Model model = aerial::Model::height;
    /// Worker threads, >= 1.
    int threads = 1;
};

/// What the core returned for one pixel, and the radiance made of it.
struct Pixel {
    Surface surface = Surface::sky;
    float distance_m = 0.0f;               ///< eye to the shaded point
    aerial::Scattering<float> scattering;  ///< F_ex, L_in, E_sun of that segment
    glm::vec3 radiance{0.0f};              ///< raw linear radiance reaching the eye
};

struct Image {
    int width = 0;
    int height = 0;
    std::vector<Pixel> pixels;       ///< row-major, top row first
    glm::vec3 sky_irradiance{0.0f};  ///< E_sky used as ambient light on the ground
    glm::dvec3 eye_m{0.0};
    double seconds = 0.0;  ///< wall time of the rendering (not of encoding)
};

/// Renders one frame. Fails only when the core rejects the atmosphere or the view.
aerial::Result<Image> render(const RenderSettings& settings);

}  // namespace sample
