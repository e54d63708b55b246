// Internal: the GL-free half of the scene's built-in sky dome (sky.cpp). The dome is the core
// sky of aerial/sky.hpp: directions from make_sky_dome_mesh, colours from shade_sky_dome of a
// prepare_sky context, plus a skirt below the horizon. Unit-testable without a GL context.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/phase.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/sky.hpp"

namespace aerial::scene::detail {

/// Elevation of the skirt ring, rad: below the horizon so that no gap shows where no terrain
/// covers it; it takes the horizon's (ring 0's) colours.
inline constexpr double kSkirtElevationRad = -10.0 * kPi / 180.0;
/// The eye may climb or sink this much (m) before the virtual dome is fitted again.
inline constexpr double kRefitAltitudeM = kVirtualDomeRefitAltitudeM;

/// The sky method of the dome for a frame's model: the 2002 dome (dome_hp) for
/// hoffman-preetham and for reference (too slow for a sky every frame), dome_height for height.
SkyMethod dome_method(Model model);

/// The built-in dome between frames: its mesh (for the frame's up axis), the virtual dome's fit
/// and the vertex colours of the last frame.
class SkyDome {
  public:
    SkyDome(int rings, int segments) : rings_(rings), segments_(segments) {}

    /// The sky of this frame: prepare_sky for the eye, sun and up with dome_method(model). For
    /// dome_hp the virtual dome fitted earlier is passed in (SkyOptions::dome) and fitted again
    /// only when the atmosphere changed or the eye's altitude moved by more than
    /// kRefitAltitudeM since the fit.
    Result<SkyContext> prepare(const FrameSettings& settings, const glm::dvec3& eye);

    /// Linear radiance towards directions(): shade_sky_dome, the skirt repeating ring 0.
    std::vector<glm::dvec3> radiance(const SkyContext& sky) const;
    /// RGBA8 colours of a radiance per direction (one light's, or the sum of several):
    /// to_unorm8(display_value(display, L)); alpha 255. Remade on every call.
    const std::vector<std::uint8_t>& encode(const std::vector<glm::dvec3>& radiance,
                                            const Display& display);
    /// encode(radiance(sky), display).
    const std::vector<std::uint8_t>& shade(const SkyContext& sky, const Display& display) {
        return encode(radiance(sky), display);
    }

    /// Unit world directions: the mesh's (rings x segments, then the zenith) then the skirt's
    /// `segments` (under ring 0's). Valid after prepare.
    const std::vector<glm::dvec3>& directions() const { return directions_; }
    /// Triangles of the mesh and the skirt, counter-clockwise seen from the centre.
    const std::vector<std::uint32_t>& indices() const { return indices_; }
    const SkyDomeMesh& mesh() const { return mesh_; }
    int fits() const { return fits_; }  ///< virtual-dome fits so far

  private:
    Result<bool> update_mesh(const glm::dvec3& up);
    Result<bool> update_fit(const Atmosphere& atmosphere, double eye_altitude_m);

    int rings_, segments_;
    SkyDomeMesh mesh_;
    glm::dvec3 mesh_up_{0.0};  ///< the up axis mesh_ was made for
    std::vector<glm::dvec3> directions_;
    std::vector<std::uint32_t> indices_;
    std::vector<std::uint8_t> colours_;
    bool fitted_ = false;
    Atmosphere fit_atmosphere_;
    double fit_altitude_m_ = 0.0;
    VirtualDome fit_;
    int fits_ = 0;
};

}  // namespace aerial::scene::detail
