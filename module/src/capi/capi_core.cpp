// The C interface (aerial/aerial.h), core part: status strings, last errors, atmospheres, views,
// contexts, single-point evaluation and batch shading. Each entry point runs inside
// capi::guard, so no exception leaves it.
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/aerial.h"
#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/scattering.hpp"
#include "capi_internal.hpp"
#include "capi_testing.hpp"

namespace aerial::capi {
namespace {

struct ThreadError {
    std::string field;
    std::string message;
};

ThreadError& thread_error() {
    thread_local ThreadError error;
    return error;
}

thread_local InjectedException armed = InjectedException::none;

glm::dvec3 vec3(const double v[3]) { return {v[0], v[1], v[2]}; }
bool is_zero(const double v[3]) { return v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0; }
void copy(const glm::dvec3& from, double to[3]) {
    to[0] = from.x;
    to[1] = from.y;
    to[2] = from.z;
}
void copy(const glm::vec3& from, float to[3]) {
    to[0] = from.x;
    to[1] = from.y;
    to[2] = from.z;
}
/// A result of the C++ API into its C struct (aerial_scattering or aerial_scattering_d).
template <class Scattering, class CScattering>
void copy_scattering(const Scattering& from, CScattering& to) {
    copy(from.extinction, to.extinction);
    copy(from.in_scattering, to.in_scattering);
    copy(from.sun_irradiance, to.sun_irradiance);
}

/// A C-side vector field: the value given, the default when all 0, or 0 when asked for.
glm::dvec3 vector_field(const double v[3], unsigned zero_fields, unsigned bit,
                        const glm::dvec3& fallback) {
    if (zero_fields & bit) return glm::dvec3(0.0);
    return is_zero(v) ? fallback : vec3(v);
}
double scalar_field(double v, const double fallback) { return v == 0.0 ? fallback : v; }

}  // namespace

void fail(aerial_status status, std::string field, std::string text) {
    throw Failure{status, std::move(field), std::move(text)};
}

void fail(aerial_status status, const Error& error) {
    fail(status, error.field, std::string(detail::text_of(error)));
}

void fail_null(const char* name) {
    fail(AERIAL_ERROR_NULL_ARGUMENT, name, "expected a pointer, got NULL");
}

void require(const void* pointer, const char* name) {
    if (pointer == nullptr) fail_null(name);
}

void record(aerial_status status, const char* function, const std::string& field,
            const std::string& text, std::string* object_error) {
    ThreadError& error = thread_error();
    if (status == AERIAL_OK) {
        error.field.clear();
        error.message.clear();
    } else {
        error.field = field;
        error.message = detail::styled(function, field, text);
    }
    if (object_error != nullptr) *object_error = error.message;
}

void throw_if_armed() {
    const InjectedException kind = armed;
    armed = InjectedException::none;
    switch (kind) {
        case InjectedException::none:
            return;
        case InjectedException::bad_alloc:
            throw std::bad_alloc();
        case InjectedException::standard_exception:
            throw std::runtime_error("injected by the test hook");
        case InjectedException::unknown:
            throw 42;
    }
}

void inject_exception_in_next_call(InjectedException kind) { armed = kind; }

Atmosphere to_cpp(const aerial_atmosphere* c) {
    const Atmosphere d;
    if (c == nullptr) return d;
    Atmosphere a;
    const unsigned z = c->zero_fields;
    a.rayleigh_scattering = vector_field(c->rayleigh_scattering, z, AERIAL_ZERO_RAYLEIGH_SCATTERING,
                                         d.rayleigh_scattering);
    a.mie_scattering =
        vector_field(c->mie_scattering, z, AERIAL_ZERO_MIE_SCATTERING, d.mie_scattering);
    a.mie_absorption = vec3(c->mie_absorption);  // its default is 0
    a.mie_g = (z & AERIAL_ZERO_MIE_G) ? 0.0 : scalar_field(c->mie_g, d.mie_g);
    a.rayleigh_scale_height_m = scalar_field(c->rayleigh_scale_height_m, d.rayleigh_scale_height_m);
    a.mie_scale_height_m = scalar_field(c->mie_scale_height_m, d.mie_scale_height_m);
    a.ozone_absorption =
        vector_field(c->ozone_absorption, z, AERIAL_ZERO_OZONE_ABSORPTION, d.ozone_absorption);
    a.ozone_center_altitude_m =
        (z & AERIAL_ZERO_OZONE_CENTER_ALTITUDE)
            ? 0.0
            : scalar_field(c->ozone_center_altitude_m, d.ozone_center_altitude_m);
    a.ozone_width_m = scalar_field(c->ozone_width_m, d.ozone_width_m);
    a.planet_radius_m = scalar_field(c->planet_radius_m, d.planet_radius_m);
    a.atmosphere_radius_m = scalar_field(c->atmosphere_radius_m, d.atmosphere_radius_m);
    a.ground_albedo = vector_field(c->ground_albedo, z, AERIAL_ZERO_GROUND_ALBEDO, d.ground_albedo);
    a.sun_irradiance =
        vector_field(c->sun_irradiance, z, AERIAL_ZERO_SUN_IRRADIANCE, d.sun_irradiance);
    return a;
}

aerial_atmosphere to_c(const Atmosphere& a) {
    aerial_atmosphere c;
    std::memset(&c, 0, sizeof c);
    copy(a.rayleigh_scattering, c.rayleigh_scattering);
    copy(a.mie_scattering, c.mie_scattering);
    copy(a.mie_absorption, c.mie_absorption);
    c.mie_g = a.mie_g;
    c.rayleigh_scale_height_m = a.rayleigh_scale_height_m;
    c.mie_scale_height_m = a.mie_scale_height_m;
    copy(a.ozone_absorption, c.ozone_absorption);
    c.ozone_center_altitude_m = a.ozone_center_altitude_m;
    c.ozone_width_m = a.ozone_width_m;
    c.planet_radius_m = a.planet_radius_m;
    c.atmosphere_radius_m = a.atmosphere_radius_m;
    copy(a.ground_albedo, c.ground_albedo);
    copy(a.sun_irradiance, c.sun_irradiance);
    if (is_zero(c.rayleigh_scattering)) c.zero_fields |= AERIAL_ZERO_RAYLEIGH_SCATTERING;
    if (is_zero(c.mie_scattering)) c.zero_fields |= AERIAL_ZERO_MIE_SCATTERING;
    if (c.mie_g == 0.0) c.zero_fields |= AERIAL_ZERO_MIE_G;
    if (is_zero(c.sun_irradiance)) c.zero_fields |= AERIAL_ZERO_SUN_IRRADIANCE;
    if (is_zero(c.ground_albedo)) c.zero_fields |= AERIAL_ZERO_GROUND_ALBEDO;
    if (is_zero(c.ozone_absorption)) c.zero_fields |= AERIAL_ZERO_OZONE_ABSORPTION;
    if (c.ozone_center_altitude_m == 0.0) c.zero_fields |= AERIAL_ZERO_OZONE_CENTER_ALTITUDE;
    return c;
}

View to_cpp(const aerial_view& c) {
    const View d;
    View v;
    v.eye = vec3(c.eye);
    v.sun_dir = is_zero(c.sun_dir) ? d.sun_dir : vec3(c.sun_dir);
    v.up = is_zero(c.up) ? d.up : vec3(c.up);
    v.meters_per_unit = scalar_field(c.meters_per_unit, d.meters_per_unit);
    return v;
}

Display to_cpp(const aerial_display* c) {
    Display d;
    if (c == nullptr) return d;
    if (c->exposure != 0.0f) d.exposure = c->exposure;
    static constexpr EnumValue<ToneCurve> kTones[] = {
        {AERIAL_TONE_CLAMP, ToneCurve::clamp}, {AERIAL_TONE_EXPONENTIAL, ToneCurve::exponential}};
    d.tone = to_cpp_enum(c_enum_value(c->tone), kTones, "display.tone",
                         "AERIAL_TONE_CLAMP (0) or AERIAL_TONE_EXPONENTIAL (1)");
    return d;
}

Model to_cpp_model(int model, const char* field) {
    static constexpr EnumValue<Model> kModels[] = {
        {AERIAL_MODEL_HOFFMAN_PREETHAM, Model::hoffman_preetham},
        {AERIAL_MODEL_HEIGHT, Model::height},
        {AERIAL_MODEL_REFERENCE, Model::reference},
        {AERIAL_MODEL_SINGLE_SCATTERING, Model::single_scattering}};
    return to_cpp_enum(model, kModels, field,
                       "AERIAL_MODEL_HOFFMAN_PREETHAM (0), _HEIGHT (1), _REFERENCE (2) or "
                       "_SINGLE_SCATTERING (3)");
}

const Frame<float>& current_frame(const aerial_context& context) {
    if (!context.frame) {
        fail(AERIAL_ERROR_NO_VIEW, "view", "none set yet: call aerial_context_set_view first");
    }
    return *context.frame;
}

namespace {

Atmosphere validated(const aerial_atmosphere* atmosphere) {
    Atmosphere a = to_cpp(atmosphere);
    if (auto error = validate(a)) fail(AERIAL_ERROR_INVALID_ATMOSPHERE, *error);
    return a;
}

View validated(const aerial_view* view) {
    require(view, "view");
    if (view->meters_per_unit < 0.0) {
        fail(AERIAL_ERROR_INVALID_VIEW, "meters_per_unit",
             "expected a finite value > 0 (0 means 1), got " +
                 detail::number(view->meters_per_unit));
    }
    View v = to_cpp(*view);
    if (auto error = validate(v)) fail(AERIAL_ERROR_INVALID_VIEW, *error);
    return v;
}

}  // namespace

Positions to_cpp_positions(const aerial_positions& positions) {
    if ((positions.y == nullptr) != (positions.z == nullptr)) {
        fail(AERIAL_ERROR_INVALID_BATCH, "positions",
             "expected y and z both NULL (interleaved records at x) or both set (separate "
             "arrays), got one of them");
    }
    if (positions.y == nullptr) {
        if (positions.stride_bytes != 0 && positions.stride_bytes < 3 * sizeof(float)) {
            fail(AERIAL_ERROR_INVALID_BATCH, "positions.stride_bytes",
                 "expected 0 or >= 12 for interleaved x, y, z records, got " +
                     detail::number(positions.stride_bytes));
        }
        Positions p = Positions::aos(positions.x, positions.count, positions.stride_bytes);
        p.model_matrix = positions.model_matrix;
        return p;
    }
    return Positions{positions.x,
                     positions.y,
                     positions.z,
                     positions.count,
                     positions.stride_bytes ? positions.stride_bytes : sizeof(float),
                     positions.model_matrix};
}

ColourFormat to_cpp_format(int format, const char* field) {
    static constexpr EnumValue<ColourFormat> kFormats[] = {
        {AERIAL_COLOUR_RGBA8, ColourFormat::rgba8},
        {AERIAL_COLOUR_BGRA8, ColourFormat::bgra8},
        {AERIAL_COLOUR_ARGB32, ColourFormat::argb32}};
    return to_cpp_enum(format, kFormats, field,
                       "AERIAL_COLOUR_RGBA8 (0), _BGRA8 (1) or _ARGB32 (2)");
}

namespace {

BatchOutputs to_cpp_outputs(const aerial_outputs& outputs) {
    BatchOutputs o;
    o.colour_format = to_cpp_format(c_enum_value(outputs.colour_format), "outputs.colour_format");
    o.extinction_rgba8 = outputs.extinction_rgba8;
    o.extinction_rgba8_stride = outputs.extinction_rgba8_stride;
    o.lit_rgba8 = outputs.lit_rgba8;
    o.lit_rgba8_stride = outputs.lit_rgba8_stride;
    o.in_scattering_rgba8 = outputs.in_scattering_rgba8;
    o.in_scattering_rgba8_stride = outputs.in_scattering_rgba8_stride;
    o.extinction_rgb = outputs.extinction_rgb;
    o.extinction_rgb_stride = outputs.extinction_rgb_stride;
    o.in_scattering_rgb = outputs.in_scattering_rgb;
    o.in_scattering_rgb_stride = outputs.in_scattering_rgb_stride;
    o.sun_irradiance_rgb = outputs.sun_irradiance_rgb;
    o.sun_irradiance_rgb_stride = outputs.sun_irradiance_rgb_stride;
    return o;
}

/// The batch settings (null: the defaults); `lighting` holds what settings->lighting asks for
/// and must outlive the returned settings, which point at it.
BatchSettings to_cpp_settings(const aerial_batch_settings* settings, Lighting& lighting) {
    BatchSettings s;
    if (settings == nullptr) return s;
    s.display = to_cpp(&settings->display);
    static constexpr EnumValue<Kernel> kKernels[] = {{AERIAL_KERNEL_SIMD, Kernel::simd},
                                                     {AERIAL_KERNEL_SIMD_FAST, Kernel::simd_fast},
                                                     {AERIAL_KERNEL_SCALAR, Kernel::scalar}};
    s.kernel = to_cpp_enum(c_enum_value(settings->kernel), kKernels, "settings.kernel",
                           "AERIAL_KERNEL_SIMD (0), _SIMD_FAST (1) or _SCALAR (2)");
    s.threads = settings->threads;
    if (settings->min_vertices_per_thread != 0) {
        s.min_vertices_per_thread = settings->min_vertices_per_thread;
    }
    if (const aerial_lighting* l = settings->lighting) {
        lighting.normals = l->normals;
        lighting.normal_stride_bytes = l->normal_stride_bytes;
        lighting.ambient = glm::vec3(l->ambient[0], l->ambient[1], l->ambient[2]);
        const bool no_albedo = l->albedo[0] == 0.0f && l->albedo[1] == 0.0f && l->albedo[2] == 0.0f;
        if (!no_albedo) lighting.albedo = glm::vec3(l->albedo[0], l->albedo[1], l->albedo[2]);
        s.lighting = &lighting;
    }
    return s;
}

/// Recomputes the context's frame from its atmosphere, model and view (when it has a view).
void refresh_frame(aerial_context& context) {
    if (!context.view) return;
    // The parts were validated one by one; prepare_frame checks them together.
    context.frame =
        value_or_fail(prepare_frame<float>(context.atmosphere, *context.view, context.model),
                      AERIAL_ERROR_INVALID_VIEW);
}

}  // namespace
}  // namespace aerial::capi

