// The C interface (aerial/aerial.h) compiled as C++: its defaults are the C++ defaults, its
// results are the C++ API's bit for bit, every status comes from some bad input with its text,
// the version check catches a mismatch, and no exception crosses it.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/aerial.h"
#include "aerial/aerial.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/headless.hpp"
#include "capi_internal.hpp"
#include "capi_testing.hpp"

namespace {

/// The C++ model of a C model number (the enums' values differ: C keeps its numbers stable).
aerial::Model cpp_model(aerial_model model) {
    switch (model) {
        case AERIAL_MODEL_HOFFMAN_PREETHAM:
            return aerial::Model::hoffman_preetham;
        case AERIAL_MODEL_HEIGHT:
            return aerial::Model::height;
        case AERIAL_MODEL_REFERENCE:
            return aerial::Model::reference;
        case AERIAL_MODEL_SINGLE_SCATTERING:
            return aerial::Model::single_scattering;
    }
    return aerial::Model::height;
}

template <class T>
T zeroed() {
    T value;
    std::memset(&value, 0, sizeof value);
    return value;
}

aerial_view test_view(double meters_per_unit = 1.0) {
    auto v = zeroed<aerial_view>();
    v.eye[0] = 0.0;
    v.eye[1] = -1.5;
    v.eye[2] = 0.01;
    v.sun_dir[0] = 0.0;
    v.sun_dir[1] = 0.6;
    v.sun_dir[2] = 0.8;
    v.up[2] = 1.0;
    v.meters_per_unit = meters_per_unit;
    return v;
}

aerial::View cpp_view(const aerial_view& v) {
    aerial::View view;
    view.eye = {v.eye[0], v.eye[1], v.eye[2]};
    view.sun_dir = {v.sun_dir[0], v.sun_dir[1], v.sun_dir[2]};
    view.up = {v.up[0], v.up[1], v.up[2]};
    view.meters_per_unit = v.meters_per_unit;
    return view;
}

/// Vertices spread over tens of kilometres at meters_per_unit 20000, and a few that are not
/// positions.
std::vector<float> test_vertices(std::size_t n) {
    std::vector<float> xyz;
    for (std::size_t i = 0; i < n; ++i) {
        const float t = float(i) / float(n);
        xyz.push_back(-1.0f + 2.0f * std::fmod(t * 37.0f, 1.0f));
        xyz.push_back(-1.0f + 2.0f * t);
        xyz.push_back(0.05f * std::fmod(t * 11.0f, 1.0f));
    }
    xyz[3 * 5 + 1] = std::nanf("");
    return xyz;
}

/// The aerial_*_destroy calls as a scope guard.
struct ContextHandle {
    aerial_context* p = nullptr;
    ~ContextHandle() { aerial_context_destroy(p); }
};

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// ---- Defaults --------------------------------------------------------------------------------

TEST(CApiDefaults, ZeroAtmosphereIsTheCppDefault) {
    const auto zero = zeroed<aerial_atmosphere>();
    const aerial::Atmosphere c = aerial::capi::to_cpp(&zero);
    const aerial::Atmosphere cpp;
    EXPECT_EQ(c.rayleigh_scattering, cpp.rayleigh_scattering);
    EXPECT_EQ(c.mie_scattering, cpp.mie_scattering);
    EXPECT_EQ(c.mie_absorption, cpp.mie_absorption);
    EXPECT_EQ(c.mie_g, cpp.mie_g);
    EXPECT_EQ(c.rayleigh_scale_height_m, cpp.rayleigh_scale_height_m);
    EXPECT_EQ(c.mie_scale_height_m, cpp.mie_scale_height_m);
    EXPECT_EQ(c.ozone_absorption, cpp.ozone_absorption);
    EXPECT_EQ(c.ozone_center_altitude_m, cpp.ozone_center_altitude_m);
    EXPECT_EQ(c.ozone_width_m, cpp.ozone_width_m);
    EXPECT_EQ(c.planet_radius_m, cpp.planet_radius_m);
    EXPECT_EQ(c.atmosphere_radius_m, cpp.atmosphere_radius_m);
    EXPECT_EQ(c.ground_albedo, cpp.ground_albedo);
    EXPECT_EQ(c.sun_irradiance, cpp.sun_irradiance);
    EXPECT_TRUE(c == cpp) << "every field, the ones listed above and any other";
    EXPECT_TRUE(aerial::capi::to_cpp(static_cast<const aerial_atmosphere*>(nullptr)) == cpp);
}

TEST(CApiDefaults, ZeroFieldsAskForAnExactZero) {
    auto a = zeroed<aerial_atmosphere>();
    a.zero_fields = AERIAL_ZERO_MIE_G | AERIAL_ZERO_MIE_SCATTERING;
    const aerial::Atmosphere c = aerial::capi::to_cpp(&a);
    EXPECT_EQ(c.mie_g, 0.0);
    EXPECT_EQ(c.mie_scattering, glm::dvec3(0.0));
    EXPECT_EQ(c.rayleigh_scattering, aerial::Atmosphere{}.rayleigh_scattering);

    const aerial::Atmosphere earth;
    a = zeroed<aerial_atmosphere>();
    a.zero_fields = AERIAL_ZERO_GROUND_ALBEDO;
    EXPECT_EQ(aerial::capi::to_cpp(&a).ground_albedo, glm::dvec3(0.0));
    EXPECT_EQ(aerial::capi::to_cpp(&a).ozone_absorption, earth.ozone_absorption);
    a.zero_fields = AERIAL_ZERO_OZONE_ABSORPTION;
    EXPECT_EQ(aerial::capi::to_cpp(&a).ozone_absorption, glm::dvec3(0.0));
    EXPECT_EQ(aerial::capi::to_cpp(&a).ground_albedo, earth.ground_albedo);
    a.zero_fields = AERIAL_ZERO_OZONE_CENTER_ALTITUDE;
    EXPECT_EQ(aerial::capi::to_cpp(&a).ozone_center_altitude_m, 0.0);
    EXPECT_EQ(aerial::capi::to_cpp(&a).ozone_width_m, earth.ozone_width_m);
    EXPECT_EQ(aerial_validate_atmosphere(&a), AERIAL_OK) << "a layer centred at sea level";
    // A bit overrides a value given in its field, as for the older bits.
    a.ground_albedo[1] = 0.5;
    a.zero_fields = AERIAL_ZERO_GROUND_ALBEDO;
    EXPECT_EQ(aerial::capi::to_cpp(&a).ground_albedo, glm::dvec3(0.0));
}

TEST(CApiDefaults, NewAtmosphereFieldsMapBothWays) {
    auto a = zeroed<aerial_atmosphere>();
    a.ground_albedo[0] = 0.3;  // the other channels 0: taken as given, not the default
    a.ozone_absorption[2] = 1e-7;
    a.ozone_center_altitude_m = 30000.0;
    a.ozone_width_m = 10000.0;
    const aerial::Atmosphere c = aerial::capi::to_cpp(&a);
    EXPECT_EQ(c.ground_albedo, glm::dvec3(0.3, 0.0, 0.0));
    EXPECT_EQ(c.ozone_absorption, glm::dvec3(0.0, 0.0, 1e-7));
    EXPECT_EQ(c.ozone_center_altitude_m, 30000.0);
    EXPECT_EQ(c.ozone_width_m, 10000.0);
    const aerial_atmosphere back = aerial::capi::to_c(c);
    EXPECT_EQ(back.zero_fields, 0u);
    EXPECT_TRUE(aerial::capi::to_cpp(&back) == c);

    // Zeros come back with their bits, and through them the same C++ atmosphere.
    aerial::Atmosphere zero;
    zero.ground_albedo = glm::dvec3(0.0);
    zero.ozone_absorption = glm::dvec3(0.0);
    zero.ozone_center_altitude_m = 0.0;
    const aerial_atmosphere zc = aerial::capi::to_c(zero);
    EXPECT_EQ(zc.zero_fields, unsigned(AERIAL_ZERO_GROUND_ALBEDO | AERIAL_ZERO_OZONE_ABSORPTION |
                                       AERIAL_ZERO_OZONE_CENTER_ALTITUDE));
    EXPECT_TRUE(aerial::capi::to_cpp(&zc) == zero);

    // JSON without the new fields: no ozone and a black ground, kept so through the C struct.
    auto j = zeroed<aerial_atmosphere>();
    ASSERT_EQ(aerial_atmosphere_from_json("{\"mie_g\": 0.7}", &j), AERIAL_OK);
    EXPECT_EQ(j.ground_albedo[0], 0.0);
    EXPECT_EQ(j.ozone_absorption[1], 0.0);
    EXPECT_NE(j.zero_fields & AERIAL_ZERO_GROUND_ALBEDO, 0u);
    EXPECT_NE(j.zero_fields & AERIAL_ZERO_OZONE_ABSORPTION, 0u);
    EXPECT_EQ(aerial::capi::to_cpp(&j).ground_albedo, glm::dvec3(0.0));
    EXPECT_EQ(aerial::capi::to_cpp(&j).ozone_absorption, glm::dvec3(0.0));
    ASSERT_EQ(aerial_atmosphere_from_json("{\"ground_albedo\": 0.2}", &j), AERIAL_OK);
    EXPECT_EQ(j.ground_albedo[2], 0.2);

    // Mars: no ozone, albedo 0.25.
    auto mars = zeroed<aerial_atmosphere>();
    ASSERT_EQ(aerial_atmosphere_preset("mars", &mars), AERIAL_OK);
    EXPECT_EQ(mars.ground_albedo[1], 0.25);
    EXPECT_NE(mars.zero_fields & AERIAL_ZERO_OZONE_ABSORPTION, 0u);
}

TEST(CApiDefaults, NewAtmosphereFieldsAreValidatedByName) {
    struct Case {
        void (*edit)(aerial_atmosphere&);
        const char* field;
        const char* message;
    } cases[] = {
        {[](aerial_atmosphere& a) { a.ground_albedo[1] = 1.5; }, "ground_albedo[1]",
         "aerial_validate_atmosphere(): ground_albedo[1]: expected a value in [0, 1] (Lambertian "
         "albedo), got 1.5"},
        {[](aerial_atmosphere& a) { a.ozone_absorption[0] = -1e-6; }, "ozone_absorption[0]",
         "aerial_validate_atmosphere(): ozone_absorption[0]: expected a coefficient in [0, 1] "
         "1/m, got -1e-06"},
        {[](aerial_atmosphere& a) { a.ozone_center_altitude_m = std::nan(""); },
         "ozone_center_altitude_m",
         "aerial_validate_atmosphere(): ozone_center_altitude_m: expected a value in [0, 1e+06] "
         "m, got nan"},
        {[](aerial_atmosphere& a) { a.ozone_width_m = 0.5; }, "ozone_width_m",
         "aerial_validate_atmosphere(): ozone_width_m: expected a value in [1, 1e+06] m, got "
         "0.5"},
    };
    for (const auto& c : cases) {
        auto a = zeroed<aerial_atmosphere>();
        c.edit(a);
        EXPECT_EQ(aerial_validate_atmosphere(&a), AERIAL_ERROR_INVALID_ATMOSPHERE) << c.field;
        EXPECT_STREQ(aerial_last_error_field(), c.field);
        EXPECT_STREQ(aerial_last_error_message(), c.message);
    }
}

TEST(CApiDefaults, PresetsRoundTripThroughTheCStruct) {
    for (std::size_t i = 0; i < aerial_atmosphere_preset_count(); ++i) {
        const char* name = aerial_atmosphere_preset_name(i);
        auto c = zeroed<aerial_atmosphere>();
        ASSERT_EQ(aerial_atmosphere_preset(name, &c), AERIAL_OK) << name;
        const aerial::Atmosphere back = aerial::capi::to_cpp(&c);
        const aerial::Atmosphere cpp = *aerial::atmosphere_preset(name);
        EXPECT_EQ(aerial::to_json(back), aerial::to_json(cpp)) << name;
    }
    EXPECT_EQ(aerial_atmosphere_preset_name(aerial_atmosphere_preset_count()), nullptr);
}

TEST(CApiDefaults, ZeroViewIsTheCppDefaultButForTheEye) {
    const aerial::View c = aerial::capi::to_cpp(zeroed<aerial_view>());
    const aerial::View cpp;
    EXPECT_EQ(c.sun_dir, cpp.sun_dir);
    EXPECT_EQ(c.up, cpp.up);
    EXPECT_EQ(c.meters_per_unit, cpp.meters_per_unit);
    EXPECT_EQ(c.eye, glm::dvec3(0.0)) << "the eye is taken as given";
}

TEST(CApiDefaults, ZeroDisplayAndSettingsShadeAsTheCppDefaults) {
    const aerial::Display d = aerial::capi::to_cpp(static_cast<const aerial_display*>(nullptr));
    const auto zero_display = zeroed<aerial_display>();
    const aerial::Display z = aerial::capi::to_cpp(&zero_display);
    EXPECT_EQ(z.exposure, aerial::Display{}.exposure);
    EXPECT_EQ(z.tone, aerial::Display{}.tone);
    EXPECT_EQ(d.exposure, aerial::Display{}.exposure);

    ContextHandle ctx;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &ctx.p), AERIAL_OK);
    const aerial_view v = test_view(20000.0);
    ASSERT_EQ(aerial_context_set_view(ctx.p, &v), AERIAL_OK);
    const auto xyz = test_vertices(100);
    std::vector<std::uint8_t> with_null(400), with_zero(400);
    auto p = zeroed<aerial_positions>();
    p.x = xyz.data();
    p.count = 100;
    auto out = zeroed<aerial_outputs>();
    out.in_scattering_rgba8 = with_null.data();
    ASSERT_EQ(aerial_shade(ctx.p, &p, &out, nullptr, nullptr), AERIAL_OK);
    const auto settings = zeroed<aerial_batch_settings>();
    out.in_scattering_rgba8 = with_zero.data();
    ASSERT_EQ(aerial_shade(ctx.p, &p, &out, &settings, nullptr), AERIAL_OK);
    EXPECT_EQ(with_null, with_zero);
}

