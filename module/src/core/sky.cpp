// The sky: methods along a view ray, the virtual sky dome of the 2002 talk, the per-vertex dome,
// the CPU cubemap and its cache, and the sun sprite (the measurements against `reference` are
// aerial::validation's, validation/src/sky_measure.cpp).
#include "aerial/sky.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "aerial/phase.hpp"
#include "sky_internal.hpp"
#include "sky_view_table.hpp"

namespace aerial {
namespace {

using detail::invalid;
using detail::number;
using glm::dvec3;

/// Distance along a ray from `origin` (frame centred on the planet) in unit direction `dir` to a
/// sphere of radius r around the centre, the far root; negative when it misses.
double exit_distance(const dvec3& origin, const dvec3& dir, double r) {
    const double b = glm::dot(origin, dir);
    const double c = glm::dot(origin, origin) - r * r;
    const double disc = b * b - c;
    if (disc < 0) return -1;
    return -b + std::sqrt(disc);
}

/// Distance to the ground (sphere of the planet radius) along the ray, or -1 when the ray does
/// not hit it in front of the origin.
double ground_distance(const dvec3& origin, const dvec3& dir, double r) {
    const double b = glm::dot(origin, dir);
    const double c = glm::dot(origin, origin) - r * r;
    const double disc = b * b - c;
    if (disc < 0 || b >= 0) return -1;
    const double t = -b - std::sqrt(disc);
    return t > 0 ? t : -1;
}

/// Ray length from an eye at altitude h (planet-centred frame along +z) for a direction of
/// elevation `elevation_rad`: to the atmosphere top, or to the ground below the horizon.
double ray_length(const Atmosphere& a, double eye_altitude_m, const dvec3& dir_local) {
    const dvec3 origin(0.0, 0.0, a.planet_radius_m + std::max(eye_altitude_m, 0.0));
    const double ground = ground_distance(origin, dir_local, a.planet_radius_m);
    if (ground > 0) return ground;
    return std::max(exit_distance(origin, dir_local, a.atmosphere_radius_m), 0.0);
}

/// The table variable of the virtual dome: u = sign(e) sqrt(|e| / (pi/2)) in [-1, 1], dense near
/// the horizon where the optical depth changes fastest.
double dome_u(double elevation_rad) {
    const double e = std::clamp(elevation_rad / (kPi / 2), -1.0, 1.0);
    return e < 0 ? -std::sqrt(-e) : std::sqrt(e);
}
double dome_elevation(double u) { return (u < 0 ? -u * u : u * u) * (kPi / 2); }

/// SkyOptions::dome, when given: a fitted table (radius_at needs two entries) of finite radii.
std::optional<Error> check_given_dome(const VirtualDome* dome) {
    if (!dome) return std::nullopt;
    if (dome->radius_m.size() < 2) {
        return invalid("prepare_sky", "dome",
                       "a fitted virtual dome of >= 2 radii (fit_virtual_dome, or null to fit "
                       "here)",
                       number(dome->radius_m.size()) + " radii");
    }
    for (double r : dome->radius_m) {
        if (!std::isfinite(r) || r < 0)
            return invalid("prepare_sky", "dome", "finite radii >= 0", number(r));
    }
    return std::nullopt;
}

using detail::display_8bit;
using detail::elevation_of;
using detail::quantised;

}  // namespace

constexpr detail::NameTable<SkyMethod, 5> kSkyMethodNames{
    {{SkyMethod::dome_hp, "dome-hp"},
     {SkyMethod::dome_hp_single, "dome-hp-single"},
     {SkyMethod::dome_height, "dome-height"},
     {SkyMethod::height_chained, "height-chained"},
     {SkyMethod::reference, "reference"}}};

std::string_view sky_method_name(SkyMethod method) {
    return detail::name_in(kSkyMethodNames, method);
}

const std::vector<SkyMethod>& all_sky_methods() {
    static const std::vector<SkyMethod> methods = [] {
        std::vector<SkyMethod> all;
        for (const auto& entry : kSkyMethodNames) all.push_back(entry.value);
        return all;
    }();
    return methods;
}

Result<SkyMethod> parse_sky_method(std::string_view name) {
    return detail::parse_in("parse_sky_method", kSkyMethodNames, "sky_method", name);
}

double VirtualDome::radius_at(double elevation_rad) const {
    if (radius_m.size() < 2) return 0.0;  // not fitted
    const double n = double(radius_m.size() - 1);
    const double x = (dome_u(elevation_rad) + 1.0) * 0.5 * n;
    const std::size_t i = std::min(std::size_t(std::max(x, 0.0)), radius_m.size() - 2);
    const double f = x - double(i);
    return radius_m[i] * (1.0 - f) + radius_m[i + 1] * f;
}

Result<VirtualDome> fit_virtual_dome(const Atmosphere& atmosphere, double eye_altitude_m,
                                     int samples) {
    constexpr const char* kFunction = "fit_virtual_dome";
    if (auto e = validate(atmosphere)) return detail::from(kFunction, *e);
    if (samples < 3) return invalid(kFunction, "samples", ">= 3", number(samples));
    if (!std::isfinite(eye_altitude_m))
        return invalid(kFunction, "eye_altitude_m", "a finite value", number(eye_altitude_m));
    View view;
    view.eye = {0.0, 0.0, eye_altitude_m};
    ReferenceOptions no_sun;
    no_sun.sun_attenuation = false;
    // G channel: the one the 2002 dome's extinction is matched in (the eye is most sensitive
    // there).
    const double sea_level_extinction = atmosphere.extinction().y;
    VirtualDome dome;
    dome.radius_m.resize(std::size_t(samples));
    for (int i = 0; i < samples; ++i) {
        const double e = dome_elevation(-1.0 + 2.0 * i / (samples - 1));
        const dvec3 dir(std::cos(e), 0.0, std::sin(e));
        const double length = ray_length(atmosphere, eye_altitude_m, dir);
        const Scattering<double> s =
            reference_scattering(atmosphere, view, view.eye + dir * length, no_sun);
        const double tau = -std::log(std::max(s.extinction.y, 1e-300));
        dome.radius_m[std::size_t(i)] =
            sea_level_extinction > 0 ? tau / sea_level_extinction : length;
    }
    return dome;
}

Result<SkyContext> prepare_sky(const Atmosphere& atmosphere, const View& view, SkyMethod method,
                               const SkyOptions& options) {
    constexpr const char* kFunction = "prepare_sky";
    if (options.segments < 1)
        return invalid(kFunction, "segments", ">= 1", number(options.segments));
    if (auto e = check_given_dome(options.dome)) return *e;
    View metres = view;
    metres.eye = view.eye * view.meters_per_unit;
    metres.meters_per_unit = 1.0;
    const bool hp = method == SkyMethod::dome_hp || method == SkyMethod::dome_hp_single;
    auto frame =
        prepare_frame<double>(atmosphere, metres, hp ? Model::hoffman_preetham : Model::height);
    if (!frame) return detail::from(kFunction, frame.error());
    SkyContext sky;
    sky.method = method;
    sky.atmosphere = atmosphere;
    sky.view = frame->view;
    sky.eye_m = metres.eye;
    sky.eye_altitude_m = altitude_above_sphere(metres.eye, sky.view.up, atmosphere.planet_radius_m);
    sky.frame = *frame;
    sky.segments = options.segments;
    if (hp) {
        if (options.dome) {
            sky.dome = *options.dome;
        } else {
            auto dome = fit_virtual_dome(atmosphere, sky.eye_altitude_m);
            if (!dome) return detail::from(kFunction, dome.error());
            sky.dome = std::move(dome).value();
        }
        // Mean over the upper hemisphere, uniform in solid angle (uniform in sin(elevation)).
        constexpr int kSteps = 256;
        double sum = 0;
        for (int i = 0; i < kSteps; ++i) sum += sky.dome.radius_at(std::asin((i + 0.5) / kSteps));
        sky.single_radius_m = sum / kSteps;
    }
    return sky;
}

double sky_ray_length_m(const SkyContext& sky, const dvec3& direction) {
    const double e = elevation_of(sky, direction);
    return ray_length(sky.atmosphere, sky.eye_altitude_m, dvec3(std::cos(e), 0.0, std::sin(e)));
}

glm::dvec3 sky_radiance(const SkyContext& sky, const dvec3& direction) {
    const double len = glm::length(direction);
    if (!(len > 0) || !std::isfinite(len)) return dvec3(0.0);
    const dvec3 dir = direction / len;
    const double cos_theta = glm::dot(dir, sky.view.sun_dir);
    switch (sky.method) {
        case SkyMethod::dome_hp:
        case SkyMethod::dome_hp_single: {
            const double s = sky.method == SkyMethod::dome_hp
                                 ? sky.dome.radius_at(elevation_of(sky, dir))
                                 : sky.single_radius_m;
            return hoffman_preetham_closed_form(sky.frame, s, cos_theta,
                                                sky.frame.sun_irradiance_eye)
                .in_scattering;
        }
        case SkyMethod::dome_height:
            return scatter(sky.frame, sky.eye_m + dir * sky_ray_length_m(sky, dir)).in_scattering;
        case SkyMethod::height_chained:
            // The chain of `height` segments (sky_view_table.cpp), its parts under this
            // direction's phases.
            return detail::sky_radiance_parts(sky, dir).in_scattering(
                rayleigh_phase(cos_theta), henyey_greenstein_phase(cos_theta, sky.frame.mie_g));
        case SkyMethod::reference: {
            View view = sky.view;
            view.eye = sky.eye_m;
            view.meters_per_unit = 1.0;
            ReferenceOptions options;
            options.multiple_scattering = true;  // the `reference` model, every order
            return reference_scattering(sky.atmosphere, view,
                                        sky.eye_m + dir * sky_ray_length_m(sky, dir), options)
                .in_scattering;
        }
    }
    return dvec3(0.0);
}

// ---- Dome ------------------------------------------------------------------------------------

Result<SkyDomeMesh> make_sky_dome_mesh(int rings, int segments, const dvec3& up) {
    constexpr const char* kFunction = "make_sky_dome_mesh";
    if (rings < 1) return invalid(kFunction, "rings", ">= 1", number(rings));
    if (segments < 3) return invalid(kFunction, "segments", ">= 3", number(segments));
    if (!std::isfinite(up.x) || !std::isfinite(up.y) || !std::isfinite(up.z) ||
        std::abs(glm::length(up) - 1.0) > 1e-3) {
        return invalid(kFunction, "up", "a unit vector", detail::vector(up));
    }
    const dvec3 u = glm::normalize(up);
    // Two horizontal axes: any vector not parallel to up, made orthogonal.
    const dvec3 helper = std::abs(u.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    const dvec3 east = glm::normalize(helper - u * glm::dot(helper, u));
    const dvec3 north = glm::cross(u, east);
    SkyDomeMesh m;
    m.rings = rings;
    m.segments = segments;
    for (int r = 0; r < rings; ++r) {
        const double e = (kPi / 2) * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double a = 2 * kPi * s / segments;
            m.directions.push_back(std::cos(e) * (std::cos(a) * east + std::sin(a) * north) +
                                   std::sin(e) * u);
        }
    }
    m.directions.push_back(u);
    const auto at = [&](int r, int s) { return std::uint32_t(r * segments + (s % segments)); };
    for (int r = 0; r + 1 < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            m.indices.insert(m.indices.end(), {at(r, s), at(r + 1, s + 1), at(r, s + 1)});
            m.indices.insert(m.indices.end(), {at(r, s), at(r + 1, s), at(r + 1, s + 1)});
        }
    }
    const auto zenith = std::uint32_t(m.directions.size() - 1);
    for (int s = 0; s < segments; ++s) {
        m.indices.insert(m.indices.end(), {at(rings - 1, s), zenith, at(rings - 1, s + 1)});
    }
    return m;
}