using namespace aerial;  // NOLINT(google-build-using-namespace): this file implements the C API
using capi::fail;
using capi::guard;
using capi::require;

extern "C" {

const char* aerial_status_string(aerial_status status) {
    switch (status) {
        case AERIAL_OK:
            return "ok";
        case AERIAL_ERROR_NULL_ARGUMENT:
            return "null argument";
        case AERIAL_ERROR_INVALID_ARGUMENT:
            return "invalid argument";
        case AERIAL_ERROR_INVALID_ATMOSPHERE:
            return "invalid atmosphere";
        case AERIAL_ERROR_INVALID_VIEW:
            return "invalid view";
        case AERIAL_ERROR_INVALID_VERTEX:
            return "invalid vertex";
        case AERIAL_ERROR_INVALID_BATCH:
            return "invalid batch";
        case AERIAL_ERROR_UNKNOWN_PRESET:
            return "unknown preset";
        case AERIAL_ERROR_NO_VIEW:
            return "no view set";
        case AERIAL_ERROR_VERSION_MISMATCH:
            return "version mismatch";
        case AERIAL_ERROR_BUFFER_TOO_SMALL:
            return "buffer too small";
        case AERIAL_ERROR_GL_UNAVAILABLE:
            return "GL unavailable";
        case AERIAL_ERROR_GL_UNSUPPORTED:
            return "GL feature unsupported";
        case AERIAL_ERROR_ARB_PROGRAM:
            return "ARB program error";
        case AERIAL_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case AERIAL_ERROR_INTERNAL:
            return "internal error";
        case AERIAL_ERROR_ENGINE_STATE:
            return "engine changed aerial's GL state";
        case AERIAL_STATUS_MAX_ENUM:
            break;
    }
    return "unknown status";
}

const char* aerial_last_error_message(void) { return capi::thread_error().message.c_str(); }
const char* aerial_last_error_field(void) { return capi::thread_error().field.c_str(); }

int aerial_library_version(void) { return AERIAL_VERSION; }

aerial_status aerial_check_version(int header_version, size_t sizeof_atmosphere, size_t sizeof_view,
                                   size_t sizeof_outputs, size_t sizeof_batch_settings,
                                   size_t sizeof_arb_options) {
    return guard("aerial_check_version", nullptr, [&] {
        const int major = header_version / 10000;
        const int minor = header_version / 100 % 100;
        const bool compatible =
            major == AERIAL_VERSION_MAJOR &&
            (major == 0 ? minor == AERIAL_VERSION_MINOR : minor <= AERIAL_VERSION_MINOR);
        if (!compatible) {
            fail(AERIAL_ERROR_VERSION_MISMATCH, "header_version",
                 "expected aerial.h " + std::to_string(AERIAL_VERSION_MAJOR) + "." +
                     std::to_string(AERIAL_VERSION_MINOR) + " (the library's), got the caller's " +
                     std::to_string(major) + "." + std::to_string(minor));
        }
        const struct {
            const char* name;
            size_t caller;
            size_t library;
        } sizes[] = {
            {"sizeof(aerial_atmosphere)", sizeof_atmosphere, sizeof(aerial_atmosphere)},
            {"sizeof(aerial_view)", sizeof_view, sizeof(aerial_view)},
            {"sizeof(aerial_outputs)", sizeof_outputs, sizeof(aerial_outputs)},
            {"sizeof(aerial_batch_settings)", sizeof_batch_settings, sizeof(aerial_batch_settings)},
            {"sizeof(aerial_arb_options)", sizeof_arb_options, sizeof(aerial_arb_options)}};
        for (const auto& s : sizes) {
            if (s.caller != s.library) {
                fail(AERIAL_ERROR_VERSION_MISMATCH, s.name,
                     "expected " + detail::number(s.library) + " bytes (the library's), got " +
                         detail::number(s.caller) + " (the caller's)");
            }
        }
    });
}

// ---- Atmosphere ------------------------------------------------------------------------------

aerial_status aerial_atmosphere_preset(const char* name, aerial_atmosphere* out) {
    return guard("aerial_atmosphere_preset", nullptr, [&] {
        require(name, "name");
        require(out, "out");
        *out =
            capi::to_c(capi::value_or_fail(atmosphere_preset(name), AERIAL_ERROR_UNKNOWN_PRESET));
    });
}

size_t aerial_atmosphere_preset_count(void) { return atmosphere_preset_names().size(); }

const char* aerial_atmosphere_preset_name(size_t i) {
    const auto& names = atmosphere_preset_names();
    return i < names.size() ? names[i].c_str() : nullptr;
}

aerial_status aerial_atmosphere_from_json(const char* json_text, aerial_atmosphere* out) {
    return guard("aerial_atmosphere_from_json", nullptr, [&] {
        require(json_text, "json_text");
        require(out, "out");
        *out = capi::to_c(
            capi::value_or_fail(atmosphere_from_json(json_text), AERIAL_ERROR_INVALID_ATMOSPHERE));
    });
}

aerial_status aerial_validate_atmosphere(const aerial_atmosphere* atmosphere) {
    return guard("aerial_validate_atmosphere", nullptr, [&] {
        require(atmosphere, "atmosphere");
        capi::validated(atmosphere);
    });
}

aerial_status aerial_validate_view(const aerial_view* view) {
    return guard("aerial_validate_view", nullptr, [&] { capi::validated(view); });
}

aerial_status aerial_evaluate(const aerial_atmosphere* atmosphere, const aerial_view* view,
                              aerial_model model, const double vertex[3],
                              aerial_scattering_d* out) {
    return guard("aerial_evaluate", nullptr, [&] {
        require(vertex, "vertex");
        require(out, "out");
        const Atmosphere a = capi::validated(atmosphere);
        const View v = capi::validated(view);
        const Model m = capi::to_cpp_model(capi::c_enum_value(model), "model");
        const glm::dvec3 p{vertex[0], vertex[1], vertex[2]};
        const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        if (finite && glm::length(p - v.eye) * v.meters_per_unit > kMaxDistanceM) {
            fail(AERIAL_ERROR_INVALID_VERTEX, "vertex",
                 "expected a point within " + detail::number(kMaxDistanceM) +
                     " m of the eye, got " +
                     detail::number(glm::length(p - v.eye) * v.meters_per_unit) + " m");
        }
        capi::copy_scattering(
            capi::value_or_fail(evaluate(a, v, m, p), AERIAL_ERROR_INVALID_VERTEX), *out);
    });
}

// ---- Context ---------------------------------------------------------------------------------

aerial_status aerial_context_create(const aerial_atmosphere* atmosphere, aerial_model model,
                                    aerial_context** out) {
    return guard("aerial_context_create", nullptr, [&] {
        require(out, "out");
        *out = nullptr;
        auto context = std::make_unique<aerial_context>();
        context->atmosphere = capi::validated(atmosphere);
        context->model = capi::to_cpp_model(capi::c_enum_value(model), "model");
        *out = context.release();
    });
}

void aerial_context_destroy(aerial_context* context) { delete context; }

aerial_status aerial_context_set_atmosphere(aerial_context* context,
                                            const aerial_atmosphere* atmosphere) {
    return guard("aerial_context_set_atmosphere", capi::last_error_of(context), [&] {
        require(context, "context");
        require(atmosphere, "atmosphere");
        aerial_context updated = *context;
        updated.atmosphere = capi::validated(atmosphere);
        capi::refresh_frame(updated);
        *context = std::move(updated);
    });
}

aerial_status aerial_context_set_model(aerial_context* context, aerial_model model) {
    return guard("aerial_context_set_model", capi::last_error_of(context), [&] {
        require(context, "context");
        aerial_context updated = *context;
        updated.model = capi::to_cpp_model(capi::c_enum_value(model), "model");
        capi::refresh_frame(updated);
        *context = std::move(updated);
    });
}

aerial_status aerial_context_set_view(aerial_context* context, const aerial_view* view) {
    return guard("aerial_context_set_view", capi::last_error_of(context), [&] {
        require(context, "context");
        aerial_context updated = *context;
        updated.view = capi::validated(view);
        capi::refresh_frame(updated);
        *context = std::move(updated);
    });
}

const char* aerial_context_last_error(const aerial_context* context) {
    return context ? context->last_error.c_str() : "";
}

aerial_status aerial_scatter(const aerial_context* context, const float vertex[3],
                             aerial_scattering* out) {
    return guard("aerial_scatter", capi::last_error_of(context), [&] {
        require(context, "context");
        require(vertex, "vertex");
        require(out, "out");
        capi::copy_scattering(
            scatter(capi::current_frame(*context), glm::vec3(vertex[0], vertex[1], vertex[2])),
            *out);
    });
}

aerial_status aerial_shade(const aerial_context* context, const aerial_positions* positions,
                           const aerial_outputs* outputs, const aerial_batch_settings* settings,
                           aerial_batch_stats* stats) {
    return guard("aerial_shade", capi::last_error_of(context), [&] {
        require(context, "context");
        require(positions, "positions");
        require(outputs, "outputs");
        const Frame<float>& frame = capi::current_frame(*context);
        const Positions p = capi::to_cpp_positions(*positions);
        Lighting lighting;
        const BatchSettings s = capi::to_cpp_settings(settings, lighting);
        const BatchStats result = capi::value_or_fail(
            shade_into(frame, p, capi::to_cpp_outputs(*outputs), s), AERIAL_ERROR_INVALID_BATCH);
        if (stats != nullptr) {
            stats->vertices = result.vertices;
            stats->invalid_vertices = result.invalid_vertices;
            stats->threads_used = result.threads_used;
        }
    });
}

}  // extern "C"
