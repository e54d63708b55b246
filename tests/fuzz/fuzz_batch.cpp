// libFuzzer target: the public batch API with arbitrary floats. The bytes give the atmosphere,
// the view (eye, sun, up, units), the model, the display, the kernel, the outputs asked for, the
// vertices and their normals. When prepare_frame and shade_into accept the inputs, every float
// output must be finite (__builtin_trap otherwise) and the RGBA8 codes of the one-pass path must
// be those of the float values under the 8-bit rule.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/scattering.hpp"
#include "batch_outputs.hpp"
#include "fuzz_check.hpp"

namespace {

/// Without the higher orders' table: a fuzzed atmosphere can take minutes to tabulate
/// (aerial::FrameOptions); the term's math is fuzzed through the stability sweeps.
const aerial::FrameOptions kNoTables{false};

using aerial::fuzz::check;

// A value near `typical` (scaled by up to 1e6 either way, either sign), any double, or `typical`.
double number(FuzzedDataProvider& in, double typical) {
    switch (in.ConsumeIntegralInRange(0, 3)) {
        case 0:
            return typical;
        case 1:
            return in.ConsumeFloatingPoint<double>();
        case 2:
            return typical * std::pow(10.0, in.ConsumeFloatingPointInRange(-6.0, 6.0));
        default:
            return in.ConsumeFloatingPointInRange(-2.0, 2.0) * typical;
    }
}

glm::dvec3 vector(FuzzedDataProvider& in, const glm::dvec3& typical) {
    return {number(in, typical.x), number(in, typical.y), number(in, typical.z)};
}

// A unit vector most of the time (validation wants unit length), anything sometimes.
glm::dvec3 direction(FuzzedDataProvider& in, const glm::dvec3& typical) {
    glm::dvec3 v = vector(in, typical);
    const double length = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    if (in.ConsumeBool() && length > 0.0 && std::isfinite(length)) v /= length;
    return v;
}

float coordinate(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange(0, 2)) {
        case 0:
            return in.ConsumeFloatingPoint<float>();
        case 1:
            return in.ConsumeFloatingPointInRange(-1e5f, 1e5f);
        default:
            return in.ConsumeFloatingPointInRange(-1e8f, 1e8f);
    }
}

