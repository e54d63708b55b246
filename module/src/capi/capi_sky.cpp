// The C interface (aerial/aerial.h), sky part: automatic exposure, dome colours for a dome the
// engine owns, cubemap faces and the sun sprite, over aerial/sky.hpp and aerial/sun.hpp. Each
// entry point runs inside capi::guard, so no exception leaves it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/aerial.h"
#include "aerial/batch.hpp"
#include "aerial/scattering.hpp"
#include "aerial/sky.hpp"
#include "aerial/sun.hpp"
#include "capi_internal.hpp"

struct aerial_sky {
    aerial_sky_method method = AERIAL_SKY_AUTOMATIC;
    int segments = 12;
    std::optional<aerial::SkyContext> context;
    glm::dvec3 eye{0.0};  ///< the view's eye in engine units (the dome's default centre)
    /// The 2002 dome's fit, kept while the atmosphere holds and the eye stays within
    /// kVirtualDomeRefitAltitudeM of the altitude it was fitted at.
    std::optional<aerial::VirtualDome> fit;
    aerial::Atmosphere fit_atmosphere;
    double fit_altitude_m = 0;
    /// The cubemap: its cache and what the last call encoded.
    std::optional<aerial::SkyCubemapCache> cubemap;
    int cubemap_size = 0;
    bool encoded = false;  ///< the caller has texels of this cubemap
    aerial::ColourFormat encoded_format = aerial::ColourFormat::rgba8;
    std::string last_error;
};

