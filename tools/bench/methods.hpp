// Two fixed-function ways of aerial perspective that aerial-bench measures against the module's
// per-vertex paths (issue 7): FlightGear's fog function and the lookup-texture alternative of the
// 2002 talk. Both draw an engine's geometry through a callback, like aerial::gl::draw_with_colours,
// and put back every piece of GL state they change.
//
// How to use this:
//   fg-fog:
//     1. `auto fog = flightgear_fog(frame, display);` per frame (frame of the `height` model: the
//        density where the eye is).
//     2. `flightgear_fog_coordinates(fog, frame, positions, count, coords)` per frame.
//     3. `draw_with_flightgear_fog(api, fog, coords.data(), draw)`.
//   lut-texture:
//     1. `auto lut = LutTexture::create(api, frame, display, max_distance_m);` once per sun
//        position (frame of the hoffman-preetham model, the only one whose F_ex and L_in depend
//        on distance and phase angle alone).
//     2. `lut->texcoords(frame, positions, count, coords)` per frame, then
//        `lut->draw(coords.data(), draw)`.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "aerial/batch.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"

namespace aerial::gl {
struct Api;
}

namespace aerial::bench {

/// FlightGear's exponential fog with a cut-off: the fraction of the surface colour left after a
/// distance d is f = exp(-x - x^4), x = d / visibility, where the visibility is one attenuation
/// length (FlightGear ALS notes, "Visibility and fog function"). Here the attenuation length is
/// that of the green channel at the eye's altitude and the haze colour that of the fog backend of
/// aerial-render (aerial::validation::fog_parameters: an infinitely long ray, phase averaged over
/// the sphere).
struct FlightGearFog {
    double visibility_m = 0.0;  ///< one attenuation length, metres
    float colour[4] = {0, 0, 0, 1};
};

FlightGearFog flightgear_fog(const Frame<float>& frame, const Display& display);

/// exp(-x - x^4) for x = distance_m / visibility_m (1 for a visibility of 0 or less).
double flightgear_fog_factor(double distance_m, double visibility_m);

/// One fog coordinate per vertex, 1 - f (GL_LINEAR fog from 0 to 1 turns it back into f);
/// positions are x, y, z floats in engine units, like View::eye.
void flightgear_fog_coordinates(const FlightGearFog& fog, const Frame<float>& frame,
                                const float* positions, std::size_t count,
                                std::vector<float>& coords);

/// Draws with GL_FOG on, GL_LINEAR from 0 to 1, the fog coordinate array as its source and the
/// haze colour; restores the fog state, the fog coordinate array and its source. Error (nothing
/// drawn): the context lacks glFogCoordPointer (GL 1.4 or EXT_fog_coord).
std::optional<Error> draw_with_flightgear_fog(const gl::Api& api, const FlightGearFog& fog,
                                              const float* coords,
                                              const std::function<void()>& draw);

/// The 2002 talk's alternative to per-vertex colours: F_ex in a 1D texture of distance and L_in
/// (through the display) in a 2D texture of distance and phase angle, on texture units 1 and 2
/// after the engine's texture on unit 0, combined by GL_COMBINE: unit 1 modulates, unit 2 adds.
/// Texel i of the distance axis is at i / (kDistanceTexels - 1) of max_distance_m, texel j of
/// the angle axis at theta = pi j / (kAngleTexels - 1) (angle rather than cosine: the Mie lobe
/// is narrow in cosine near the sun). Values from aerial::hoffman_preetham_closed_form with the
/// frame's E_sun. Move-only; deletes its two textures.
class LutTexture {
  public:
    static constexpr int kDistanceTexels = 256;
    static constexpr int kAngleTexels = 128;

    /// Errors: "model" unless the frame is hoffman-preetham, "max_distance_m" unless positive
    /// and finite, "GL_ARB_texture_env_combine" when the context lacks GL 1.3 combiners and
    /// three texture units.
    static Result<LutTexture> create(const gl::Api& api, const Frame<float>& frame,
                                     const Display& display, double max_distance_m);
    LutTexture(LutTexture&& other) noexcept;
    LutTexture& operator=(LutTexture&& other) noexcept;
    LutTexture(const LutTexture&) = delete;
    LutTexture& operator=(const LutTexture&) = delete;
    ~LutTexture();

    /// Two texture coordinates per vertex (distance, angle), texel centres mapped.
    void texcoords(const Frame<float>& frame, const float* positions, std::size_t count,
                   std::vector<float>& coords) const;
    /// Draws the engine's geometry (unit 0 textured, GL_MODULATE, current colour white) with the
    /// two tables applied; restores the state of units 1 and 2, the active and client-active
    /// units and their texture-coordinate arrays.
    void draw(const float* coords, const std::function<void()>& draw) const;

  private:
    LutTexture(const gl::Api* api, unsigned f_ex, unsigned l_in, double max_distance_m)
        : api_(api),
          extinction_id_(f_ex),
          in_scattering_id_(l_in),
          max_distance_m_(max_distance_m) {}
    const gl::Api* api_ = nullptr;
    unsigned extinction_id_ = 0;
    unsigned in_scattering_id_ = 0;
    double max_distance_m_ = 1.0;
};

}  // namespace aerial::bench