TEST(CApiDefaults, ZeroArbOptionsGenerateTheCppDefaultProgram) {
    std::vector<char> text(16384);
    std::size_t length = 0;
    int count = 0;
    const auto zero = zeroed<aerial_arb_options>();
    ASSERT_EQ(aerial_arb_generate(&zero, text.data(), text.size(), &length, &count), AERIAL_OK);
    const auto cpp = aerial::generate_arb_program({});
    ASSERT_TRUE(cpp.ok());
    EXPECT_EQ(std::string(text.data(), length), cpp->text);
    EXPECT_EQ(count, aerial::kArbParameterCount);
    std::size_t null_length = 0;
    ASSERT_EQ(aerial_arb_generate(nullptr, nullptr, 0, &null_length, nullptr), AERIAL_OK);
    EXPECT_EQ(null_length, length);
}

// ---- Bit for bit against the C++ API ---------------------------------------------------------

TEST(CApiResults, ScatterAndShadeEqualTheCppApiBitForBit) {
    const auto xyz = test_vertices(257);
    const std::size_t n = xyz.size() / 3;
    for (std::size_t i = 0; i < aerial_atmosphere_preset_count(); ++i) {
        const char* name = aerial_atmosphere_preset_name(i);
        auto atmosphere = zeroed<aerial_atmosphere>();
        ASSERT_EQ(aerial_atmosphere_preset(name, &atmosphere), AERIAL_OK);
        // The numerical path through single-scattering (the reference's tables cost seconds per
        // preset; EvaluateEqualsTheCppEvaluateBitForBit takes the reference on earth).
        for (aerial_model model :
             {AERIAL_MODEL_HOFFMAN_PREETHAM, AERIAL_MODEL_HEIGHT, AERIAL_MODEL_SINGLE_SCATTERING}) {
            SCOPED_TRACE(std::string(name) + " model " + std::to_string(model));
            const std::size_t count = model == AERIAL_MODEL_SINGLE_SCATTERING ? 16 : n;
            ContextHandle ctx;
            ASSERT_EQ(aerial_context_create(&atmosphere, model, &ctx.p), AERIAL_OK);
            const aerial_view v = test_view(20000.0);
            ASSERT_EQ(aerial_context_set_view(ctx.p, &v), AERIAL_OK);
            const auto frame = aerial::prepare_frame<float>(*aerial::atmosphere_preset(name),
                                                            cpp_view(v), cpp_model(model));
            ASSERT_TRUE(frame.ok());

            for (std::size_t k = 0; k < count; k += 7) {
                aerial_scattering s;
                ASSERT_EQ(aerial_scatter(ctx.p, &xyz[3 * k], &s), AERIAL_OK);
                const auto r =
                    aerial::scatter(*frame, glm::vec3(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]));
                for (int c = 0; c < 3; ++c) {
                    EXPECT_TRUE(same_bits(s.extinction[c], r.extinction[c])) << k;
                    EXPECT_TRUE(same_bits(s.in_scattering[c], r.in_scattering[c])) << k;
                    EXPECT_TRUE(same_bits(s.sun_irradiance[c], r.sun_irradiance[c])) << k;
                }
            }

            // Every output, strided, with lighting and a non-default display.
            std::vector<float> normals(3 * count, 0.0f);
            for (std::size_t k = 0; k < count; ++k) normals[3 * k + 2] = 1.0f;
            auto lighting = zeroed<aerial_lighting>();
            lighting.normals = normals.data();
            lighting.ambient[2] = 0.1f;
            auto settings = zeroed<aerial_batch_settings>();
            settings.display.exposure = 3.0f;
            settings.display.tone = AERIAL_TONE_EXPONENTIAL;
            settings.kernel = AERIAL_KERNEL_SIMD_FAST;
            settings.threads = 1;
            settings.lighting = &lighting;
            std::vector<std::uint8_t> c8(3 * 8 * count), cpp8(3 * 8 * count);
            std::vector<float> cf(3 * 4 * count), cppf(3 * 4 * count);
            // The same layout for both APIs (their output structs share the field names): codes
            // 8 bytes apart, floats 16 bytes apart, the lit codes and L_in floats packed.
            const auto lay_out = [count](auto& out, std::uint8_t* codes, float* floats) {
                out.extinction_rgba8 = codes;
                out.extinction_rgba8_stride = 8;
                out.lit_rgba8 = codes + 8 * count;
                out.in_scattering_rgba8 = codes + 16 * count;
                out.in_scattering_rgba8_stride = 8;
                out.extinction_rgb = floats;
                out.extinction_rgb_stride = 16;
                out.in_scattering_rgb = floats + 4 * count;
                out.sun_irradiance_rgb = floats + 8 * count;
                out.sun_irradiance_rgb_stride = 16;
            };
            auto out = zeroed<aerial_outputs>();
            lay_out(out, c8.data(), cf.data());
            auto p = zeroed<aerial_positions>();
            p.x = xyz.data();
            p.count = count;
            aerial_batch_stats stats;
            ASSERT_EQ(aerial_shade(ctx.p, &p, &out, &settings, &stats), AERIAL_OK)
                << aerial_last_error_message();

            aerial::BatchOutputs o;
            lay_out(o, cpp8.data(), cppf.data());
            aerial::Lighting l;
            l.normals = normals.data();
            l.ambient = {0.0f, 0.0f, 0.1f};
            aerial::BatchSettings s;
            s.display = {3.0f, aerial::ToneCurve::exponential};
            s.kernel = aerial::Kernel::simd_fast;
            s.threads = 1;
            s.lighting = &l;
            const auto cpp_stats =
                aerial::shade_into(*frame, aerial::Positions::aos(xyz.data(), count), o, s);
            ASSERT_TRUE(cpp_stats.ok());
            EXPECT_EQ(c8, cpp8);
            EXPECT_EQ(0, std::memcmp(cf.data(), cppf.data(), cf.size() * sizeof(float)));
            EXPECT_EQ(stats.vertices, cpp_stats->vertices);
            EXPECT_EQ(stats.invalid_vertices, cpp_stats->invalid_vertices);
            EXPECT_EQ(stats.invalid_vertices, 1u);
        }
    }
}