namespace aerial::capi {
namespace {

constexpr EnumValue<aerial_sky_method> kSkyMethods[] = {
    {AERIAL_SKY_AUTOMATIC, AERIAL_SKY_AUTOMATIC},
    {AERIAL_SKY_DOME_HP, AERIAL_SKY_DOME_HP},
    {AERIAL_SKY_DOME_HP_SINGLE, AERIAL_SKY_DOME_HP_SINGLE},
    {AERIAL_SKY_DOME_HEIGHT, AERIAL_SKY_DOME_HEIGHT},
    {AERIAL_SKY_HEIGHT_CHAINED, AERIAL_SKY_HEIGHT_CHAINED},
    {AERIAL_SKY_REFERENCE, AERIAL_SKY_REFERENCE}};

/// The method a sky uses for the dome and the radiance (AUTOMATIC: aerial::scene's dome for the
/// context's model).
SkyMethod dome_method(aerial_sky_method method, Model model) {
    switch (method) {
        case AERIAL_SKY_DOME_HP:
            return SkyMethod::dome_hp;
        case AERIAL_SKY_DOME_HP_SINGLE:
            return SkyMethod::dome_hp_single;
        case AERIAL_SKY_DOME_HEIGHT:
            return SkyMethod::dome_height;
        case AERIAL_SKY_HEIGHT_CHAINED:
            return SkyMethod::height_chained;
        case AERIAL_SKY_REFERENCE:
            return SkyMethod::reference;
        default:
            break;
    }
    return model == Model::hoffman_preetham ? SkyMethod::dome_hp : SkyMethod::dome_height;
}

/// The cubemap's method: AUTOMATIC is height-chained, as aerial::scene's cubemap sky.
SkyMethod cubemap_method(aerial_sky_method method, Model model) {
    return method == AERIAL_SKY_AUTOMATIC ? SkyMethod::height_chained : dome_method(method, model);
}

const SkyContext& prepared(const aerial_sky& sky) {
    if (!sky.context) {
        fail(AERIAL_ERROR_NO_VIEW, "sky", "expected aerial_sky_set_frame first, got no frame");
    }
    return *sky.context;
}

/// Fits the 2002 dome again when the atmosphere changed or the eye moved beyond the bound.
const VirtualDome& current_fit(aerial_sky& sky, const Atmosphere& atmosphere, double altitude) {
    if (!sky.fit || !(atmosphere == sky.fit_atmosphere) ||
        std::abs(altitude - sky.fit_altitude_m) > kVirtualDomeRefitAltitudeM) {
        sky.fit = value_or_fail(fit_virtual_dome(atmosphere, altitude), AERIAL_ERROR_INTERNAL);
        sky.fit_atmosphere = atmosphere;
        sky.fit_altitude_m = altitude;
    }
    return *sky.fit;
}

/// The direction a dome vertex shows: below the horizon, the horizon in its azimuth; zero for a
/// vertex at the centre, straight below it or not finite.
glm::dvec3 dome_direction(const glm::dvec3& offset, const glm::dvec3& up) {
    const double length = glm::length(offset);
    if (!(length > 0.0) || !std::isfinite(length)) return glm::dvec3(0.0);
    glm::dvec3 d = offset / length;
    const double rise = glm::dot(d, up);
    if (rise >= 0.0) return d;
    const glm::dvec3 horizontal = d - rise * up;
    const double h = glm::length(horizontal);
    return h > 1e-9 ? horizontal / h : glm::dvec3(0.0);
}

void store_sky_colour(const aerial_sky_colours& out, std::size_t v, const glm::dvec3& radiance,
                      const Display& display, ColourFormat format) {
    if (out.rgba8) {
        const std::size_t stride = out.rgba8_stride ? out.rgba8_stride : 4;
        store_colour(out.rgba8 + v * stride, format,
                     to_unorm8(display_value(display, float(radiance.x))),
                     to_unorm8(display_value(display, float(radiance.y))),
                     to_unorm8(display_value(display, float(radiance.z))), 255);
    }
    if (out.rgb) {
        const std::size_t stride = out.rgb_stride ? out.rgb_stride : 12;
        float* rgb =
            reinterpret_cast<float*>(reinterpret_cast<unsigned char*>(out.rgb) + v * stride);
        rgb[0] = float(radiance.x), rgb[1] = float(radiance.y), rgb[2] = float(radiance.z);
    }
}

void check_sky_colours(const aerial_sky_colours& out) {
    if (!out.rgba8 && !out.rgb) {
        fail(AERIAL_ERROR_INVALID_BATCH, "out", "expected rgba8 or rgb set, got neither");
    }
    if (out.rgba8_stride != 0 && out.rgba8_stride < 4) {
        fail(AERIAL_ERROR_INVALID_BATCH, "out.rgba8_stride",
             "expected 0 (packed) or >= 4 bytes, got " + detail::number(out.rgba8_stride));
    }
    if (out.rgb_stride != 0 && out.rgb_stride < 12) {
        fail(AERIAL_ERROR_INVALID_BATCH, "out.rgb_stride",
             "expected 0 (packed) or >= 12 bytes, got " + detail::number(out.rgb_stride));
    }
}

/// The world positions of the dome's vertices (the model matrix applied), in engine units.
std::vector<glm::dvec3> world_positions(const aerial_positions& vertices) {
    const Positions p = to_cpp_positions(vertices);
    if (p.count > 0 && (!p.x || !p.y || !p.z)) {
        fail(AERIAL_ERROR_INVALID_BATCH, "vertices",
             "expected arrays for " + detail::number(p.count) + " vertices, got NULL");
    }
    const float* m = p.model_matrix;
    std::vector<glm::dvec3> world(p.count);
    for (std::size_t i = 0; i < p.count; ++i) {
        const auto at = [&](const float* a) {
            return double(*reinterpret_cast<const float*>(
                reinterpret_cast<const unsigned char*>(a) + i * p.stride_bytes));
        };
        const glm::dvec3 v(at(p.x), at(p.y), at(p.z));
        world[i] = m ? glm::dvec3(m[0] * v.x + m[4] * v.y + m[8] * v.z + m[12],
                                  m[1] * v.x + m[5] * v.y + m[9] * v.z + m[13],
                                  m[2] * v.x + m[6] * v.y + m[10] * v.z + m[14])
                     : v;
    }
    return world;
}

Display display_of(const aerial_display* display) {
    const Display d = to_cpp(display);
    if (!std::isfinite(d.exposure) || d.exposure <= 0.0f) {
        fail(AERIAL_ERROR_INVALID_ARGUMENT, "display.exposure",
             "expected a finite value > 0 (0 means 1), got " + detail::number(d.exposure));
    }
    return d;
}

/// Sky rays of the exposure's skylight: as the sample game (8 elevations x 16 azimuths).
constexpr int kExposureElevationSteps = 8;
constexpr int kExposureAzimuthSteps = 16;

}  // namespace

ExposureOptions exposure_options(const aerial_exposure_options* o) {
    ExposureOptions e;
    if (!o) return e;
    if (o->albedo != 0.0) e.albedo = o->albedo;
    if (o->key != 0.0) e.key = o->key;
    if (o->min_gain != 0.0) e.min_gain = o->min_gain;
    if (o->max_gain != 0.0) e.max_gain = o->max_gain;
    const struct {
        const char* field;
        double value;
        bool ok;
    } checks[] = {{"albedo", e.albedo, e.albedo > 0.0 && e.albedo <= 1.0},
                  {"key", e.key, e.key > 0.0 && std::isfinite(e.key)},
                  {"min_gain", e.min_gain, e.min_gain > 0.0 && std::isfinite(e.min_gain)},
                  {"max_gain", e.max_gain, e.max_gain >= e.min_gain && std::isfinite(e.max_gain)}};
    for (const auto& c : checks) {
        if (!c.ok) {
            fail(AERIAL_ERROR_INVALID_ARGUMENT, c.field,
                 std::string("expected ") +
                     (c.field == std::string("albedo")     ? "a value in (0, 1]"
                      : c.field == std::string("max_gain") ? "a finite value >= min_gain"
                                                           : "a finite value > 0") +
                     ", got " + detail::number(c.value));
        }
    }
    return e;
}

}  // namespace aerial::capi