std::vector<glm::dvec3> shade_sky_dome(const SkyContext& sky, const SkyDomeMesh& mesh) {
    std::vector<glm::dvec3> out;
    out.reserve(mesh.directions.size());
    for (const dvec3& d : mesh.directions) out.push_back(sky_radiance(sky, d));
    return out;
}

// ---- Cubemap ---------------------------------------------------------------------------------

glm::dvec3 cubemap_texel_direction(int face, int i, int j, int size) {
    const double sc = 2.0 * (i + 0.5) / size - 1.0;
    const double tc = 2.0 * (j + 0.5) / size - 1.0;
    dvec3 d;
    switch (face) {  // the GL spec's table: (sc, tc) per major axis
        case 0:
            d = {1.0, -tc, -sc};
            break;
        case 1:
            d = {-1.0, -tc, sc};
            break;
        case 2:
            d = {sc, 1.0, tc};
            break;
        case 3:
            d = {sc, -1.0, -tc};
            break;
        case 4:
            d = {sc, -tc, 1.0};
            break;
        default:
            d = {-sc, -tc, -1.0};
            break;
    }
    return glm::normalize(d);
}

Result<SkyCubemap> compute_sky_cubemap(const SkyContext& sky, int size) {
    if (size < 1 || size > 4096) {
        return invalid("compute_sky_cubemap", "size", "1 .. 4096", number(size));
    }
    detail::SkyViewTable table(sky);
    table.compute_rows(0, detail::SkyViewTable::kRows);
    return detail::cubemap_from_table(table, size);
}