TEST(CApiResults, SeparateArraysShadeAsInterleavedOnes) {
    const auto xyz = test_vertices(64);
    std::vector<float> x, y, z;
    for (std::size_t k = 0; k < 64; ++k) {
        x.push_back(xyz[3 * k]);
        y.push_back(xyz[3 * k + 1]);
        z.push_back(xyz[3 * k + 2]);
    }
    ContextHandle ctx;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HOFFMAN_PREETHAM, &ctx.p), AERIAL_OK);
    const aerial_view v = test_view(20000.0);
    ASSERT_EQ(aerial_context_set_view(ctx.p, &v), AERIAL_OK);
    std::vector<std::uint8_t> a(256), b(256);
    auto out = zeroed<aerial_outputs>();
    auto p = zeroed<aerial_positions>();
    p.x = xyz.data();
    p.count = 64;
    out.in_scattering_rgba8 = a.data();
    ASSERT_EQ(aerial_shade(ctx.p, &p, &out, nullptr, nullptr), AERIAL_OK);
    p.x = x.data();
    p.y = y.data();
    p.z = z.data();
    out.in_scattering_rgba8 = b.data();
    ASSERT_EQ(aerial_shade(ctx.p, &p, &out, nullptr, nullptr), AERIAL_OK);
    EXPECT_EQ(a, b);
}

