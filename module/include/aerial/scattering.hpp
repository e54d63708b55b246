// aerial/scattering.hpp — extinction F_ex and in-scattering L_in per vertex, four models.
//
// How to use this:
//   1. Validate the atmosphere once (atmosphere.hpp) and describe the frame in a `View`:
//      eye position, unit direction towards the sun, the world's up axis.
//   2. Once per frame: `auto frame = aerial::prepare_frame<float>(atmosphere, view, model);`
//      (it validates the view and does the per-frame work, such as E_sun for the 2002 model).
//   3. Per vertex: `aerial::Scattering<float> s = aerial::scatter(*frame, vertex_position);`
//      then colour = texel * s.extinction + s.in_scattering (both raw linear; apply exposure).
//
// Conventions (docs/conventions.md, Physics): metres, any up axis and either handedness, sea
// level is the plane through the origin perpendicular to `up`, the planet centre is at
// -planet_radius_m * up. Distances are Euclidean |vertex - eye|. Every output is finite, 0 <=
// extinction <= 1, in_scattering >= 0.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/error.hpp"

namespace aerial {

namespace detail {
struct MultipleScatteringSlice;
}

/// The physics models (docs/conventions.md, Physics), cheapest first.
enum class Model {
    /// The 2002 model: constant sea-level density, F_ex = exp(-beta_ex s),
    /// L_in = beta_sc(theta) / beta_ex * E_sun * (1 - F_ex), E_sun = E_sun0 * T_sun(eye).
    hoffman_preetham,
    /// Exponential density profiles averaged along the eye->vertex segment in closed form, sun
    /// transmittance (Chapman approximation) at the altitude where the scattering happens, and
    /// the light scattered more than once from a small table per atmosphere, cut per frame at the
    /// eye (docs/models.md, "The height model's higher orders").
    height,
    /// Single scattering integrated numerically in a spherical planet, double precision, sun
    /// transmittance per sample, shadowed by the planet: the `reference` without the light
    /// scattered more than once or reflected by the ground. Slow.
    single_scattering,
    /// Ground truth: every order of scattering (Rayleigh, Mie, ozone absorption, a Lambertian
    /// ground) in a spherical planet, double precision. The first order is integrated per vertex
    /// as in `single_scattering`; the higher orders come from tables computed once per atmosphere
    /// (docs/models.md). Slowest.
    reference,
};

/// "hoffman-preetham", "height", "single-scattering", "reference".
std::string_view model_name(Model model);
/// Inverse of model_name; the error lists the valid names.
Result<Model> parse_model(std::string_view name);
/// All models, cheapest first.
const std::vector<Model>& all_models();
/// Whether the model is integrated numerically per vertex (single-scattering, reference): no
/// SIMD kernel, no ARB program, no skip bound; for tools and tests, not for frames.
constexpr bool is_numerical(Model model) {
    return model == Model::single_scattering || model == Model::reference;
}

/// What changes per frame.
struct View {
    glm::dvec3 eye{0.0, 0.0, 2.0};      ///< eye position, engine units (see meters_per_unit)
    glm::dvec3 sun_dir{0.0, 0.0, 1.0};  ///< unit vector from the scene towards the sun
    glm::dvec3 up{0.0, 0.0, 1.0};       ///< unit world up axis
    double meters_per_unit = 1.0;       ///< engine units to metres for positions, > 0
};

/// The first bad field: non-finite values, sun_dir or up not of unit length (within 1e-3),
/// meters_per_unit <= 0.
std::optional<Error> validate(const View& view);

/// Result for one vertex, raw linear values.
template <class T>
struct Scattering {
    glm::vec<3, T> extinction{1, 1, 1};      ///< F_ex in [0, 1]: multiplies the surface colour
    glm::vec<3, T> in_scattering{0, 0, 0};   ///< L_in >= 0: added to it
    glm::vec<3, T> sun_irradiance{0, 0, 0};  ///< sun irradiance reaching the vertex in this model
};

/// Altitudes below this (m) are treated as this for density: deep enough for any real terrain,
/// shallow enough that exp(-h/H) stays finite in float for every valid scale height >= 1 m.
inline constexpr double kMinAltitudeM = -5000.0;

/// Per-frame constants of one (atmosphere, view, model), ready for many `scatter` calls.
/// Plain data; built by prepare_frame, which is where all validation happens.
template <class T>
struct Frame {
    Model model = Model::height;
    Atmosphere atmosphere;  ///< validated copy (the reference model works from it in double)
    View view;              ///< validated copy
    glm::vec<3, T> eye_m{0};
    glm::vec<3, T> sun_dir{0, 0, 1};
    glm::vec<3, T> up{0, 0, 1};
    T meters_per_unit = 1;
    T planet_radius_m = 0;
    T eye_altitude_m = 0;  ///< above the sphere, clamped to min_altitude_m
    glm::vec<3, T> rayleigh_scattering{0};
    glm::vec<3, T> mie_scattering{0};
    glm::vec<3, T> mie_extinction{0};
    T mie_g = 0;
    T inv_rayleigh_scale_height = 0;  ///< 1/m
    T inv_mie_scale_height = 0;       ///< 1/m
    T rayleigh_scale_height_m = 0;
    T mie_scale_height_m = 0;
    /// Altitudes below this are treated as this for density: kMinAltitudeM, or higher when a
    /// scale height is so short that exp(-h/H) would leave float range (at most exp(40)).
    T min_altitude_m = T(kMinAltitudeM);
    /// E_sun0 times the ozone layer's transmittance towards the sun from the eye
    /// (ozone_transmittance): the sunlight above the Rayleigh and Mie columns for the `height`
    /// model, exact for points below the ozone layer (10 km for earth). E_sun0 without ozone.
    glm::vec<3, T> sun_irradiance_top{0};
    glm::vec<3, T> sun_irradiance_eye{0};  ///< E_sun0 * T_sun(eye), exact (2002 model's E_sun)
    /// log(H Ch) of each component at the eye for the `height` model's sun transmittance (see
    /// sun_transmittance_chapman); 80 or more when the planet blocks the sun there.
    T eye_log_chapman_rayleigh = 0;
    T eye_log_chapman_mie = 0;
    /// Unit local zenith at the eye and the sun's cosine to it.
    glm::vec<3, T> eye_zenith{0, 0, 1};
    T eye_cos_sun_zenith = 1;
    /// The `height` model's light scattered more than once, cut for the sun at prepare_frame's eye
    /// (frame_with_eye keeps it); null for the other models and where nothing scatters.
    std::shared_ptr<const detail::MultipleScatteringSlice> multiple_scattering;
};

/// The altitude below which density is clamped for this atmosphere (Frame::min_altitude_m):
/// kMinAltitudeM, or -40 times the shorter scale height when that is higher.
double min_density_altitude_m(const Atmosphere& atmosphere);

/// What prepare_frame computes beyond a model's constants.
struct FrameOptions {
    /// `height` only: add the light scattered more than once (Frame::multiple_scattering). The
    /// first frame of an atmosphere computes its table (docs/models.md, "The height model's
    /// higher orders": about 0.6 s for `earth` on 2 cores, then kept in memory and in the disk
    /// cache); for atmospheres far outside any planet's (scale heights of metres, optical depths
    /// of thousands) that takes minutes: leave it off there.
    bool multiple_scattering = true;
};

/// Validates atmosphere and view, then does the per-frame work. T is float or double.
template <class T>
Result<Frame<T>> prepare_frame(const Atmosphere& atmosphere, const View& view, Model model,
                               const FrameOptions& options = {});

/// The frame with its eye moved to `eye_m` (metres, world frame): the eye's altitude and the
/// `height` model's sun factors there. For speed the 2002 model's exact E_sun is recomputed
/// only when frame.model is hoffman_preetham (the only model that reads it). Used to chain the
/// models along a long ray (aerial/sky.hpp).
template <class T>
Frame<T> frame_with_eye(const Frame<T>& frame, const glm::dvec3& eye_m);

/// Vertices farther than this from the eye (m), or with a NaN or infinite coordinate, are not
/// positions: `scatter` returns F_ex = 1, L_in = 0, E_sun = 0 for them (the batch API counts
/// them; `evaluate` reports them as an error).
inline constexpr double kMaxDistanceM = 1e12;

/// F_ex, L_in and E_sun at one vertex (engine units, like View::eye). Never NaN.
template <class T>
Scattering<T> scatter(const Frame<T>& frame, const glm::vec<3, T>& vertex);

/// Convenience for one-off evaluations in double: prepare_frame + scatter.
Result<Scattering<double>> evaluate(const Atmosphere& atmosphere, const View& view, Model model,
                                    const glm::dvec3& vertex);

// ---- Building blocks, exposed for tests and tools --------------------------------------------

/// Altitude above the sphere of radius planet_radius_m centred at -planet_radius_m * up, for a
/// position in metres; accurate in float near the origin (no cancellation against the radius).
template <class T>
T altitude_above_sphere(const glm::vec<3, T>& position_m, const glm::vec<3, T>& up,
                        T planet_radius_m);

/// Exact transmittance from a point at `altitude_m` to space along a direction whose cosine
/// with the local zenith is `cos_zenith`, through the truncated exponential atmosphere (numerical
/// integration, double). Zero when the planet blocks the direction. Points below sea level are
/// shadowed as if they were on the surface.
glm::dvec3 sun_transmittance(const Atmosphere& atmosphere, double altitude_m, double cos_zenith);

/// Transmittance of the ozone layer alone from a point at `altitude_m` towards a direction whose
/// cosine with the local zenith is `cos_zenith` (1 without ozone), in closed form (about 0.1 us).
/// Where the planet blocks the direction it is taken at the horizon's cosine, where sunlight
/// grazing the shadow comes from. The `height` and 2002 models multiply E_sun0 by it at the eye
/// (Frame::sun_irradiance_top).
glm::dvec3 ozone_transmittance(const Atmosphere& atmosphere, double altitude_m, double cos_zenith);

/// The ozone layer's column along that direction up to the atmosphere's top (not stopped by the
/// planet), m of peak density: ozone_absorption times it is the optical depth.
double ozone_column_m(const Atmosphere& atmosphere, double altitude_m, double cos_zenith);

/// Fast approximation of the same for the `height` model: per component
/// tau = beta * H * exp(-h/H) * Ch(x, chi) with the asymptotic Chapman function of
/// x = (R + h) / H, no truncation at the atmosphere top. Within 1 % in optical depth of
/// sun_transmittance for zenith angles up to 90 deg, and handles the sun below the horizon.
template <class T>
glm::vec<3, T> sun_transmittance_chapman(const Frame<T>& frame, T altitude_m, T cos_zenith);

/// The closed form of the 2002 model for a given segment length, phase cosine and E_sun: used by
/// the hoffman_preetham model and by the bridge test against the reference integrator.
template <class T>
Scattering<T> hoffman_preetham_closed_form(const Frame<T>& frame, T distance_m, T cos_theta,
                                           const glm::vec<3, T>& sun_irradiance);

/// Resolution and stopping rule of the `reference` model's tables of the light scattered more
/// than once (docs/models.md, "The reference"). The defaults are what `reference` uses; finer
/// tables are for convergence studies. `validate` names a field out of its range;
/// reference_scattering clamps such fields into range instead.
struct MultipleScatteringSettings {
    int altitudes = 32;            ///< table rows in altitude, denser towards the ground, >= 4
    int sun_zenith_angles = 32;    ///< rows in sun zenith angle over 0 .. 108 degrees, >= 4
    int view_zenith_angles = 33;   ///< rows in view zenith angle over 0 .. 180 degrees, >= 5
    int azimuths = 16;             ///< rows in view azimuth from the sun's, 0 .. 180 deg, >= 3
    int sky_directions = 16;       ///< incoming zenith cosines above the horizon (Gauss), >= 2
    int ground_directions = 8;     ///< incoming zenith cosines below the horizon (Gauss), >= 2
    int half_azimuths = 12;        ///< incoming azimuths over 0 .. 180 degrees (mirrored), >= 2
    double steps_per_efold = 2.0;  ///< ray steps per e-fold of density or optical depth, >= 0.5
    /// Stop when the geometric bound on the orders not summed is below this fraction of the sum.
    double max_remainder = 1e-3;
    int max_orders = 80;  ///< hard stop (the report then gives the remainder bound reached)
};
bool operator==(const MultipleScatteringSettings& a, const MultipleScatteringSettings& b);
/// The first field outside its range: the minimums above, at most 256 rows per table axis and
/// 128 incoming directions per axis (the tables' memory grows with their product), steps per
/// e-fold at most 64, max_remainder in (0, 0.5], max_orders at most 1000.
std::optional<Error> validate(const MultipleScatteringSettings& settings);

/// What computing the tables found and cost.
struct MultipleScatteringReport {
    int orders = 0;  ///< highest order summed (2 or more)
    /// Bound on the share of the orders not summed, per channel: q/(1-q) times the last order's
    /// share, q the ratio of the last two orders (infinite if they do not decrease, or if
    /// max_orders stopped the sum before two orders could be compared); 0 without scattering.
    glm::dvec3 remainder_bound{0.0};
    /// Sum of each order's scattering density over the table, per channel, orders 2, 3, ...
    std::vector<glm::dvec3> order_sums;
    double seconds = 0.0;  ///< wall time to compute the tables
    /// Read from the per-user disk cache (docs/models.md, "Table cache"): `seconds` is then the
    /// time it took when it was computed.
    bool from_cache = false;
};

/// Computes (or finds in the cache) the tables `reference` uses for this atmosphere, and reports
/// on them; an invalid atmosphere or settings is an error naming the field. The first call per
/// atmosphere costs seconds (docs/models.md gives the figures); later calls and `reference` itself
/// reuse the tables.
Result<MultipleScatteringReport> reference_multiple_scattering(
    const Atmosphere& atmosphere, const MultipleScatteringSettings& settings = {});

/// Options of the reference integrator.
struct ReferenceOptions {
    /// Use sea-level density everywhere (no exponential fall-off, no atmosphere top): with
    /// sun_attenuation off this is exactly the 2002 closed form with E_sun = E_sun0.
    bool constant_density = false;
    /// Attenuate sunlight on its way to each sample (and shadow it by the planet).
    bool sun_attenuation = true;
    /// Integration steps per e-fold of density or of optical depth; 2 gives <= 1e-6 relative
    /// against the closed forms, larger is for convergence studies.
    double steps_per_efold = 2.0;
    /// Add the light scattered more than once and the ground's reflection (the `reference`
    /// model); off, the integrator is the `single_scattering` model. Needs the real profile
    /// (constant_density off) and sun_attenuation on; ignored otherwise.
    bool multiple_scattering = false;
    /// The tables of the higher orders (defaults: those of the `reference` model).
    MultipleScatteringSettings tables;
};

/// The `single_scattering` model at one vertex (metres, world frame), or with
/// options.multiple_scattering the `reference` model.
Scattering<double> reference_scattering(const Atmosphere& atmosphere, const View& view,
                                        const glm::dvec3& vertex,
                                        const ReferenceOptions& options = {});

}  // namespace aerial
