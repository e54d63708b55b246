// aerial/sky.hpp — the sky: per-vertex domes, a CPU cubemap and the sun sprite.
//
// How to use this:
//   1. `auto sky = aerial::prepare_sky(atmosphere, view, aerial::SkyMethod::height_chained);`
//      (View as in scattering.hpp: eye, sun_dir, up). `aerial::sky_radiance(*sky, dir)` is the
//      raw linear radiance seen along a unit world direction.
//   2. Per-vertex dome: `auto dome = aerial::make_sky_dome_mesh(12, 32);` then
//      `aerial::shade_sky_dome(*sky, dome)` gives one colour per vertex; draw it around the eye.
//   3. Cubemap: `aerial::SkyCubemapCache cache;` and each frame `cache.update(atmosphere, view)`
//      recomputes the faces only when the sun or the atmosphere moved beyond its bound;
//      `aerial::cubemap_to_rgba8` turns them into texels (aerial/sky_gl.hpp draws them).
//   4. The sun: `aerial::make_sun_sprite(...)` is the disc and the narrow Mie halo (g >= 0.9)
//      that no per-vertex dome can carry; draw it additively (aerial/sky_gl.hpp).
// How each compares with `reference` (the figures of the table in docs/sky.md) is
// measured by aerial::validation (aerial/validation/sky_measure.hpp), for tests and tools.
//
// Radiance is per steradian in the units of Atmosphere::sun_irradiance (E_sun0), like L_in.
// Rays end at the top of the atmosphere, or on the ground when they point below the horizon.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"
#include "aerial/sun.hpp"