TEST(CApiResults, EvaluateEqualsTheCppEvaluateBitForBit) {
    const aerial_view v = test_view(1.0);
    for (aerial_model model : {AERIAL_MODEL_HOFFMAN_PREETHAM, AERIAL_MODEL_HEIGHT,
                               AERIAL_MODEL_REFERENCE, AERIAL_MODEL_SINGLE_SCATTERING}) {
        const double vertex[3] = {3000.0, 12000.0, 150.0};
        aerial_scattering_d s;
        ASSERT_EQ(aerial_evaluate(nullptr, &v, model, vertex, &s), AERIAL_OK);
        const auto r = aerial::evaluate(aerial::Atmosphere{}, cpp_view(v), cpp_model(model),
                                        {vertex[0], vertex[1], vertex[2]});
        ASSERT_TRUE(r.ok());
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(s.extinction[c], r->extinction[c]);
            EXPECT_EQ(s.in_scattering[c], r->in_scattering[c]);
            EXPECT_EQ(s.sun_irradiance[c], r->sun_irradiance[c]);
        }
    }
}

TEST(CApiResults, ArbTextAndParametersEqualTheCppGenerator) {
    for (aerial_model model : {AERIAL_MODEL_HOFFMAN_PREETHAM, AERIAL_MODEL_HEIGHT}) {
        auto options = zeroed<aerial_arb_options>();
        options.model = model;
        options.parameter_base = 4;
        options.texcoord_units = AERIAL_NO_TEXCOORDS;
        std::size_t length = 0;
        ASSERT_EQ(aerial_arb_generate(&options, nullptr, 0, &length, nullptr), AERIAL_OK);
        std::vector<char> text(length + 1);
        int count = 0;
        ASSERT_EQ(aerial_arb_generate(&options, text.data(), text.size(), nullptr, &count),
                  AERIAL_OK);
        aerial::ArbProgramOptions cpp;
        cpp.model = cpp_model(model);
        cpp.parameter_base = 4;
        cpp.texcoord_units = 0;
        const auto program = aerial::generate_arb_program(cpp);
        ASSERT_TRUE(program.ok());
        EXPECT_EQ(std::string(text.data()), program->text);
        EXPECT_EQ(count, aerial::arb_parameter_count(program->options));

        ContextHandle ctx;
        ASSERT_EQ(aerial_context_create(nullptr, model, &ctx.p), AERIAL_OK);
        const aerial_view v = test_view(20000.0);
        ASSERT_EQ(aerial_context_set_view(ctx.p, &v), AERIAL_OK);
        auto display = zeroed<aerial_display>();
        display.exposure = 2.0f;
        std::vector<float> vectors(4 * std::size_t(count));
        std::size_t written = 0;
        ASSERT_EQ(aerial_arb_parameters(ctx.p, &options, &display, vectors.data(),
                                        std::size_t(count), &written),
                  AERIAL_OK);
        const auto frame =
            aerial::prepare_frame<float>(aerial::Atmosphere{}, cpp_view(v), cpp_model(model));
        const auto p = aerial::arb_program_parameters(*frame, {2.0f, aerial::ToneCurve::clamp},
                                                      program->options);
        ASSERT_TRUE(p.ok());
        ASSERT_EQ(written, p->size());
        EXPECT_EQ(0, std::memcmp(vectors.data(), p->data(), 16 * p->size()));
    }
}