std::array<std::vector<std::uint8_t>, 6> cubemap_to_rgba8(const SkyCubemap& cubemap,
                                                          double exposure, ToneCurve curve) {
    std::array<std::vector<std::uint8_t>, 6> out;
    for (std::size_t f = 0; f < 6; ++f) {
        out[f].reserve(cubemap.faces[f].size() * 4);
        for (const glm::vec3& l : cubemap.faces[f]) {
            const dvec3 v = quantised(display_8bit(dvec3(l), exposure, curve));
            out[f].insert(out[f].end(), {std::uint8_t(v.x), std::uint8_t(v.y), std::uint8_t(v.z),
                                         std::uint8_t(255)});
        }
    }
    return out;
}

glm::dvec3 sample_cubemap_rgba8(const std::array<std::vector<std::uint8_t>, 6>& faces, int size,
                                const dvec3& d) {
    const dvec3 a = glm::abs(d);
    int face;
    double ma, sc, tc;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0 ? 0 : 1;
        ma = a.x;
        sc = d.x >= 0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y >= 0 ? 2 : 3;
        ma = a.y;
        sc = d.x;
        tc = d.y >= 0 ? d.z : -d.z;
    } else {
        face = d.z >= 0 ? 4 : 5;
        ma = a.z;
        sc = d.z >= 0 ? d.x : -d.x;
        tc = -d.y;
    }
    if (!(ma > 0)) return dvec3(0.0);
    const double s = 0.5 * (sc / ma + 1.0) * size - 0.5;
    const double t = 0.5 * (tc / ma + 1.0) * size - 0.5;
    const double fs = std::floor(s), ft = std::floor(t);
    const double ws = s - fs, wt = t - ft;
    const auto& texels = faces[std::size_t(face)];
    auto texel = [&](int i, int j) {
        i = std::clamp(i, 0, size - 1);
        j = std::clamp(j, 0, size - 1);
        const std::size_t k = (std::size_t(j) * std::size_t(size) + std::size_t(i)) * 4;
        return dvec3(texels[k], texels[k + 1], texels[k + 2]);
    };
    const int i0 = int(fs), j0 = int(ft);
    return (texel(i0, j0) * (1 - ws) + texel(i0 + 1, j0) * ws) * (1 - wt) +
           (texel(i0, j0 + 1) * (1 - ws) + texel(i0 + 1, j0 + 1) * ws) * wt;
}

