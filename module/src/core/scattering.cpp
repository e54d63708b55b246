// The per-vertex models `hoffman-preetham` and `height`, the per-frame preparation, and the
// Chapman approximation of sun transmittance. The `reference` model lives in reference.cpp.
#include "aerial/scattering.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "aerial/phase.hpp"
#include "height_constants.hpp"
#include "height_multiple_scattering.hpp"
#include "height_parts.hpp"
#include "math.hpp"

namespace aerial {
namespace {

using detail::invalid;
using detail::number;
using detail::vector;

template <class T>
using Vec3 = glm::vec<3, T>;

constexpr double kUnitLengthTolerance = 1e-3;

using detail::height::kBlockedLogColumn;
using detail::height::kMaxExponent;
using detail::height::kMaxFitSlope;

}  // namespace

constexpr detail::NameTable<Model, 4> kModelNames{{{Model::hoffman_preetham, "hoffman-preetham"},
                                                   {Model::height, "height"},
                                                   {Model::single_scattering, "single-scattering"},
                                                   {Model::reference, "reference"}}};

std::string_view model_name(Model model) { return detail::name_in(kModelNames, model); }

const std::vector<Model>& all_models() {
    static const std::vector<Model> models = [] {
        std::vector<Model> all;
        for (const auto& entry : kModelNames) all.push_back(entry.value);
        return all;
    }();
    return models;
}

Result<Model> parse_model(std::string_view name) {
    return detail::parse_in("parse_model", kModelNames, "model", name);
}

std::optional<Error> validate(const View& view) {
    auto finite = [](const glm::dvec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    constexpr const char* kFunction = "validate";
    if (!finite(view.eye)) return invalid(kFunction, "eye", "finite coordinates", vector(view.eye));
    const struct {
        const char* name;
        const glm::dvec3& value;
    } units[] = {{"sun_dir", view.sun_dir}, {"up", view.up}};
    for (const auto& u : units) {
        if (!finite(u.value) || std::abs(glm::length(u.value) - 1.0) > kUnitLengthTolerance) {
            return invalid(kFunction, u.name, "a unit vector",
                           vector(u.value) + " (length " + number(glm::length(u.value)) + ")");
        }
    }
    if (!std::isfinite(view.meters_per_unit) || view.meters_per_unit <= 0.0) {
        return invalid(kFunction, "meters_per_unit", "a finite value > 0",
                       number(view.meters_per_unit));
    }
    // The float paths take the eye in engine units and in metres: beyond kMaxDistanceM (where
    // vertices count as invalid) or beyond float's range it would be infinite there, and every
    // colour NaN.
    const double largest =
        std::max({std::abs(view.eye.x), std::abs(view.eye.y), std::abs(view.eye.z)});
    if (largest * view.meters_per_unit > kMaxDistanceM ||
        largest > double(std::numeric_limits<float>::max())) {
        return invalid(kFunction, "eye",
                       "coordinates within " + number(kMaxDistanceM) +
                           " m of the origin (and float-sized in engine units)",
                       vector(view.eye) + " at " + number(view.meters_per_unit) + " m per unit");
    }
    return std::nullopt;
}

template <class T>
T altitude_above_sphere(const Vec3<T>& p, const Vec3<T>& up, T planet_radius_m) {
    // |p - c| - R with c = -R up, rewritten as (|p|^2 + 2 R p.up) / (|p - c| + R) so that float
    // keeps full precision near the origin instead of cancelling two numbers of size R.
    const T along_up = glm::dot(p, up);
    const T p2 = glm::dot(p, p);
    const T numerator = p2 + T(2) * planet_radius_m * along_up;
    const T distance_to_centre =
        std::sqrt(std::max(T(0), numerator + planet_radius_m * planet_radius_m));
    return numerator / (distance_to_centre + planet_radius_m);
}

namespace {

/// log(H Ch(x, chi)): the optical depth of one exponential component from altitude h to space,
/// along a direction with cosine mu to the local zenith, is beta * exp(-h/H) * exp(this). Uses the
/// asymptotic Chapman function of x = (R + h) / H (relative error about 1/x). Returns
/// kBlockedLogColumn when the planet blocks the direction.
template <class T>
T log_chapman_factor(T altitude_m, T cos_zenith, T planet_radius_m, T scale_height_m,
                     T min_altitude_m) {
    using detail::height::kSqrtHalfPi;
    const T h = std::max(altitude_m, min_altitude_m);
    const T x = (planet_radius_m + h) / scale_height_m;
    const T mu = std::clamp(cos_zenith, T(-1), T(1));
    const T upward =
        T(kSqrtHalfPi) * std::sqrt(x) * detail::erfcx(std::sqrt(x * T(0.5)) * std::abs(mu));
    if (mu >= T(0)) return std::log(scale_height_m * upward);
    // Below the horizon: the ray passes a tangent point at altitude h_t <= h. Twice the
    // horizontal column from there, minus the column of the mirrored upward ray from the point;
    // relative to exp(-h/H): 2 Ch(x_t, 90 deg) exp((h - h_t)/H) - Ch(x, 180 deg - chi).
    const T sin_chi = std::sqrt(std::max(T(0), T(1) - mu * mu));
    // h_t = (R + h) sin_chi - R, written without cancelling R against R.
    const T tangent_altitude = h * sin_chi - planet_radius_m * mu * mu / (T(1) + sin_chi);
    const T shadow_floor = std::min(h, T(0));  // points below sea level see the sun like h = 0
    if (tangent_altitude < shadow_floor) return T(kBlockedLogColumn);
    const T x_t = (planet_radius_m + tangent_altitude) / scale_height_m;
    const T rise = (h - tangent_altitude) / scale_height_m;  // >= 0
    const T horizontal = T(kSqrtHalfPi) * std::sqrt(x_t);
    const T factor = std::max(T(2) * horizontal - upward * std::exp(-rise),
                              T(detail::height::kMinChapmanFactor));
    return std::min(rise + std::log(scale_height_m * factor), T(kBlockedLogColumn));
}

/// Sun transmittance from the log Chapman factors of both components at altitude h.
template <class T>
Vec3<T> transmittance_from_log_factors(const Frame<T>& f, T h, T log_factor_r, T log_factor_m) {
    if (log_factor_r >= T(kBlockedLogColumn) || log_factor_m >= T(kBlockedLogColumn)) {
        return Vec3<T>(0);
    }
    const T column_r =
        std::exp(std::min(log_factor_r - h * f.inv_rayleigh_scale_height, T(kMaxExponent)));
    const T column_m =
        std::exp(std::min(log_factor_m - h * f.inv_mie_scale_height, T(kMaxExponent)));
    return glm::exp(-(f.rayleigh_scattering * column_r + f.mie_extinction * column_m));
}

/// Cosine between the sun and the local zenith at a point (metres, world frame).
template <class T>
T sun_cos_zenith_at(const Frame<T>& f, const Vec3<T>& p_m) {
    const Vec3<T> from_centre = p_m + f.up * f.planet_radius_m;
    const T length = glm::length(from_centre);
    return length > T(0) ? glm::dot(from_centre, f.sun_dir) / length : T(1);
}

}  // namespace

template <class T>
Vec3<T> sun_transmittance_chapman(const Frame<T>& f, T altitude_m, T cos_zenith) {
    const T min_h = f.min_altitude_m;
    const T h = std::max(altitude_m, min_h);
    return transmittance_from_log_factors(
        f, h,
        log_chapman_factor(h, cos_zenith, f.planet_radius_m, f.rayleigh_scale_height_m, min_h),
        log_chapman_factor(h, cos_zenith, f.planet_radius_m, f.mie_scale_height_m, min_h));
}

template <class T>
Scattering<T> hoffman_preetham_closed_form(const Frame<T>& f, T distance_m, T cos_theta,
                                           const Vec3<T>& sun_irradiance) {
    const T s = std::max(distance_m, T(0));
    const Vec3<T> extinction = f.rayleigh_scattering + f.mie_extinction;
    const Vec3<T> angular = f.rayleigh_scattering * rayleigh_phase(cos_theta) +
                            f.mie_scattering * henyey_greenstein_phase(cos_theta, f.mie_g);
    Scattering<T> out;
    for (int c = 0; c < 3; ++c) {
        const T tau = extinction[c] * s;
        out.extinction[c] = std::exp(-tau);
        out.in_scattering[c] =
            angular[c] * sun_irradiance[c] * s * detail::one_minus_exp_over_x(tau);
    }
    out.sun_irradiance = sun_irradiance;
    return out;
}

namespace {

using detail::height::kSunNodes;
using detail::height::kSunWeights;

/// The u in [0, 1] below which a fraction v of the weight exp(-k u) on [0, 1] lies (its inverse
/// CDF), for |k| <= 80.
template <class T>
T exponential_quantile(T v, T k) {
    if (std::abs(k) < T(detail::height::kLinearFitLimit)) return v - k * v * (T(1) - v) * T(0.5);
    return std::clamp(-std::log1p(v * std::expm1(-k)) / k, T(0), T(1));
}

/// Whether the planet's shadow covers a point (metres, world frame): it lies on the night side
/// within the cylinder of radius R around the axis through the planet centre along the sun.
/// With c = p + R up, along = c.sun and |c|^2 - along^2 < R^2 is expanded so that no R^2 term is
/// formed and cancelled in float: the edge stays sharp to millimetres.
template <class T>
bool in_planet_shadow(const Frame<T>& f, const Vec3<T>& p_m) {
    const T r = f.planet_radius_m;
    const T up_sun = glm::dot(f.up, f.sun_dir);
    const T p_sun = glm::dot(p_m, f.sun_dir);
    const T along = p_sun + r * up_sun;
    if (along >= T(0)) return false;
    const T excess = glm::dot(p_m, p_m) + T(2) * r * glm::dot(p_m, f.up) - p_sun * p_sun -
                     T(2) * r * p_sun * up_sun - r * r * up_sun * up_sun;
    return excess < T(0);
}

/// shape(h, v) of the frame's slice at altitude h for the view from the eye along d (length
/// s > 0; the zenith's shape at s = 0), cos_theta its cosine to the sun.
template <class T>
Vec3<T> multiple_scattering_shape(const Frame<T>& f, T altitude_m, const Vec3<T>& d, T s,
                                  T cos_theta) {
    const T mu_v = s > T(0) ? std::clamp(glm::dot(d, f.eye_zenith) / s, T(-1), T(1)) : T(1);
    const T mu_s = f.eye_cos_sun_zenith;
    const T across = std::sqrt(std::max(T(0), (T(1) - mu_v * mu_v) * (T(1) - mu_s * mu_s)));
    const T cos_azimuth =
        across > T(1e-6) ? std::clamp((cos_theta - mu_v * mu_s) / across, T(-1), T(1)) : T(1);
    return detail::slice_shape(*f.multiple_scattering, altitude_m, mu_v, cos_azimuth);
}

}  // namespace

template <class T>
detail::HeightParts<T> detail::height_parts(const Frame<T>& f, const Vec3<T>& p_m) {
    const Vec3<T> d = p_m - f.eye_m;
    const T s = glm::length(d);
    const T cos_theta = s > T(0) ? glm::dot(d, f.sun_dir) / s : T(1);
    const T min_h = f.min_altitude_m;
    const T h0 = f.eye_altitude_m;
    const T h1 = std::max(altitude_above_sphere(p_m, f.up, f.planet_radius_m), min_h);
    const T rise = h1 - h0;
    const T dh = std::abs(rise);
    // A straight segment sags below the line joining its end altitudes by u (1 - u) s^2 / (2 R)
    // at fraction u; its mean sag s^2 / (12 R) lowers the altitude of the density average.
    const T sag = s * s / (T(2) * f.planet_radius_m);
    const T h_low = std::max(std::min(h0, h1) - sag * T(detail::height::kMeanSagFraction), min_h);

    // Path-averaged density of each component over a segment whose altitude goes linearly from
    // h0 to h1: exp(-h_low/H) (1 - exp(-dh/H)) / (dh/H), exact when dh = 0.
    const T x_r = dh * f.inv_rayleigh_scale_height;
    const T x_m = dh * f.inv_mie_scale_height;
    const T rho_r =
        std::exp(-h_low * f.inv_rayleigh_scale_height) * detail::one_minus_exp_over_x(x_r);
    const T rho_m = std::exp(-h_low * f.inv_mie_scale_height) * detail::one_minus_exp_over_x(x_m);

    HeightParts<T> out;
    // Sun at the vertex, and the log Chapman factors at both ends of the segment.
    const T mu1 = sun_cos_zenith_at(f, p_m);
    const T lf_r1 =
        log_chapman_factor(h1, mu1, f.planet_radius_m, f.rayleigh_scale_height_m, min_h);
    const T lf_m1 = log_chapman_factor(h1, mu1, f.planet_radius_m, f.mie_scale_height_m, min_h);
    out.sun_irradiance = f.sun_irradiance_top * transmittance_from_log_factors(f, h1, lf_r1, lf_m1);
    // A blocked end borrows the other end's factor; the shadow itself is tested per node below.
    const bool lit0 = f.eye_log_chapman_rayleigh < T(kBlockedLogColumn);
    const bool lit1 = lf_r1 < T(kBlockedLogColumn) && lf_m1 < T(kBlockedLogColumn);
    const T lr0 = lit0 ? f.eye_log_chapman_rayleigh : lf_r1,
            lm0 = lit0 ? f.eye_log_chapman_mie : lf_m1;
    const T lr1 = lit1 ? lf_r1 : lr0, lm1 = lit1 ? lf_m1 : lm0;

    // Sunlight scattered by each component i: the mean of the sun transmittance T(u) over the
    // segment (u in [0, 1] from the eye), weighted by the light that reaches the eye from there,
    // rho_i(u) exp(-tau(0, u)) (G channel). At a low sun T varies by e^2 and more along the
    // segment, so no single mean point will do (Jensen's inequality); in fog the weight piles up
    // near the eye. Quadrature: 3 Gauss nodes in y = share of the segment's attenuation
    // 1 - exp(-tau(0, u)), mapped to u through a one-exponential fit of the extinction profile,
    // which makes the weight flat in y for a single dominant component; the exact Jacobian and
    // each component's density ratio enter the weights, which are normalised per component.
    const T a_r = rise * f.inv_rayleigh_scale_height;
    const T a_m = rise * f.inv_mie_scale_height;
    const T rho_r0 = std::exp(-h0 * f.inv_rayleigh_scale_height);  // densities at the eye
    const T rho_m0 = std::exp(-h0 * f.inv_mie_scale_height);
    const T k_r0 = f.rayleigh_scattering.y * rho_r0;
    const T k_m0 = f.mie_extinction.y * rho_m0;
    const T k_total = k_r0 + k_m0;  // G extinction at the eye, 1/m
    // Optical depth of channel c from the eye to u along the linear altitude profile (closed
    // form), from the components' mean densities over [0, u] relative to the eye's.
    auto tau_c = [&](int c, T u, T mean_r, T mean_m) {
        return s * u *
               (f.rayleigh_scattering[c] * rho_r0 * mean_r + f.mie_extinction[c] * rho_m0 * mean_m);
    };
    auto tau_to = [&](T u) {  // G
        return tau_c(1, u, detail::exponential_average(a_r * u),
                     detail::exponential_average(a_m * u));
    };
    // sunlit[i][c] = the integral over u of rho_i(u) exp(-tau_c(0, u)) T_c(u); for a uniform
    // medium in full sun it is rho_i phi(tau_c), phi(x) = (1 - exp(-x)) / x. The quadrature's
    // nodes and weights follow the G channel; each channel's own attenuation to the node enters
    // as exp(tau_G(0, u) - tau_c(0, u)) (away from the G channel it decides which part of a long
    // ray reaches the eye). The weights are assembled in log form: dense haze and long segments
    // make their factors overflow floats.
    Vec3<T> sunlit[2] = {Vec3<T>(0), Vec3<T>(0)};
    // The same weights times level(h) at the nodes: the light scattered more than once, which
    // also reaches the planet's shadow (height_multiple_scattering.hpp).
    const detail::MultipleScatteringSlice* ms = f.multiple_scattering.get();
    Vec3<T> multiple[2] = {Vec3<T>(0), Vec3<T>(0)};
    // The altitude the higher orders come from: the nodes' altitudes weighted by their share of
    // them (G channel); the shape is taken there.
    T ms_weight = 0, ms_altitude = 0;
    if ((lit0 || lit1 || ms) && k_total > T(0)) {
        const T tau_total = tau_to(T(1));
        const T k_end = k_r0 * std::exp(std::min(-a_r, T(kMaxExponent))) +
                        k_m0 * std::exp(std::min(-a_m, T(kMaxExponent)));
        const T a_fit = std::clamp(k_end > T(0) ? std::log(k_total / k_end) : T(kMaxFitSlope),
                                   T(-kMaxFitSlope), T(kMaxFitSlope));
        const T log_scale =
            detail::log_one_minus_exp_over_x(a_fit) + detail::log_one_minus_exp_over_x(tau_total);
        for (int n = 0; n < 3; ++n) {
            const T y = T(kSunNodes[n]);
            // Fitted optical depth to the node, then the u where the fit reaches it.
            const T tau_fit = tau_total < T(detail::height::kLinearDepthLimit)
                                  ? y * tau_total
                                  : -std::log1p(y * std::expm1(-tau_total));
            const T fraction = tau_total > T(0) ? std::clamp(tau_fit / tau_total, T(0), T(1)) : y;
            const T u = exponential_quantile(fraction, a_fit);
            const T h = std::max(h0 + rise * u - sag * u * (T(1) - u), min_h);
            const T mean_r = detail::exponential_average(a_r * u);
            const T mean_m = detail::exponential_average(a_m * u);
            const T tau_g = tau_c(1, u, mean_r, mean_m);
            // log of du/dy times the exact over the fitted attenuation, plus the scale.
            const T log_jacobian = tau_fit - tau_g + a_fit * u + log_scale;
            const T w_r =
                std::exp(std::min(log_jacobian - h * f.inv_rayleigh_scale_height, T(kMaxExponent)));
            const T w_m =
                std::exp(std::min(log_jacobian - h * f.inv_mie_scale_height, T(kMaxExponent)));
            Vec3<T> channel(1);  // exp(tau_G - tau_c) to the node, the Gauss weight included
            for (int c : {0, 2}) {
                channel[c] = std::exp(std::clamp(tau_g - tau_c(c, u, mean_r, mean_m),
                                                 T(-kMaxExponent), T(kMaxExponent)));
            }
            channel *= T(kSunWeights[n]);
            if (ms) {
                // The sun at the node: linear in its cosine between the eye's and the vertex's.
                const T mu_node = f.eye_cos_sun_zenith + (mu1 - f.eye_cos_sun_zenith) * u;
                const Vec3<T> level = channel * detail::slice_level(*ms, h, mu_node);
                multiple[0] += w_r * level;
                multiple[1] += w_m * level;
                const T share =
                    (f.rayleigh_scattering.y * w_r + f.mie_scattering.y * w_m) * level.y;  // G
                ms_weight += share;
                ms_altitude += share * h;
            }
            if (!(lit0 || lit1) || in_planet_shadow(f, f.eye_m + d * u)) continue;
            const Vec3<T> sun = channel * transmittance_from_log_factors(
                                              f, h, lr0 + (lr1 - lr0) * u, lm0 + (lm1 - lm0) * u);
            sunlit[0] += w_r * sun;
            sunlit[1] += w_m * sun;
        }
    }

    const T ms_h = ms_weight > T(0) ? ms_altitude / ms_weight : h0;
    const Vec3<T> shape = ms ? multiple_scattering_shape(f, ms_h, d, s, cos_theta) : Vec3<T>(0);
    for (int c = 0; c < 3; ++c) {
        const T beta_ex = f.rayleigh_scattering[c] * rho_r + f.mie_extinction[c] * rho_m;
        const T sun_s = f.sun_irradiance_top[c] * s;
        out.extinction[c] = std::exp(-beta_ex * s);
        out.rayleigh[c] = f.rayleigh_scattering[c] * sunlit[0][c] * sun_s;
        out.mie[c] = f.mie_scattering[c] * sunlit[1][c] * sun_s;
        out.multiple[c] =
            (f.rayleigh_scattering[c] * multiple[0][c] + f.mie_scattering[c] * multiple[1][c]) *
            shape[c] * s;
    }
    return out;
}

namespace {

template <class T>
Scattering<T> height_model(const Frame<T>& f, const Vec3<T>& p_m) {
    const detail::HeightParts<T> parts = detail::height_parts(f, p_m);
    const Vec3<T> d = p_m - f.eye_m;
    const T s = glm::length(d);
    const T cos_theta = s > T(0) ? glm::dot(d, f.sun_dir) / s : T(1);
    Scattering<T> out;
    out.extinction = parts.extinction;
    out.sun_irradiance = parts.sun_irradiance;
    out.in_scattering =
        parts.in_scattering(rayleigh_phase(cos_theta), henyey_greenstein_phase(cos_theta, f.mie_g));
    return out;
}

}  // namespace

double min_density_altitude_m(const Atmosphere& a) {
    // exp(-h/H) <= exp(40) for either component: finite in float.
    return std::max(kMinAltitudeM,
                    -40.0 * std::min(a.rayleigh_scale_height_m, a.mie_scale_height_m));
}

namespace {

/// The eye-dependent part of a frame; the exact E_sun at the eye (a numerical integration) only
/// when asked.
template <class T>
void set_frame_eye(Frame<T>& f, const glm::dvec3& eye_m, bool exact_sun_irradiance) {
    const Atmosphere& atmosphere = f.atmosphere;
    f.eye_m = Vec3<T>(eye_m);
    f.view.eye = eye_m / f.view.meters_per_unit;
    const double eye_altitude = altitude_above_sphere(eye_m, f.view.up, atmosphere.planet_radius_m);
    f.eye_altitude_m = std::max(T(eye_altitude), f.min_altitude_m);
    const glm::dvec3 eye_from_centre = eye_m + f.view.up * atmosphere.planet_radius_m;
    const double eye_cos_zenith =
        glm::dot(eye_from_centre, f.view.sun_dir) / glm::length(eye_from_centre);
    f.eye_zenith = Vec3<T>(glm::normalize(eye_from_centre));
    f.eye_cos_sun_zenith = T(eye_cos_zenith);
    if (exact_sun_irradiance) {
        f.sun_irradiance_eye = Vec3<T>(atmosphere.sun_irradiance *
                                       sun_transmittance(atmosphere, eye_altitude, eye_cos_zenith));
    }
    f.sun_irradiance_top = Vec3<T>(atmosphere.sun_irradiance *
                                   ozone_transmittance(atmosphere, eye_altitude, eye_cos_zenith));
    const T min_h = f.min_altitude_m;
    f.eye_log_chapman_rayleigh =
        log_chapman_factor(f.eye_altitude_m, T(eye_cos_zenith), f.planet_radius_m,
                           T(atmosphere.rayleigh_scale_height_m), min_h);
    f.eye_log_chapman_mie =
        log_chapman_factor(f.eye_altitude_m, T(eye_cos_zenith), f.planet_radius_m,
                           T(atmosphere.mie_scale_height_m), min_h);
    if (f.eye_log_chapman_mie >= T(kBlockedLogColumn))
        f.eye_log_chapman_rayleigh = f.eye_log_chapman_mie;
}

}  // namespace

template <class T>
Result<Frame<T>> prepare_frame(const Atmosphere& atmosphere, const View& view, Model model,
                               const FrameOptions& options) {
    if (auto e = validate(atmosphere)) return detail::from("prepare_frame", *e);
    if (auto e = validate(view)) return detail::from("prepare_frame", *e);
    Frame<T> f;
    f.model = model;
    f.atmosphere = atmosphere;
    f.view = view;
    f.view.sun_dir = glm::normalize(view.sun_dir);
    f.view.up = glm::normalize(view.up);
    const glm::dvec3 eye_m = view.eye * view.meters_per_unit;
    f.eye_m = Vec3<T>(eye_m);
    f.sun_dir = Vec3<T>(f.view.sun_dir);
    f.up = Vec3<T>(f.view.up);
    f.meters_per_unit = T(view.meters_per_unit);
    f.planet_radius_m = T(atmosphere.planet_radius_m);
    f.rayleigh_scattering = Vec3<T>(atmosphere.rayleigh_scattering);
    f.mie_scattering = Vec3<T>(atmosphere.mie_scattering);
    f.mie_extinction = Vec3<T>(atmosphere.mie_extinction());
    f.mie_g = T(atmosphere.mie_g);
    f.inv_rayleigh_scale_height = T(1.0 / atmosphere.rayleigh_scale_height_m);
    f.inv_mie_scale_height = T(1.0 / atmosphere.mie_scale_height_m);
    f.rayleigh_scale_height_m = T(atmosphere.rayleigh_scale_height_m);
    f.mie_scale_height_m = T(atmosphere.mie_scale_height_m);
    f.min_altitude_m = T(min_density_altitude_m(atmosphere));
    set_frame_eye(f, eye_m, true);
    if (model == Model::height && options.multiple_scattering) {
        f.multiple_scattering =
            detail::multiple_scattering_slice(atmosphere, double(f.eye_cos_sun_zenith));
    }
    return f;
}

template <class T>
Frame<T> frame_with_eye(const Frame<T>& base, const glm::dvec3& eye_m) {
    Frame<T> f = base;
    set_frame_eye(f, eye_m, f.model == Model::hoffman_preetham);
    return f;
}

template <class T>
void detail::move_frame_eye(Frame<T>& frame, const glm::dvec3& eye_m) {
    set_frame_eye(frame, eye_m, frame.model == Model::hoffman_preetham);
}

template <class T>
Scattering<T> scatter(const Frame<T>& f, const Vec3<T>& vertex) {
    const Vec3<T> p_m = vertex * f.meters_per_unit;
    const T distance = glm::length(p_m - f.eye_m);
    if (!(distance <= T(kMaxDistanceM))) {  // also catches NaN and Inf coordinates
        return Scattering<T>{Vec3<T>(1), Vec3<T>(0), Vec3<T>(0)};
    }
    switch (f.model) {
        case Model::hoffman_preetham: {
            const Vec3<T> d = p_m - f.eye_m;
            const T s = glm::length(d);
            const T cos_theta = s > T(0) ? glm::dot(d, f.sun_dir) / s : T(1);
            return hoffman_preetham_closed_form(f, s, cos_theta, f.sun_irradiance_eye);
        }
        case Model::height:
            return height_model(f, p_m);
        case Model::single_scattering:
        case Model::reference: {
            View view = f.view;
            view.meters_per_unit = 1.0;
            view.eye = view.eye * f.view.meters_per_unit;
            ReferenceOptions options;
            options.multiple_scattering = f.model == Model::reference;
            const Scattering<double> r =
                reference_scattering(f.atmosphere, view, glm::dvec3(p_m), options);
            return Scattering<T>{Vec3<T>(r.extinction), Vec3<T>(r.in_scattering),
                                 Vec3<T>(r.sun_irradiance)};
        }
    }
    return {};
}

Result<Scattering<double>> evaluate(const Atmosphere& atmosphere, const View& view, Model model,
                                    const glm::dvec3& vertex) {
    auto frame = prepare_frame<double>(atmosphere, view, model);
    if (!frame) return detail::from("evaluate", frame.error());
    if (!std::isfinite(vertex.x) || !std::isfinite(vertex.y) || !std::isfinite(vertex.z))
        return invalid("evaluate", "vertex", "finite coordinates", vector(vertex));
    return scatter(*frame, vertex);
}

#define AERIAL_INSTANTIATE(T)                                                                      \
    template T altitude_above_sphere<T>(const Vec3<T>&, const Vec3<T>&, T);                        \
    template Vec3<T> sun_transmittance_chapman<T>(const Frame<T>&, T, T);                          \
    template Scattering<T> hoffman_preetham_closed_form<T>(const Frame<T>&, T, T, const Vec3<T>&); \
    template Result<Frame<T>> prepare_frame<T>(const Atmosphere&, const View&, Model,              \
                                               const FrameOptions&);                               \
    template Frame<T> frame_with_eye<T>(const Frame<T>&, const glm::dvec3&);                       \
    template Scattering<T> scatter<T>(const Frame<T>&, const Vec3<T>&);                            \
    template detail::HeightParts<T> detail::height_parts<T>(const Frame<T>&, const Vec3<T>&);      \
    template void detail::move_frame_eye<T>(Frame<T>&, const glm::dvec3&);
AERIAL_INSTANTIATE(float)
AERIAL_INSTANTIATE(double)
#undef AERIAL_INSTANTIATE

}  // namespace aerial