// ---- Every status, from bad input ------------------------------------------------------------

struct StatusCase {
    aerial_status status;
    const char* text;
    const char* field;  ///< the field the error names
    std::function<aerial_status()> call;
};

TEST(CApiStatus, EveryStatusComesFromSomeBadInputWithItsText) {
    aerial_context* ctx = nullptr;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &ctx), AERIAL_OK);
    const aerial_view good_view = test_view(20000.0);
    aerial_context* viewless = nullptr;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &viewless), AERIAL_OK);
    ASSERT_EQ(aerial_context_set_view(ctx, &good_view), AERIAL_OK);

    auto ctx_holder =
        std::unique_ptr<aerial_context, void (*)(aerial_context*)>(ctx, aerial_context_destroy);
    auto viewless_holder = std::unique_ptr<aerial_context, void (*)(aerial_context*)>(
        viewless, aerial_context_destroy);

    auto headless = aerial::headless::Context::create({aerial::headless::Platform::osmesa, 8, 8});
    ASSERT_TRUE(headless.ok()) << headless.error().message;
    aerial_gl* gl = nullptr;
    ASSERT_EQ(aerial_gl_create(headless->loader(), headless->loader_user(), &gl), AERIAL_OK);
    auto gl_holder = std::unique_ptr<aerial_gl, void (*)(aerial_gl*)>(gl, aerial_gl_destroy);

    const float xyz[3] = {0, 0, 0};
    aerial_scattering s;
    std::vector<StatusCase> cases = {
        {AERIAL_OK, "ok", "", [&] { return aerial_scatter(ctx, xyz, &s); }},
        {AERIAL_ERROR_NULL_ARGUMENT, "null argument", "out",
         [&] { return aerial_scatter(ctx, xyz, nullptr); }},
        {AERIAL_ERROR_INVALID_ARGUMENT, "invalid argument", "model",
         [&] { return aerial_context_set_model(ctx, aerial_model(4)); }},
        {AERIAL_ERROR_INVALID_ATMOSPHERE, "invalid atmosphere", "mie_g",
         [&] {
             auto a = zeroed<aerial_atmosphere>();
             a.mie_g = 1.5;
             return aerial_context_set_atmosphere(ctx, &a);
         }},
        {AERIAL_ERROR_INVALID_VIEW, "invalid view", "up",
         [&] {
             aerial_view v = good_view;
             v.up[2] = 2.0;
             return aerial_context_set_view(ctx, &v);
         }},
        {AERIAL_ERROR_INVALID_VERTEX, "invalid vertex", "vertex",
         [&] {
             const double far[3] = {0, 2e12, 0};
             aerial_scattering_d d;
             return aerial_evaluate(nullptr, &good_view, AERIAL_MODEL_HEIGHT, far, &d);
         }},
        {AERIAL_ERROR_INVALID_BATCH, "invalid batch", "positions.stride_bytes",
         [&] {
             std::uint8_t fex[4];
             auto p = zeroed<aerial_positions>();
             p.x = xyz;
             p.count = 1;
             p.stride_bytes = 8;
             auto out = zeroed<aerial_outputs>();
             out.extinction_rgba8 = fex;
             return aerial_shade(ctx, &p, &out, nullptr, nullptr);
         }},
        {AERIAL_ERROR_UNKNOWN_PRESET, "unknown preset", "preset",
         [&] {
             aerial_atmosphere a;
             return aerial_atmosphere_preset("venus", &a);
         }},
        {AERIAL_ERROR_NO_VIEW, "no view set", "view",
         [&] { return aerial_scatter(viewless, xyz, &s); }},
        {AERIAL_ERROR_VERSION_MISMATCH, "version mismatch", "sizeof(aerial_view)",
         [&] {
             return aerial_check_version(AERIAL_VERSION, sizeof(aerial_atmosphere),
                                         sizeof(aerial_view) - 8, sizeof(aerial_outputs),
                                         sizeof(aerial_batch_settings), sizeof(aerial_arb_options));
         }},
        {AERIAL_ERROR_BUFFER_TOO_SMALL, "buffer too small", "capacity",
         [&] {
             char text[16];
             return aerial_arb_generate(nullptr, text, sizeof text, nullptr, nullptr);
         }},
        {AERIAL_ERROR_GL_UNAVAILABLE, "GL unavailable", "glGetString",
         [&] {
             aerial_gl* none = nullptr;
             return aerial_gl_create([](void*, const char*) -> void* { return nullptr; }, nullptr,
                                     &none);
         }},
        {AERIAL_ERROR_GL_UNSUPPORTED, "GL feature unsupported", "fixed_function_lighting",
         [&] {
             aerial_path path;
             return aerial_gl_choose_path(gl, AERIAL_PATH_SECONDARY_COLOR, 1, &path);
         }},
        {AERIAL_ERROR_ARB_PROGRAM, "ARB program error", "model",
         [&] {
             auto o = zeroed<aerial_arb_options>();
             o.model = AERIAL_MODEL_REFERENCE;
             return aerial_arb_generate(&o, nullptr, 0, nullptr, nullptr);
         }},
        {AERIAL_ERROR_OUT_OF_MEMORY, "out of memory", "",
         [&] {
             aerial::capi::inject_exception_in_next_call(
                 aerial::capi::InjectedException::bad_alloc);
             return aerial_scatter(ctx, xyz, &s);
         }},
        {AERIAL_ERROR_INTERNAL, "internal error", "",
         [&] {
             aerial::capi::inject_exception_in_next_call(
                 aerial::capi::InjectedException::standard_exception);
             return aerial_scatter(ctx, xyz, &s);
         }},
    };
    std::vector<bool> seen(AERIAL_ERROR_INTERNAL + 1, false);
    for (const StatusCase& c : cases) {
        SCOPED_TRACE(c.text);
        const aerial_status status = c.call();
        EXPECT_EQ(status, c.status) << aerial_last_error_message();
        EXPECT_STREQ(aerial_status_string(status), c.text);
        EXPECT_STREQ(aerial_last_error_field(), c.field);
        if (status == AERIAL_OK) {
            EXPECT_STREQ(aerial_last_error_message(), "");
        } else {
            const std::string message = aerial_last_error_message();
            const std::string field = c.field;
            EXPECT_EQ(message.rfind("aerial_", 0), 0u) << "starts with the function's name";
            EXPECT_NE(message.find(field.empty() ? "(): " : "(): " + field + ": "),
                      std::string::npos)
                << message;
        }
        seen[std::size_t(status)] = true;
    }
    for (std::size_t i = 0; i < seen.size(); ++i) {
        EXPECT_TRUE(seen[i]) << "no case produces status " << i << " ("
                             << aerial_status_string(aerial_status(i)) << ")";
    }
}