namespace aerial {

/// How the sky radiance along a direction is computed, cheapest first.
enum class SkyMethod {
    /// The 2002 talk's dome: the constant-density closed form (E_sun at the eye) along the ray
    /// to a *virtual sky dome* whose radius per direction is fitted (fit_virtual_dome).
    dome_hp,
    /// The same with one radius for every direction (the fit's mean over the upper hemisphere).
    dome_hp_single,
    /// The `height` model from the eye to where the ray leaves the atmosphere, one segment.
    dome_height,
    /// The `height` model chained over SkyOptions::segments pieces of the ray, each attenuated
    /// by the ones before it: a short ray march (the approach of the codeflow sky, in physical
    /// units and with exponential profiles).
    height_chained,
    /// The `reference` model along the whole ray. Slow (about a millisecond a direction).
    reference,
};

std::string_view sky_method_name(SkyMethod method);  ///< "dome-hp", "dome-hp-single", ...
Result<SkyMethod> parse_sky_method(std::string_view name);
const std::vector<SkyMethod>& all_sky_methods();

/// The virtual sky dome: its radius as a function of the view direction's elevation, chosen so
/// that the constant sea-level density over that distance holds the same G-channel optical
/// depth as the spherical exponential atmosphere along the real ray (to the top, or to the
/// ground below the horizon). Tabulated on a grid that is dense near the horizon.
struct VirtualDome {
    std::vector<double> radius_m;  ///< by table index, see radius_at
    /// The radius for a direction at this elevation (radians, -pi/2 .. pi/2), interpolated; 0
    /// for a dome that was not fitted.
    double radius_at(double elevation_rad) const;
};

/// Fits the virtual dome for an eye at `eye_altitude_m` (the reference integrator gives the
/// optical depths). `samples` >= 3 table entries.
Result<VirtualDome> fit_virtual_dome(const Atmosphere& atmosphere, double eye_altitude_m,
                                     int samples = 257);

/// How far (m) the eye may climb or sink before a renderer fits the virtual dome again (the
/// scene's sky and the C interface's aerial_sky keep a fit while the atmosphere holds).
inline constexpr double kVirtualDomeRefitAltitudeM = 25.0;

struct SkyOptions {
    int segments = 12;  ///< height_chained: pieces of the ray, >= 1
    /// dome_hp and dome_hp_single: the virtual dome fitted for this atmosphere and eye altitude
    /// (fit_virtual_dome), copied into the context; null: fitted here (257 reference rays, far
    /// too slow per frame: a renderer keeps its fit while the atmosphere and altitude hold).
    /// Other methods ignore it.
    const VirtualDome* dome = nullptr;
};

/// Everything one sky needs per frame. Plain data; built by prepare_sky.
struct SkyContext {
    SkyMethod method = SkyMethod::height_chained;
    Atmosphere atmosphere;
    View view;  ///< validated, sun_dir and up normalised
    glm::dvec3 eye_m{0.0};
    double eye_altitude_m = 0;
    Frame<double> frame;  ///< the height (or 2002) model's frame at the eye
    VirtualDome dome;     ///< dome_hp and dome_hp_single
    double single_radius_m = 0;
    int segments = 12;
};

/// Validates and does the per-frame work (for the 2002 domes, fits the virtual dome unless
/// SkyOptions::dome gives it; a given dome needs >= 2 finite radii >= 0).
Result<SkyContext> prepare_sky(const Atmosphere& atmosphere, const View& view, SkyMethod method,
                               const SkyOptions& options = {});

/// Sky radiance towards a world direction (any length > 0; normalised inside).
glm::dvec3 sky_radiance(const SkyContext& sky, const glm::dvec3& direction);

/// Length of the ray from the eye along a unit direction to the atmosphere top or the ground, m.
double sky_ray_length_m(const SkyContext& sky, const glm::dvec3& direction);

// ---- Per-vertex dome -------------------------------------------------------------------------

/// A hemisphere of unit directions in the world frame of `up`: `rings` bands of elevation from
/// the horizon up, `segments` around, and one vertex at the zenith. Triangles, counter-clockwise
/// seen from the centre.
struct SkyDomeMesh {
    int rings = 0, segments = 0;
    std::vector<glm::dvec3> directions;  ///< unit, world frame
    std::vector<std::uint32_t> indices;
};
/// The default dome: the scene renderer's built-in sky (aerial::scene::default_sky_drawer) and
/// the dome that aerial-sky-table measures (--dome), 385 vertices.
inline constexpr int kSkyDomeRings = 12;
inline constexpr int kSkyDomeSegments = 32;

/// rings >= 1, segments >= 3; `up` is a unit vector.
Result<SkyDomeMesh> make_sky_dome_mesh(int rings, int segments,
                                       const glm::dvec3& up = {0.0, 0.0, 1.0});

/// Sky radiance at each vertex of the dome.
std::vector<glm::dvec3> shade_sky_dome(const SkyContext& sky, const SkyDomeMesh& mesh);

// ---- Cubemap ---------------------------------------------------------------------------------

/// Six faces of linear radiance in OpenGL's order and orientation (+X, -X, +Y, -Y, +Z, -Z; the
/// face's s and t axes as in the GL spec's cube map table), size x size texels each, row t = 0
/// first. Directions are world directions.
struct SkyCubemap {
    int size = 0;
    std::array<std::vector<glm::vec3>, 6> faces;
};

/// The world direction through the centre of texel (i, j) of a face (0..5).
glm::dvec3 cubemap_texel_direction(int face, int i, int j, int size);

/// Computes every texel with the given sky (any method; height_chained is the default choice:
/// within 1 % of reference at a few microseconds a texel). size >= 1. Texels below the horizon
/// repeat the horizon's radiance: terrain covers them, and the much darker rays to the ground
/// would otherwise bleed into the horizon through texture filtering.
Result<SkyCubemap> compute_sky_cubemap(const SkyContext& sky, int size);

/// The faces as RGBA8 texels after exposure and tone curve (alpha 255).
std::array<std::vector<std::uint8_t>, 6> cubemap_to_rgba8(const SkyCubemap& cubemap,
                                                          double exposure, ToneCurve curve);

/// Samples RGBA8 faces like GL does with GL_LINEAR and GL_CLAMP_TO_EDGE on each face (no seamless
/// filtering): the CPU oracle of the GL sky box. Returns RGB in [0, 255].
glm::dvec3 sample_cubemap_rgba8(const std::array<std::vector<std::uint8_t>, 6>& faces, int size,
                                const glm::dvec3& direction);

/// Keeps a sky cubemap current for a moving eye, sun and exposure, doing only the work whose
/// result could show (the sky's counterpart of ShadingCache):
/// - the sky itself (SkyViewTable's few hundred directions, the costly part) is recomputed when
///   a texel could have moved by `max_change_steps` 8-bit steps since the sky shown was made:
///   a first-order bound from the sky's sensitivity to the sun's elevation and the eye's
///   altitude, measured at probe directions when each sky is made. Any change of the atmosphere,
///   the up axis or the display's tone curve recomputes it at once;
/// - a recompute is spread over `spread_updates` updates while the shown sky stays within
///   `max_lag_steps` of the current one, and shown whole when done (every texel at once: no
///   seam between faces);
/// - the texels are re-encoded from the sky shown when the sun's direction (the phase angle of
///   each texel, its azimuth) or the exposure moved them by the same bound, or a new sky is
///   shown.
class SkyCubemapCache {
  public:
    struct Options {
        int size = 64;  ///< texels along a face, 1 .. 4096
        SkyMethod method = SkyMethod::height_chained;
        double max_change_steps = 0.5;  ///< >= 0; 0 recomputes whenever anything moved
        int spread_updates = 4;         ///< >= 1; 1 recomputes within one update
        double max_lag_steps = 2.0;     ///< >= max_change_steps
    };
    /// What the cache did; the cost figures are those of the last update.
    struct Stats {
        int recomputes = 0;              ///< skies completed and shown
        int encodes = 0;                 ///< times the RGBA8 texels were rewritten
        int directions_last_update = 0;  ///< sky directions evaluated by the last update
        double bound_steps = 0.0;        ///< how far the shown texels could be off (the bound)
        double last_switch_steps = 0.0;  ///< largest texel change when the last sky was shown
        bool building = false;           ///< a recompute is under way
    };
    SkyCubemapCache();
    explicit SkyCubemapCache(const Options& options);
    ~SkyCubemapCache();
    SkyCubemapCache(SkyCubemapCache&&) noexcept;
    SkyCubemapCache& operator=(SkyCubemapCache&&) noexcept;