// ---- Sun sprite ------------------------------------------------------------------------------

namespace {

/// What a sun sprite's texels take from its geometry alone, over the texel's subsamples: the
/// mean halo phase max(0, P_HG(theta, halo_g) - P_HG(theta, g)) and the share of the disc.
struct SpriteGeometry {
    SunSpriteOptions options;
    double mie_g = 0;
    std::vector<double> halo, disc;  ///< by texel, row j = 0 first
};

SpriteGeometry compute_sprite_geometry(const SunSpriteOptions& o, double mie_g) {
    SpriteGeometry g{o, mie_g, {}, {}};
    const double tan_half = std::tan(o.half_width_rad);
    const double cos_radius = std::cos(o.sun_radius_rad);
    const int ss = o.disc_supersampling;
    for (int j = 0; j < o.size; ++j) {
        for (int i = 0; i < o.size; ++i) {
            // The sprite is a square on the plane one unit towards the sun: texel (i, j) looks
            // along (1, x, y) in the sprite's frame.
            double halo = 0, cover = 0;
            for (int sj = 0; sj < ss; ++sj) {
                for (int si = 0; si < ss; ++si) {
                    const double x = (2.0 * (i + (si + 0.5) / ss) / o.size - 1.0) * tan_half;
                    const double y = (2.0 * (j + (sj + 0.5) / ss) / o.size - 1.0) * tan_half;
                    const double cos_theta = 1.0 / std::sqrt(1.0 + x * x + y * y);
                    if (cos_theta >= cos_radius) cover += 1.0;
                    halo += std::max(henyey_greenstein_phase(cos_theta, o.halo_g) -
                                         henyey_greenstein_phase(cos_theta, mie_g),
                                     0.0);
                }
            }
            g.halo.push_back(halo / double(ss * ss));
            g.disc.push_back(cover / double(ss * ss));
        }
    }
    return g;
}

/// The geometry of the last few sprites (a renderer remakes its sprite as the sun moves, with
/// the same options).
std::shared_ptr<const SpriteGeometry> sprite_geometry(const SunSpriteOptions& o, double mie_g) {
    static std::mutex mutex;
    static std::vector<std::shared_ptr<const SpriteGeometry>> kept;  // most recent last
    const auto same = [&](const SpriteGeometry& g) {
        const SunSpriteOptions& k = g.options;
        return k.size == o.size && k.half_width_rad == o.half_width_rad &&
               k.sun_radius_rad == o.sun_radius_rad && k.halo_g == o.halo_g &&
               k.disc_supersampling == o.disc_supersampling && g.mie_g == mie_g;
    };
    {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& g : kept) {
            if (same(*g)) return g;
        }
    }
    auto g = std::make_shared<const SpriteGeometry>(compute_sprite_geometry(o, mie_g));
    std::lock_guard<std::mutex> lock(mutex);
    if (kept.size() == 4) kept.erase(kept.begin());
    kept.push_back(g);
    return g;
}

}  // namespace