TEST(CApiStatus, ObjectsKeepTheMessageOfTheirLastCall) {
    ContextHandle ctx;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &ctx.p), AERIAL_OK);
    aerial_view v = test_view();
    v.meters_per_unit = -2.0;
    EXPECT_EQ(aerial_context_set_view(ctx.p, &v), AERIAL_ERROR_INVALID_VIEW);
    // The library's one style, with the C function's name: "FUNCTION(): FIELD: TEXT".
    EXPECT_STREQ(aerial_context_last_error(ctx.p),
                 "aerial_context_set_view(): meters_per_unit: expected a finite value > 0 (0 "
                 "means 1), got -2");
    EXPECT_STREQ(aerial_last_error_message(), aerial_context_last_error(ctx.p));
    EXPECT_STREQ(aerial_last_error_field(), "meters_per_unit");
    // The failed call left the context as it was: still no view.
    const float xyz[3] = {0, 0, 0};
    aerial_scattering s;
    EXPECT_EQ(aerial_scatter(ctx.p, xyz, &s), AERIAL_ERROR_NO_VIEW);
    v.meters_per_unit = 0.0;  // 0 means 1
    EXPECT_EQ(aerial_context_set_view(ctx.p, &v), AERIAL_OK);
    EXPECT_STREQ(aerial_context_last_error(ctx.p), "");
}

TEST(CApiStatus, ACppErrorKeepsItsTextUnderTheCFunctionsName) {
    auto a = zeroed<aerial_atmosphere>();
    a.mie_g = 1.5;
    EXPECT_EQ(aerial_validate_atmosphere(&a), AERIAL_ERROR_INVALID_ATMOSPHERE);
    EXPECT_STREQ(aerial_last_error_message(),
                 "aerial_validate_atmosphere(): mie_g: expected |g| < 1 (g > 0 scatters "
                 "forwards), got 1.5");
    EXPECT_EQ(aerial_validate_atmosphere(nullptr), AERIAL_ERROR_NULL_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_message(),
                 "aerial_validate_atmosphere(): atmosphere: expected a pointer, got NULL");
}

TEST(CApiVersion, MismatchesAreDetected) {
    EXPECT_EQ(AERIAL_CHECK_VERSION(), AERIAL_OK);
    const auto check = [](int version, std::size_t delta_index) {
        std::size_t sizes[5] = {sizeof(aerial_atmosphere), sizeof(aerial_view),
                                sizeof(aerial_outputs), sizeof(aerial_batch_settings),
                                sizeof(aerial_arb_options)};
        if (delta_index < 5) sizes[delta_index] += 8;
        return aerial_check_version(version, sizes[0], sizes[1], sizes[2], sizes[3], sizes[4]);
    };
    EXPECT_EQ(check(AERIAL_VERSION + 10000, 5), AERIAL_ERROR_VERSION_MISMATCH);
    EXPECT_EQ(check(AERIAL_VERSION + 100, 5), AERIAL_ERROR_VERSION_MISMATCH)
        << "before 1.0 another minor version is incompatible";
    EXPECT_EQ(check(AERIAL_VERSION + 1, 5), AERIAL_OK) << "a patch release is compatible";
    const char* fields[5] = {"sizeof(aerial_atmosphere)", "sizeof(aerial_view)",
                             "sizeof(aerial_outputs)", "sizeof(aerial_batch_settings)",
                             "sizeof(aerial_arb_options)"};
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_EQ(check(AERIAL_VERSION, i), AERIAL_ERROR_VERSION_MISMATCH);
        EXPECT_STREQ(aerial_last_error_field(), fields[i]);
    }
    EXPECT_EQ(aerial_library_version(), AERIAL_VERSION);
}

