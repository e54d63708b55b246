// The per-vertex models `hoffman-preetham` and `height`, the per-frame preparation, and the
// Chapman approximation of sun transmittance. The `reference` model lives in reference.cpp.
#include "aerial/scattering.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "aerial/phase.hpp"
#include "format.hpp"
#include "math.hpp"

namespace aerial {
namespace {

using detail::format_number;
using detail::format_vector;

template <class T>
using Vec3 = glm::vec<3, T>;

constexpr double kUnitLengthTolerance = 1e-3;

}  // namespace

std::string_view model_name(Model model) {
    switch (model) {
        case Model::hoffman_preetham: return "hoffman-preetham";
        case Model::height: return "height";
        case Model::reference: return "reference";
    }
    return "unknown";
}

const std::vector<Model>& all_models() {
    static const std::vector<Model> models{Model::hoffman_preetham, Model::height,
                                           Model::reference};
    return models;
}

Result<Model> parse_model(std::string_view name) {
    for (Model m : all_models()) {
        if (model_name(m) == name) return m;
    }
    return Error{"model", "model '" + std::string(name) +
                              "' is unknown; known models: hoffman-preetham, height, reference"};
}

std::optional<Error> validate(const View& view) {
    auto finite = [](const glm::dvec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    if (!finite(view.eye)) {
        return Error{"eye", "eye must be finite, got " + format_vector(view.eye)};
    }
    const struct {
        const char* name;
        const glm::dvec3& value;
    } units[] = {{"sun_dir", view.sun_dir}, {"up", view.up}};
    for (const auto& u : units) {
        if (!finite(u.value) || std::abs(glm::length(u.value) - 1.0) > kUnitLengthTolerance) {
            return Error{u.name, std::string(u.name) + " must be a unit vector, got " +
                                     format_vector(u.value) + " (length " +
                                     format_number(glm::length(u.value)) + ")"};
        }
    }
    if (!std::isfinite(view.meters_per_unit) || view.meters_per_unit <= 0.0) {
        return Error{"meters_per_unit",
                     "meters_per_unit must be finite and > 0, got " +
                         format_number(view.meters_per_unit)};
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
    const T distance_to_centre = std::sqrt(std::max(T(0), numerator + planet_radius_m * planet_radius_m));
    return numerator / (distance_to_centre + planet_radius_m);
}

namespace {

/// Optical depth of one exponential component from altitude h to space along a direction with
/// cosine mu to the local zenith, divided by its sea-level coefficient: H exp(-h/H) Ch(x, chi),
/// with the asymptotic Chapman function of x = (R + h) / H (relative error about 1/x). Returns
/// a negative value when the planet blocks the direction.
template <class T>
T chapman_column_m(T altitude_m, T cos_zenith, T planet_radius_m, T scale_height_m,
                   T min_altitude_m) {
    constexpr double kSqrtHalfPi = 1.2533141373155002512;
    const T h = std::max(altitude_m, min_altitude_m);
    const T r = planet_radius_m + h;
    const T x = r / scale_height_m;
    const T mu = std::clamp(cos_zenith, T(-1), T(1));
    if (mu >= T(0)) {
        const T y = std::sqrt(x * T(0.5)) * mu;
        return scale_height_m * std::exp(-h / scale_height_m) * T(kSqrtHalfPi) * std::sqrt(x) *
               detail::erfcx(y);
    }
    // Below the horizon: the ray passes a tangent point at altitude h_t. Twice the horizontal
    // column from there, minus the column of the mirrored upward ray from the point.
    const T sin_chi = std::sqrt(std::max(T(0), T(1) - mu * mu));
    // h_t = r sin_chi - R, written without cancelling r against R.
    const T tangent_altitude = h * sin_chi - planet_radius_m * mu * mu / (T(1) + sin_chi);
    const T shadow_floor = std::min(h, T(0));  // points below sea level see the sun like h = 0
    if (tangent_altitude < shadow_floor) return T(-1);
    const T x_t = (planet_radius_m + tangent_altitude) / scale_height_m;
    const T horizontal = T(kSqrtHalfPi) * std::sqrt(x_t) * std::exp(-tangent_altitude / scale_height_m);
    const T upward = std::exp(-h / scale_height_m) * T(kSqrtHalfPi) * std::sqrt(x) *
                     detail::erfcx(std::sqrt(x * T(0.5)) * (-mu));
    return scale_height_m * std::max(T(0), T(2) * horizontal - upward);
}

template <class T>
Vec3<T> transmittance_from_columns(const Frame<T>& f, T rayleigh_column_m, T mie_column_m) {
    if (rayleigh_column_m < T(0) || mie_column_m < T(0)) return Vec3<T>(0);
    const Vec3<T> tau = f.rayleigh_scattering * rayleigh_column_m + f.mie_extinction * mie_column_m;
    return glm::exp(-tau);
}

template <class T>
T min_density_altitude(const Frame<T>& f) {
    // Clamp so that exp(-h/H) <= exp(40) for either component: finite in float.
    const T min_scale_height = T(1) / std::max(f.inv_rayleigh_scale_height, f.inv_mie_scale_height);
    return std::max(T(kMinAltitudeM), T(-40) * min_scale_height);
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
    const T min_h = min_density_altitude(f);
    const T rayleigh = chapman_column_m(altitude_m, cos_zenith, f.planet_radius_m,
                                        T(1) / f.inv_rayleigh_scale_height, min_h);
    const T mie = chapman_column_m(altitude_m, cos_zenith, f.planet_radius_m,
                                   T(1) / f.inv_mie_scale_height, min_h);
    return transmittance_from_columns(f, rayleigh, mie);
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

template <class T>
Scattering<T> height_model(const Frame<T>& f, const Vec3<T>& p_m) {
    const Vec3<T> d = p_m - f.eye_m;
    const T s = glm::length(d);
    const T cos_theta = s > T(0) ? glm::dot(d, f.sun_dir) / s : T(1);
    const T min_h = min_density_altitude(f);
    const T h0 = f.eye_altitude_m;
    const T h1 = std::max(altitude_above_sphere(p_m, f.up, f.planet_radius_m), min_h);
    const T rise = h1 - h0;
    const T dh = std::abs(rise);
    // A straight segment sags below the line joining its end altitudes by t (s - t) / (2 R);
    // its mean sag s^2 / (12 R) lowers the altitude at which the density is averaged.
    const T mean_sag = s * s / (T(12) * f.planet_radius_m);
    const T h_low = std::max(std::min(h0, h1) - mean_sag, min_h);

    // Path-averaged density of each component over a segment whose altitude goes linearly from
    // h0 to h1: exp(-h_low/H) (1 - exp(-dh/H)) / (dh/H), exact when dh = 0.
    const T x_r = dh * f.inv_rayleigh_scale_height;
    const T x_m = dh * f.inv_mie_scale_height;
    const T rho_r = std::exp(-h_low * f.inv_rayleigh_scale_height) * detail::one_minus_exp_over_x(x_r);
    const T rho_m = std::exp(-h_low * f.inv_mie_scale_height) * detail::one_minus_exp_over_x(x_m);
    const T phase_r = rayleigh_phase(cos_theta);
    const T phase_m = henyey_greenstein_phase(cos_theta, f.mie_g);

    // Sunlight. Along the segment, each component's contribution to L_in is weighted by its
    // density (exponential in t, rate rise/H) times the transmittance back to the eye
    // (exponential in t, rate tau, G channel). The sun's optical depth at a point is
    // sum_j column_j, each column_j proportional to the density of component j there, with a
    // Chapman factor that varies slowly along the segment. So: take the Chapman factors at the
    // weighted mean point, and average each density exactly over each scatterer's weight.
    const T tau_g = s * (f.rayleigh_scattering.y * rho_r + f.mie_extinction.y * rho_m);
    const T k_r = rise * f.inv_rayleigh_scale_height + tau_g;  // weight rates over t in [0, 1]
    const T k_m = rise * f.inv_mie_scale_height + tau_g;
    const T w_r = f.rayleigh_scattering.y * rho_r * phase_r;
    const T w_m = f.mie_scattering.y * rho_m * phase_m;
    const T w = w_r + w_m;
    const T t_star = w > T(0) ? (w_r * detail::exponential_mean_fraction(k_r) +
                                 w_m * detail::exponential_mean_fraction(k_m)) /
                                    w
                              : T(0.5);
    const T h_star = std::max(h0 + rise * t_star, min_h);
    const T mu_star = sun_cos_zenith_at(f, f.eye_m + d * t_star);
    const T column_r = chapman_column_m(h_star, mu_star, f.planet_radius_m,
                                        T(1) / f.inv_rayleigh_scale_height, min_h);
    const T column_m = chapman_column_m(h_star, mu_star, f.planet_radius_m,
                                        T(1) / f.inv_mie_scale_height, min_h);
    Vec3<T> sun_r(0), sun_m(0);  // transmittance of the sunlight each component scatters
    if (column_r >= T(0) && column_m >= T(0)) {
        // Mean over scatterer i of density_j(h) / density_j(h_star), in log form (no overflow).
        const T a_r = rise * f.inv_rayleigh_scale_height;
        const T a_m = rise * f.inv_mie_scale_height;
        const T lr = detail::log_one_minus_exp_over_x(k_r);
        const T lm = detail::log_one_minus_exp_over_x(k_m);
        const T shift_r = (h_star - h0) * f.inv_rayleigh_scale_height;
        const T shift_m = (h_star - h0) * f.inv_mie_scale_height;
        auto ratio = [](T shift, T k_plus_a, T log_phi_k) {
            return std::exp(std::min(shift + detail::log_one_minus_exp_over_x(k_plus_a) - log_phi_k,
                                     T(80)));
        };
        const T r_rr = ratio(shift_r, k_r + a_r, lr), r_rm = ratio(shift_m, k_r + a_m, lr);
        const T r_mr = ratio(shift_r, k_m + a_r, lm), r_mm = ratio(shift_m, k_m + a_m, lm);
        sun_r = glm::exp(-(f.rayleigh_scattering * (column_r * r_rr) +
                           f.mie_extinction * (column_m * r_rm)));
        sun_m = glm::exp(-(f.rayleigh_scattering * (column_r * r_mr) +
                           f.mie_extinction * (column_m * r_mm)));
    }

    Scattering<T> out;
    for (int c = 0; c < 3; ++c) {
        const T beta_ex = f.rayleigh_scattering[c] * rho_r + f.mie_extinction[c] * rho_m;
        const T sunlit_scattering = f.rayleigh_scattering[c] * rho_r * phase_r * sun_r[c] +
                                    f.mie_scattering[c] * rho_m * phase_m * sun_m[c];
        const T tau = beta_ex * s;
        out.extinction[c] = std::exp(-tau);
        out.in_scattering[c] = sunlit_scattering * f.sun_irradiance_top[c] * s *
                               detail::one_minus_exp_over_x(tau);
    }
    out.sun_irradiance =
        f.sun_irradiance_top * sun_transmittance_chapman(f, h1, sun_cos_zenith_at(f, p_m));
    return out;
}

}  // namespace

template <class T>
Result<Frame<T>> prepare_frame(const Atmosphere& atmosphere, const View& view, Model model) {
    if (auto e = validate(atmosphere)) return *e;
    if (auto e = validate(view)) return *e;
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
    f.sun_irradiance_top = Vec3<T>(atmosphere.sun_irradiance);

    const double eye_altitude =
        altitude_above_sphere(eye_m, f.view.up, atmosphere.planet_radius_m);
    f.eye_altitude_m = std::max(T(eye_altitude), min_density_altitude(f));
    const glm::dvec3 eye_from_centre = eye_m + f.view.up * atmosphere.planet_radius_m;
    const double eye_cos_zenith =
        glm::dot(eye_from_centre, f.view.sun_dir) / glm::length(eye_from_centre);
    f.sun_irradiance_eye = Vec3<T>(atmosphere.sun_irradiance *
                                   sun_transmittance(atmosphere, eye_altitude, eye_cos_zenith));
    return f;
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
        case Model::height: return height_model(f, p_m);
        case Model::reference: {
            View view = f.view;
            view.meters_per_unit = 1.0;
            view.eye = view.eye * f.view.meters_per_unit;
            const Scattering<double> r =
                reference_scattering(f.atmosphere, view, glm::dvec3(p_m));
            return Scattering<T>{Vec3<T>(r.extinction), Vec3<T>(r.in_scattering),
                                 Vec3<T>(r.sun_irradiance)};
        }
    }
    return {};
}

Result<Scattering<double>> evaluate(const Atmosphere& atmosphere, const View& view, Model model,
                                    const glm::dvec3& vertex) {
    auto frame = prepare_frame<double>(atmosphere, view, model);
    if (!frame) return frame.error();
    if (!std::isfinite(vertex.x) || !std::isfinite(vertex.y) || !std::isfinite(vertex.z)) {
        return Error{"vertex", "vertex must be finite, got " + format_vector(vertex)};
    }
    return scatter(*frame, vertex);
}

#define AERIAL_INSTANTIATE(T)                                                                   \
    template T altitude_above_sphere<T>(const Vec3<T>&, const Vec3<T>&, T);                     \
    template Vec3<T> sun_transmittance_chapman<T>(const Frame<T>&, T, T);                       \
    template Scattering<T> hoffman_preetham_closed_form<T>(const Frame<T>&, T, T,               \
                                                           const Vec3<T>&);                     \
    template Result<Frame<T>> prepare_frame<T>(const Atmosphere&, const View&, Model);          \
    template Scattering<T> scatter<T>(const Frame<T>&, const Vec3<T>&);
AERIAL_INSTANTIATE(float)
AERIAL_INSTANTIATE(double)
#undef AERIAL_INSTANTIATE

}  // namespace aerial