    /// Brings the texels up to date for this atmosphere, view and display; true when rgba8()
    /// changed. Errors name the field (options included) and leave the cache as it was.
    Result<bool> update(const Atmosphere& atmosphere, const View& view, const Display& display);
    /// The linear radiance of the texels shown (empty before the first update).
    const SkyCubemap& cubemap() const;
    /// The texels shown after the display of the last update (GL's face order; alpha 255).
    const std::array<std::vector<std::uint8_t>, 6>& rgba8() const;
    const Stats& stats() const;
    int recomputes() const { return stats().recomputes; }

  private:
    struct State;
    std::unique_ptr<State> state_;
};

// ---- Sun sprite ------------------------------------------------------------------------------

struct SunSpriteOptions {
    int size = 128;                   ///< texels per side, >= 8
    double half_width_rad = 0.087;    ///< angular half-width of the square sprite (5 deg)
    double sun_radius_rad = 0.00465;  ///< angular radius of the disc (0.267 deg)
    double halo_g = 0.95;             ///< Henyey–Greenstein g of the halo, [0.9, 1)
    int disc_supersampling = 4;       ///< per axis, for the disc's edge, >= 1
};

/// RGBA8 image, size x size, row 0 at the sprite's -v edge (see draw_sun_sprite).
struct SunSprite {
    int size = 0;
    double half_width_rad = 0;
    std::vector<std::uint8_t> rgba;
};

/// The sun disc (radiance E_sun at the eye over the disc's solid angle) and the part of the
/// forward Mie lobe the sky cannot carry: E_sun(eye) * tau_Mie(towards the sun) *
/// max(0, P_HG(theta, halo_g) - P_HG(theta, atmosphere g)), which is exact single scattering at
/// theta = 0. After exposure and tone curve; meant to be added to the sky (GL_ONE, GL_ONE).
Result<SunSprite> make_sun_sprite(const SkyContext& sky, double exposure, ToneCurve curve,
                                  const SunSpriteOptions& options = {});

}  // namespace aerial