TEST(CApiExceptions, NoExceptionCrossesTheInterface) {
    using aerial::capi::InjectedException;
    ContextHandle ctx;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &ctx.p), AERIAL_OK);
    for (InjectedException kind :
         {InjectedException::bad_alloc, InjectedException::standard_exception,
          InjectedException::unknown}) {
        const aerial_status expected = kind == InjectedException::bad_alloc
                                           ? AERIAL_ERROR_OUT_OF_MEMORY
                                           : AERIAL_ERROR_INTERNAL;
        aerial_context* created = nullptr;
        aerial::capi::inject_exception_in_next_call(kind);
        EXPECT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &created), expected);
        EXPECT_EQ(created, nullptr);
        const aerial_view v = test_view();
        aerial::capi::inject_exception_in_next_call(kind);
        EXPECT_EQ(aerial_context_set_view(ctx.p, &v), expected);
        EXPECT_NE(std::string(aerial_context_last_error(ctx.p)), "");
        aerial::capi::inject_exception_in_next_call(kind);
        EXPECT_EQ(aerial_arb_generate(nullptr, nullptr, 0, nullptr, nullptr), expected);
    }
    // Bad data of every kind gives a status, never a crash or an exception.
    auto a = zeroed<aerial_atmosphere>();
    a.rayleigh_scattering[1] = std::nan("");
    EXPECT_EQ(aerial_validate_atmosphere(&a), AERIAL_ERROR_INVALID_ATMOSPHERE);
    EXPECT_STREQ(aerial_last_error_field(), "rayleigh_scattering[1]");
    EXPECT_EQ(aerial_atmosphere_from_json("{\"mie_g\": \"x\"}", &a),
              AERIAL_ERROR_INVALID_ATMOSPHERE);
    EXPECT_EQ(aerial_atmosphere_from_json("{", &a), AERIAL_ERROR_INVALID_ATMOSPHERE);
    EXPECT_EQ(aerial_validate_view(nullptr), AERIAL_ERROR_NULL_ARGUMENT);
    EXPECT_EQ(aerial_context_set_view(nullptr, nullptr), AERIAL_ERROR_NULL_ARGUMENT);
    auto settings = zeroed<aerial_batch_settings>();
    settings.kernel = aerial_kernel(3);
    const aerial_view v = test_view();
    ASSERT_EQ(aerial_context_set_view(ctx.p, &v), AERIAL_OK);
    auto p = zeroed<aerial_positions>();
    auto out = zeroed<aerial_outputs>();
    EXPECT_EQ(aerial_shade(ctx.p, &p, &out, &settings, nullptr), AERIAL_ERROR_INVALID_ARGUMENT);
    settings.kernel = AERIAL_KERNEL_SIMD;
    EXPECT_EQ(aerial_shade(ctx.p, &p, &out, &settings, nullptr), AERIAL_ERROR_INVALID_BATCH)
        << "no output";
    std::uint8_t lit[4];
    out.lit_rgba8 = lit;
    p.count = 0;
    EXPECT_EQ(aerial_shade(ctx.p, &p, &out, &settings, nullptr), AERIAL_ERROR_INVALID_BATCH)
        << "lit without lighting";
    EXPECT_STREQ(aerial_last_error_field(), "lighting");
}

// ---- GL: the C paths draw what the C++ API draws ---------------------------------------------

constexpr int kSize = 64;

/// A grid of triangles over [-1, 1]^2 (drawn with identity matrices), shaded by the engine's
/// draw callback.
struct Mesh {
    const aerial::gl::Api* api = nullptr;
    std::vector<float> xyz;
    std::vector<GLuint> indices;
};

Mesh grid_mesh(const aerial::gl::Api& api) {
    Mesh m;
    m.api = &api;
    const int n = 9;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            m.xyz.push_back(-1.0f + 2.0f * float(i) / float(n - 1));
            m.xyz.push_back(-1.0f + 2.0f * float(j) / float(n - 1));
            m.xyz.push_back(0.0f);
        }
    }
    for (int j = 0; j + 1 < n; ++j) {
        for (int i = 0; i + 1 < n; ++i) {
            const GLuint a = GLuint(j * n + i), b = a + 1, c = a + GLuint(n), d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
    }
    return m;
}

void draw_mesh(void* user) {
    const Mesh& m = *static_cast<const Mesh*>(user);
    m.api->EnableClientState(GL_VERTEX_ARRAY);
    m.api->VertexPointer(3, GL_FLOAT, 0, m.xyz.data());
    m.api->DrawElements(GL_TRIANGLES, GLsizei(m.indices.size()), GL_UNSIGNED_INT, m.indices.data());
    m.api->DisableClientState(GL_VERTEX_ARRAY);
}

class CApiGl : public ::testing::Test {
  protected:
    void SetUp() override {
        auto ctx =
            aerial::headless::Context::create({aerial::headless::Platform::osmesa, kSize, kSize});
        ASSERT_TRUE(ctx.ok()) << ctx.error().message;
        ctx_.emplace(std::move(ctx).value());
        ASSERT_EQ(aerial_gl_create(ctx_->loader(), ctx_->loader_user(), &gl_), AERIAL_OK)
            << aerial_last_error_message();
        ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HOFFMAN_PREETHAM, &scene_),
                  AERIAL_OK);
        view_ = test_view(20000.0);
        ASSERT_EQ(aerial_context_set_view(scene_, &view_), AERIAL_OK);
        mesh_ = grid_mesh(api());
    }
    void TearDown() override {
        aerial_context_destroy(scene_);
        aerial_gl_destroy(gl_);
    }
    const aerial::gl::Api& api() const { return ctx_->api(); }
    std::vector<std::uint8_t> clear_and(const std::function<void()>& draw) {
        api().ClearColor(0.2f, 0.1f, 0.3f, 1.0f);
        api().Clear(GL_COLOR_BUFFER_BIT);
        draw();
        api().Finish();
        return ctx_->read_rgba8();
    }

    std::optional<aerial::headless::Context> ctx_;
    aerial_gl* gl_ = nullptr;
    aerial_context* scene_ = nullptr;
    aerial_view view_{};
    Mesh mesh_;
};