using namespace aerial;  // NOLINT(google-build-using-namespace): this file implements the C API
using capi::guard;
using capi::require;

extern "C" {

aerial_status aerial_auto_exposure(const aerial_context* context,
                                   const aerial_exposure_options* options, float* exposure) {
    return guard("aerial_auto_exposure", capi::last_error_of(context), [&] {
        require(context, "context");
        require(exposure, "exposure");
        const Frame<float>& frame = capi::current_frame(*context);
        const ExposureOptions e = capi::exposure_options(options);
        if (options && options->use_card_altitude && !std::isfinite(options->card_altitude_m)) {
            capi::fail(
                AERIAL_ERROR_INVALID_ARGUMENT, "card_altitude_m",
                "expected a finite altitude, got " + detail::number(options->card_altitude_m));
        }
        const double altitude = options && options->use_card_altitude
                                    ? options->card_altitude_m
                                    : double(frame.eye_altitude_m);
        const double elevation = std::asin(
            std::clamp(glm::dot(glm::dvec3(frame.sun_dir), context->view->up), -1.0, 1.0));
        const glm::dvec3 sun = sun_irradiance_at_altitude(context->atmosphere, altitude, elevation);
        SkyAmbientOptions ambient;
        ambient.elevation_steps = capi::kExposureElevationSteps;
        ambient.azimuth_steps = capi::kExposureAzimuthSteps;
        const glm::dvec3 sky = capi::value_or_fail(
            sky_ambient(context->atmosphere, altitude, elevation, ambient), AERIAL_ERROR_INTERNAL);
        *exposure =
            float(auto_exposure(sun, elevation, sky, context->atmosphere.sun_irradiance, e));
    });
}

aerial_status aerial_sky_create(const aerial_sky_options* options, aerial_sky** out) {
    return guard("aerial_sky_create", nullptr, [&] {
        require(out, "out");
        *out = nullptr;
        auto sky = std::make_unique<aerial_sky>();
        if (options) {
            sky->method =
                capi::to_cpp_enum(capi::c_enum_value(options->method), capi::kSkyMethods, "method",
                                  "AERIAL_SKY_AUTOMATIC (0) .. AERIAL_SKY_REFERENCE (5)");
            if (options->segments < 0) {
                capi::fail(AERIAL_ERROR_INVALID_ARGUMENT, "segments",
                           "expected >= 1 (0 means 12), got " + detail::number(options->segments));
            }
            if (options->segments > 0) sky->segments = options->segments;
        }
        *out = sky.release();
    });
}

void aerial_sky_destroy(aerial_sky* sky) { delete sky; }

const char* aerial_sky_last_error(const aerial_sky* sky) {
    return sky ? sky->last_error.c_str() : "";
}

aerial_status aerial_sky_set_frame(aerial_sky* sky, const aerial_context* context) {
    return guard("aerial_sky_set_frame", capi::last_error_of(sky), [&] {
        require(sky, "sky");
        require(context, "context");
        const Frame<float>& frame = capi::current_frame(*context);
        const SkyMethod method = capi::dome_method(sky->method, context->model);
        SkyOptions options;
        options.segments = sky->segments;
        if (method == SkyMethod::dome_hp || method == SkyMethod::dome_hp_single) {
            options.dome = &capi::current_fit(*sky, context->atmosphere, frame.eye_altitude_m);
        }
        sky->eye = context->view->eye;
        sky->context =
            capi::value_or_fail(prepare_sky(context->atmosphere, *context->view, method, options),
                                AERIAL_ERROR_INVALID_VIEW);
    });
}

aerial_status aerial_sky_radiance(const aerial_sky* sky, const double direction[3], float rgb[3]) {
    return guard("aerial_sky_radiance", capi::last_error_of(sky), [&] {
        require(sky, "sky");
        require(direction, "direction");
        require(rgb, "rgb");
        const glm::dvec3 d(direction[0], direction[1], direction[2]);
        const double length = glm::length(d);
        if (!(length > 0.0) || !std::isfinite(length)) {
            capi::fail(AERIAL_ERROR_INVALID_ARGUMENT, "direction",
                       "expected a finite non-zero vector, got " + detail::vector(d));
        }
        const glm::dvec3 l = sky_radiance(capi::prepared(*sky), d);
        rgb[0] = float(l.x), rgb[1] = float(l.y), rgb[2] = float(l.z);
    });
}

aerial_status aerial_sky_shade_dome(const aerial_sky* sky, const aerial_positions* vertices,
                                    const double centre[3], const aerial_display* display,
                                    const aerial_sky_colours* out) {
    return guard("aerial_sky_shade_dome", capi::last_error_of(sky), [&] {
        require(sky, "sky");
        require(vertices, "vertices");
        require(out, "out");
        const SkyContext& context = capi::prepared(*sky);
        capi::check_sky_colours(*out);
        const ColourFormat format =
            capi::to_cpp_format(capi::c_enum_value(out->format), "out.format");
        const Display d = capi::display_of(display);
        const glm::dvec3 c = centre ? glm::dvec3(centre[0], centre[1], centre[2]) : sky->eye;
        const std::vector<glm::dvec3> world = capi::world_positions(*vertices);
        for (std::size_t v = 0; v < world.size(); ++v) {
            const glm::dvec3 dir = capi::dome_direction(world[v] - c, context.view.up);
            const glm::dvec3 l = dir == glm::dvec3(0.0) ? dir : sky_radiance(context, dir);
            capi::store_sky_colour(*out, v, l, d, format);
        }
    });
}

aerial_status aerial_sky_cubemap(aerial_sky* sky, int size, aerial_colour_format format,
                                 const aerial_display* display, unsigned char* faces,
                                 size_t capacity_bytes, int* changed) {
    return guard("aerial_sky_cubemap", capi::last_error_of(sky), [&] {
        require(sky, "sky");
        require(faces, "faces");
        const SkyContext& context = capi::prepared(*sky);
        if (size < 1 || size > 4096) {
            capi::fail(AERIAL_ERROR_INVALID_ARGUMENT, "size",
                       "expected 1 .. 4096 texels, got " + detail::number(size));
        }
        const ColourFormat f = capi::to_cpp_format(capi::c_enum_value(format), "format");
        const std::size_t face_bytes = std::size_t(size) * std::size_t(size) * 4;
        if (capacity_bytes < 6 * face_bytes) {
            capi::fail(AERIAL_ERROR_BUFFER_TOO_SMALL, "capacity_bytes",
                       "expected >= " + detail::number(6 * face_bytes) + " (6 x " +
                           detail::number(size) + "^2 x 4), got " + detail::number(capacity_bytes));
        }
        const Display d = capi::display_of(display);
        if (!sky->cubemap || sky->cubemap_size != size) {
            SkyCubemapCache::Options options;
            options.size = size;
            options.method = capi::cubemap_method(sky->method, context.frame.model);
            sky->cubemap.emplace(options);
            sky->cubemap_size = size;
            sky->encoded = false;
        }
        const bool recoded = capi::value_or_fail(
            sky->cubemap->update(context.atmosphere, context.view, d), AERIAL_ERROR_INVALID_VIEW);
        const bool fresh = recoded || sky->encoded_format != f || !sky->encoded;
        const auto& texels = sky->cubemap->rgba8();
        for (int face = 0; face < 6; ++face) {
            const std::vector<std::uint8_t>& t = texels[std::size_t(face)];
            unsigned char* dst = faces + std::size_t(face) * face_bytes;
            for (std::size_t i = 0; i < face_bytes; i += 4)
                store_colour(dst + i, f, t[i], t[i + 1], t[i + 2], t[i + 3]);
        }
        sky->encoded = true;
        sky->encoded_format = f;
        if (changed) *changed = fresh ? 1 : 0;
    });
}

aerial_status aerial_sky_sun_sprite(const aerial_sky* sky, const aerial_sun_sprite_options* options,
                                    const aerial_display* display, aerial_colour_format format,
                                    unsigned char* rgba, size_t capacity_bytes,
                                    aerial_sun_sprite_info* info) {
    return guard("aerial_sky_sun_sprite", capi::last_error_of(sky), [&] {
        require(sky, "sky");
        require(info, "info");
        const SkyContext& context = capi::prepared(*sky);
        const ColourFormat f = capi::to_cpp_format(capi::c_enum_value(format), "format");
        const Display d = capi::display_of(display);
        SunSpriteOptions o;
        o.size = 64;
        if (options) {
            if (options->size != 0) o.size = options->size;
            if (options->half_width_rad != 0.0) o.half_width_rad = options->half_width_rad;
            if (options->sun_radius_rad != 0.0) o.sun_radius_rad = options->sun_radius_rad;
            if (options->halo_g != 0.0) o.halo_g = options->halo_g;
            if (options->disc_supersampling != 0)
                o.disc_supersampling = options->disc_supersampling;
        }
        const std::size_t bytes =
            std::size_t(std::max(o.size, 0)) * std::size_t(std::max(o.size, 0)) * 4;
        if (rgba && capacity_bytes < bytes) {
            capi::fail(AERIAL_ERROR_BUFFER_TOO_SMALL, "capacity_bytes",
                       "expected >= " + detail::number(bytes) + " (" + detail::number(o.size) +
                           "^2 x 4), got " + detail::number(capacity_bytes));
        }
        const SunSprite sprite = capi::value_or_fail(
            make_sun_sprite(context, d.exposure, d.tone, o), AERIAL_ERROR_INVALID_ARGUMENT);
        if (rgba) {
            for (std::size_t i = 0; i < sprite.rgba.size(); i += 4) {
                store_colour(rgba + i, f, sprite.rgba[i], sprite.rgba[i + 1], sprite.rgba[i + 2],
                             sprite.rgba[i + 3]);
            }
        }
        info->size = sprite.size;
        info->half_width_rad = sprite.half_width_rad;
        const glm::dvec3 sun = context.view.sun_dir;
        info->direction[0] = sun.x, info->direction[1] = sun.y, info->direction[2] = sun.z;
        const glm::dvec3 e = context.frame.sun_irradiance_eye;
        const glm::dvec3 top = context.atmosphere.sun_irradiance;
        for (int c = 0; c < 3; ++c)
            info->transmittance[c] =
                top[c] > 0.0 ? float(std::clamp(e[c] / top[c], 0.0, 1.0)) : 0.0f;
    });
}

}  // extern "C"