std::uint8_t code(float v) { return aerial::to_unorm8(v); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);

    aerial::Atmosphere a;
    a.rayleigh_scattering = vector(in, a.rayleigh_scattering);
    a.mie_scattering = vector(in, a.mie_scattering);
    a.mie_absorption = vector(in, glm::dvec3(1e-6));
    a.mie_g = number(in, a.mie_g);
    a.rayleigh_scale_height_m = number(in, a.rayleigh_scale_height_m);
    a.mie_scale_height_m = number(in, a.mie_scale_height_m);
    a.planet_radius_m = number(in, a.planet_radius_m);
    a.atmosphere_radius_m =
        in.ConsumeBool() ? a.planet_radius_m + number(in, 60e3) : number(in, a.atmosphere_radius_m);
    a.sun_irradiance = vector(in, a.sun_irradiance);

    aerial::View view;
    view.eye = vector(in, glm::dvec3(100.0, -50.0, 2.0));
    view.sun_dir = direction(in, glm::dvec3(0.0, 0.6, 0.8));
    view.up = in.ConsumeBool() ? direction(in, view.up) : view.up;
    view.meters_per_unit = number(in, 1.0);

    // hoffman-preetham, height or single-scattering: `reference` adds a table computed per
    // atmosphere (seconds each), which fuzz_atmosphere_json covers at a small resolution.
    const auto model = static_cast<aerial::Model>(in.ConsumeIntegralInRange(0, 2));
    aerial::BatchSettings settings;
    settings.kernel = static_cast<aerial::Kernel>(in.ConsumeIntegralInRange(0, 2));
    settings.display.exposure = float(number(in, 8.0));
    settings.display.tone =
        in.ConsumeBool() ? aerial::ToneCurve::exponential : aerial::ToneCurve::clamp;
    settings.threads = 1;

    // The numerical models integrate per vertex (up to 1024 steps along the view ray, each with a
    // sun ray of as many): fewer vertices keep inputs fast under the sanitizers.
    const std::size_t max_count = aerial::is_numerical(model) ? 2 : 70;
    const std::size_t count = in.ConsumeIntegralInRange<std::size_t>(0, max_count);
    std::vector<float> positions(3 * count), normals(3 * count);
    for (float& v : positions) v = coordinate(in);
    for (float& v : normals) v = in.ConsumeFloatingPointInRange(-1.0f, 1.0f);
    aerial::Lighting lighting;
    lighting.normals = normals.data();
    lighting.ambient = glm::vec3(vector(in, glm::dvec3(0.1)));
    lighting.albedo = glm::vec3(vector(in, glm::dvec3(0.5)));

    auto frame = aerial::prepare_frame<float>(a, view, model, kNoTables);
    if (!frame) return 0;
    check(!aerial::validate(a) && !aerial::validate(view), "prepare_frame accepted bad input");

    const std::size_t n = count;
    std::vector<float> fex(3 * n), lin(3 * n), esun(3 * n);
    std::vector<std::uint8_t> fex8(4 * n), lit8(4 * n), lin8(4 * n);
    aerial::BatchOutputs out = aerial_test::floats_and_codes(fex, lin, esun, fex8, lin8);
    const bool lit = in.ConsumeBool();
    if (lit) {
        out.lit_rgba8 = lit8.data();
        settings.lighting = &lighting;
    }
    const auto positions_in = aerial::Positions::aos(positions.data(), n);
    auto stats = aerial::shade_into(*frame, positions_in, out, settings);
    if (!stats) return 0;
    check(stats->vertices == n && stats->invalid_vertices <= n, "wrong BatchStats");
    for (std::size_t i = 0; i < 3 * n; ++i) {
        if (!std::isfinite(fex[i]) || !std::isfinite(lin[i]) || !std::isfinite(esun[i])) {
            // What the input was, for the report (the artifact alone is opaque bytes).
            std::fprintf(stderr,
                         "model %d kernel %d vertex %zu (%g %g %g) fex %g lin %g esun %g\n"
                         "beta_R %g %g %g beta_M %g %g %g abs %g %g %g g %g H_R %g H_M %g "
                         "R %g R_top %g E %g %g %g\neye %g %g %g sun %g %g %g up %g %g %g "
                         "m/unit %g exposure %g\n",
                         int(model), int(settings.kernel), i / 3, double(positions[i / 3 * 3]),
                         double(positions[i / 3 * 3 + 1]), double(positions[i / 3 * 3 + 2]),
                         double(fex[i]), double(lin[i]), double(esun[i]), a.rayleigh_scattering.x,
                         a.rayleigh_scattering.y, a.rayleigh_scattering.z, a.mie_scattering.x,
                         a.mie_scattering.y, a.mie_scattering.z, a.mie_absorption.x,
                         a.mie_absorption.y, a.mie_absorption.z, a.mie_g, a.rayleigh_scale_height_m,
                         a.mie_scale_height_m, a.planet_radius_m, a.atmosphere_radius_m,
                         a.sun_irradiance.x, a.sun_irradiance.y, a.sun_irradiance.z, view.eye.x,
                         view.eye.y, view.eye.z, view.sun_dir.x, view.sun_dir.y, view.sun_dir.z,
                         view.up.x, view.up.y, view.up.z, view.meters_per_unit,
                         double(settings.display.exposure));
        }
        check(std::isfinite(fex[i]), "non-finite F_ex from accepted inputs");
        check(std::isfinite(lin[i]), "non-finite L_in from accepted inputs");
        check(std::isfinite(esun[i]), "non-finite E_sun from accepted inputs");
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            check(fex8[4 * i + c] == code(fex[3 * i + c]), "F_ex RGBA8 off its float value");
        }
    }

    // Only the codes: the one-pass path (hoffman-preetham on a SIMD kernel) must give the codes
    // the float path gave, within one step (its arithmetic is reordered, not reduced).
    std::vector<std::uint8_t> fex8_only(4 * n), lin8_only(4 * n);
    aerial::BatchOutputs codes;
    codes.extinction_rgba8 = fex8_only.data();
    codes.in_scattering_rgba8 = lin8_only.data();
    settings.lighting = nullptr;
    stats = aerial::shade_into(*frame, positions_in, codes, settings);
    check(stats.ok(), "shade_into rejected codes only after accepting all outputs");
    for (std::size_t i = 0; i < 4 * n; ++i) {
        check(std::abs(int(fex8_only[i]) - int(fex8[i])) <= 1, "one-pass F_ex code differs");
        check(std::abs(int(lin8_only[i]) - int(lin8[i])) <= 1, "one-pass L_in code differs");
    }
    return 0;
}