TEST_F(CApiGl, DrawColoursDrawsWhatTheCppPathDraws) {
    const std::size_t n = mesh_.xyz.size() / 3;
    std::vector<std::uint8_t> fex(4 * n), lin(4 * n);
    auto p = zeroed<aerial_positions>();
    p.x = mesh_.xyz.data();
    p.count = n;
    auto out = zeroed<aerial_outputs>();
    out.extinction_rgba8 = fex.data();
    out.in_scattering_rgba8 = lin.data();
    auto settings = zeroed<aerial_batch_settings>();
    settings.display.exposure = 4.0f;
    ASSERT_EQ(aerial_shade(scene_, &p, &out, &settings, nullptr), AERIAL_OK);
    auto colours = zeroed<aerial_vertex_colours>();
    colours.primary = fex.data();
    colours.secondary = lin.data();
    colours.vertex_count = n;
    for (aerial_path path :
         {AERIAL_PATH_SECONDARY_COLOR, AERIAL_PATH_COMBINER, AERIAL_PATH_TWO_PASS}) {
        aerial_path chosen;
        if (aerial_gl_choose_path(gl_, path, 0, &chosen) != AERIAL_OK) {
            EXPECT_EQ(aerial_gl_choose_path(gl_, path, 0, &chosen), AERIAL_ERROR_GL_UNSUPPORTED);
            continue;
        }
        SCOPED_TRACE(aerial::gl::path_name(aerial::gl::Path(path)));
        auto options = zeroed<aerial_draw_options>();
        options.path = path;
        options.untextured = 1;
        aerial_path used = AERIAL_PATH_AUTOMATIC;
        const auto c_image = clear_and([&] {
            ASSERT_EQ(aerial_gl_draw_colours(gl_, &options, &colours, draw_mesh, &mesh_, &used),
                      AERIAL_OK)
                << aerial_gl_last_error(gl_);
        });
        EXPECT_EQ(used, path);
        aerial::gl::VertexColours v{fex.data(), lin.data(), 0, 0, n};
        aerial::gl::ApplyOptions o;
        o.path = aerial::gl::Path(path);
        o.textured = false;
        auto combiner = aerial::gl::CombinerTexture::create(api());
        if (combiner) o.combiner = &combiner.value();
        const auto cpp_image = clear_and([&] {
            ASSERT_TRUE(
                aerial::gl::draw_with_colours(api(), o, v, [&] { draw_mesh(&mesh_); }).ok());
        });
        EXPECT_EQ(c_image, cpp_image);
        // The haze is drawn: the image is not the clear colour everywhere.
        EXPECT_NE(c_image[4 * (kSize * kSize / 2)], 51);
    }
}

TEST_F(CApiGl, ArbProgramDrawsWhatTheCppProgramDraws) {
    auto options = zeroed<aerial_arb_options>();
    aerial_arb_program* program = nullptr;
    const aerial_status status = aerial_arb_program_create(gl_, &options, &program);
    if (!api().caps.vertex_program) {
        EXPECT_EQ(status, AERIAL_ERROR_GL_UNSUPPORTED);
        GTEST_SKIP() << "no GL_ARB_vertex_program";
    }
    ASSERT_EQ(status, AERIAL_OK) << aerial_last_error_message();
    auto display = zeroed<aerial_display>();
    display.exposure = 4.0f;
    ASSERT_EQ(aerial_arb_program_set_frame(program, scene_, &display), AERIAL_OK);
    auto draw = zeroed<aerial_draw_options>();
    draw.untextured = 1;
    const auto c_image = clear_and([&] {
        ASSERT_EQ(aerial_arb_program_draw(program, &draw, draw_mesh, &mesh_), AERIAL_OK)
            << aerial_arb_program_last_error(program);
    });
    const std::string text = aerial_arb_program_text(program);
    EXPECT_NE(aerial_arb_program_id(program), 0u);

    // A context of the wrong model is refused, naming it.
    aerial_context* height = nullptr;
    ASSERT_EQ(aerial_context_create(nullptr, AERIAL_MODEL_HEIGHT, &height), AERIAL_OK);
    ASSERT_EQ(aerial_context_set_view(height, &view_), AERIAL_OK);
    EXPECT_EQ(aerial_arb_program_set_frame(program, height, &display),
              AERIAL_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(aerial_last_error_field(), "frame.model");
    aerial_context_destroy(height);
    aerial_arb_program_destroy(program);

    const auto generated = aerial::generate_arb_program({});
    ASSERT_TRUE(generated.ok());
    EXPECT_EQ(text, generated->text);
    auto cpp = aerial::gl::ArbVertexProgram::create(api(), *generated);
    ASSERT_TRUE(cpp.ok());
    const auto frame = aerial::prepare_frame<float>(aerial::Atmosphere{}, cpp_view(view_),
                                                    aerial::Model::hoffman_preetham);
    ASSERT_FALSE(cpp->set_parameters(
                        *aerial::arb_program_parameters(*frame, {4.0f, aerial::ToneCurve::clamp}))
                     .has_value());
    aerial::gl::ApplyOptions o;
    o.textured = false;
    const auto cpp_image =
        clear_and([&] { ASSERT_TRUE(cpp->draw([&] { draw_mesh(&mesh_); }, o).ok()); });
    EXPECT_EQ(c_image, cpp_image);
}

TEST_F(CApiGl, AThrowingDrawCallbackBecomesAStatus) {
    std::vector<std::uint8_t> fex(4 * 3, 255), lin(4 * 3, 0);
    auto colours = zeroed<aerial_vertex_colours>();
    colours.primary = fex.data();
    colours.secondary = lin.data();
    colours.vertex_count = 3;
    aerial_draw_function thrower = [](void*) { throw std::runtime_error("engine draw failed"); };
    EXPECT_EQ(aerial_gl_draw_colours(gl_, nullptr, &colours, thrower, nullptr, nullptr),
              AERIAL_ERROR_INTERNAL);
    EXPECT_NE(std::string(aerial_gl_last_error(gl_)).find("engine draw failed"), std::string::npos)
        << aerial_gl_last_error(gl_);
    // GL is usable and unchanged afterwards: the colour array is off again.
    EXPECT_FALSE(api().IsEnabled(GL_COLOR_ARRAY));
}

}  // namespace