Result<SunSprite> make_sun_sprite(const SkyContext& sky, double exposure, ToneCurve curve,
                                  const SunSpriteOptions& o) {
    constexpr const char* kFunction = "make_sun_sprite";
    if (o.size < 8 || o.size > 4096) return invalid(kFunction, "size", "8 .. 4096", number(o.size));
    if (!(o.half_width_rad > o.sun_radius_rad) || !(o.half_width_rad < kPi / 4)) {
        return invalid(kFunction, "half_width_rad", "a value in (sun_radius_rad, pi/4)",
                       number(o.half_width_rad));
    }
    if (!(o.sun_radius_rad > 0))
        return invalid(kFunction, "sun_radius_rad", "a value > 0", number(o.sun_radius_rad));
    if (!(o.halo_g >= 0.9 && o.halo_g < 1.0))
        return invalid(kFunction, "halo_g", "a value in [0.9, 1)", number(o.halo_g));
    if (o.disc_supersampling < 1) {
        return invalid(kFunction, "disc_supersampling", ">= 1", number(o.disc_supersampling));
    }
    if (!(exposure >= 0) || !std::isfinite(exposure))
        return invalid(kFunction, "exposure", "a finite value >= 0", number(exposure));
    const Atmosphere& a = sky.atmosphere;
    const dvec3 sun = sky.view.sun_dir;
    const double sun_elevation = elevation_of(sky, sun);
    // Sun at the eye (zero in the planet's shadow), and the Mie scattering column towards it.
    const dvec3 e_sun =
        a.sun_irradiance * sun_transmittance(a, sky.eye_altitude_m, std::sin(sun_elevation));
    Atmosphere mie_only = a;
    mie_only.rayleigh_scattering = dvec3(0.0);
    mie_only.mie_absorption = dvec3(0.0);
    View view = sky.view;
    view.eye = sky.eye_m;
    view.meters_per_unit = 1.0;
    ReferenceOptions no_sun;
    no_sun.sun_attenuation = false;
    const double length = ray_length(a, sky.eye_altitude_m,
                                     dvec3(std::cos(sun_elevation), 0.0, std::sin(sun_elevation)));
    const dvec3 tau_mie = -glm::log(
        glm::max(reference_scattering(mie_only, view, sky.eye_m + sun * length, no_sun).extinction,
                 dvec3(1e-300)));
    const double disc_solid_angle = 2 * kPi * (1 - std::cos(o.sun_radius_rad));
    const dvec3 disc_radiance = e_sun / disc_solid_angle;

    SunSprite sprite;
    sprite.size = o.size;
    sprite.half_width_rad = o.half_width_rad;
    sprite.rgba.resize(std::size_t(o.size) * std::size_t(o.size) * 4);
    const auto geometry = sprite_geometry(o, a.mie_g);
    for (std::size_t t = 0; t < geometry->halo.size(); ++t) {
        const dvec3 radiance =
            e_sun * tau_mie * geometry->halo[t] + disc_radiance * geometry->disc[t];
        const dvec3 v = quantised(display_8bit(radiance, exposure, curve));
        sprite.rgba[4 * t] = std::uint8_t(v.x);
        sprite.rgba[4 * t + 1] = std::uint8_t(v.y);
        sprite.rgba[4 * t + 2] = std::uint8_t(v.z);
        sprite.rgba[4 * t + 3] = std::uint8_t(std::max({v.x, v.y, v.z}));
    }
    return sprite;
}

}  // namespace aerial
