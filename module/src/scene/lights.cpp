// The frame's lights: the sun and FrameSettings::moon (lights.hpp).
#include "lights.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/batch.hpp"
#include "aerial/night.hpp"
#include "aerial/sun.hpp"

namespace aerial::scene::detail {
namespace {

float max3(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

bool given_ambient(const FrameSettings& s) {
    return s.ambient.r >= 0.0f && s.ambient.g >= 0.0f && s.ambient.b >= 0.0f;
}

/// The light's sky ambient at sea level (frame_ambient's estimate, whatever the caller gave).
glm::vec3 estimated_ambient(SkyAmbientCache& cache, FrameSettings s) {
    s.ambient = glm::vec3(-1.0f);
    return frame_ambient(cache, s);
}

/// The largest 8-bit step a light adds to the frame, by the rule of FrameSettings::moon.
double light_steps(const FrameSettings& s, const glm::vec3& sky, const glm::dvec3& eye) {
    const glm::dvec3 up = glm::normalize(s.up);
    const double altitude = std::max(
        0.0, altitude_above_sphere(eye * s.meters_per_unit, up, s.atmosphere.planet_radius_m));
    const double sin_elevation = std::clamp(glm::dot(glm::normalize(s.sun_dir), up), -1.0, 1.0);
    const glm::dvec3 e =
        sun_irradiance_at_altitude(s.atmosphere, altitude, std::asin(sin_elevation));
    const double brightest = std::max(e.x, std::max(e.y, e.z)) + kSkyPeakFactor * max3(sky);
    return 255.0 * double(s.display.exposure) * brightest;
}

}  // namespace

std::optional<Error> validate_moon(const FrameSettings& settings) {
    if (!settings.moon) return std::nullopt;
    using aerial::detail::invalid;
    const Moonlight& moon = *settings.moon;
    const double length = glm::length(moon.dir);
    if (!(length > 0.0) || !std::isfinite(length)) {
        return invalid(kRender, "moon.dir", "a finite non-zero vector",
                       aerial::detail::vector(moon.dir));
    }
    if (!(moon.fraction >= 0.0 && moon.fraction <= kMaxMoonFraction)) {
        return invalid(kRender, "moon.fraction",
                       "a value in [0, " + aerial::detail::number(kMaxMoonFraction) +
                           "] (the moon's light as a fraction of the sun's)",
                       aerial::detail::number(moon.fraction));
    }
    return std::nullopt;
}

FrameSettings moon_settings(const FrameSettings& settings) {
    FrameSettings moon = settings;
    moon.sun_dir = glm::normalize(settings.moon->dir);
    moon.atmosphere = moonlit(settings.atmosphere, settings.moon->fraction);
    moon.moon.reset();
    return moon;
}

FrameLights choose_lights(LightState& state, const FrameSettings& settings, const glm::dvec3& eye) {
    FrameLights out;
    out.first = &settings;
    // Settings render() is about to reject: the sun alone (prepare_frame_inputs names the error).
    View view;
    view.eye = eye;
    view.sun_dir = settings.sun_dir;
    view.up = settings.up;
    view.meters_per_unit = settings.meters_per_unit;
    if (validate(settings.atmosphere) || validate(view) || !(settings.display.exposure > 0.0f) ||
        !std::isfinite(settings.display.exposure)) {
        return out;
    }
    const bool given = given_ambient(settings);
    const glm::vec3 sun_sky = estimated_ambient(state.sun_ambient, settings);
    out.first_ambient = given ? settings.ambient : sun_sky;
    if (!settings.moon || !(settings.moon->fraction > 0.0)) return out;
    state.moon = moon_settings(settings);
    const glm::vec3 moon_sky = estimated_ambient(state.moon_ambient, state.moon);
    const double sun_steps = light_steps(settings, sun_sky, eye);
    const double moon_steps = light_steps(state.moon, moon_sky, eye);
    const bool sun_counts = !settings.policy || sun_steps >= 0.5;
    const bool moon_counts = !settings.policy || moon_steps >= 0.5;
    if (sun_counts && moon_counts) {
        out.lights = Lights::both;
        out.second = &state.moon;
        out.second_ambient = given ? glm::vec3(0.0f) : moon_sky;
    } else if (!sun_counts && (moon_counts || moon_steps > sun_steps)) {
        out.lights = Lights::moon;
        out.first = &state.moon;
        out.first_ambient = given ? settings.ambient : moon_sky;
    }
    return out;
}

std::optional<Error> prepare_second_light(FrameInputs& f, const FrameSettings& moon,
                                          const glm::vec3& ambient) {
    View view = f.view;
    view.sun_dir = moon.sun_dir;
    auto model = prepare_frame<float>(moon.atmosphere, view, moon.model);
    if (!model) return aerial::detail::from(kRender, model.error());
    auto bound = prepare_frame<double>(moon.atmosphere, view, moon.model);
    if (!bound) return aerial::detail::from(kRender, bound.error());
    SecondLight second;
    second.settings = &moon;
    second.model = std::move(model).value();
    second.bound = std::move(bound).value();
    second.ambient = ambient;
    f.second = std::move(second);
    return std::nullopt;
}

namespace {

/// One light's floats for a node: F_ex, L_in and E (3 per vertex each).
struct LightFloats {
    std::vector<float> extinction, in_scattering, irradiance;
};

std::optional<Error> shade_floats(const Frame<float>& frame, const NodeState& st,
                                  LightFloats& out) {
    const std::size_t n = st.positions.size() / 3;
    out.extinction.resize(3 * n);
    out.in_scattering.resize(3 * n);
    out.irradiance.resize(3 * n);
    BatchOutputs outputs;
    outputs.extinction_rgb = out.extinction.data();
    outputs.in_scattering_rgb = out.in_scattering.data();
    outputs.sun_irradiance_rgb = out.irradiance.data();
    BatchSettings settings;
    settings.threads = 1;  // nodes are shaded on the worker threads already
    auto stats = shade_into(frame, Positions::aos(st.positions.data(), n), outputs, settings);
    if (!stats) return stats.error();
    return std::nullopt;
}

}  // namespace

std::optional<Error> shade_two_lights(const FrameInputs& f, NodeState& st, bool lit,
                                      const glm::vec3& albedo) {
    LightFloats sun, moon;
    if (auto e = shade_floats(f.model, st, sun)) return e;
    if (auto e = shade_floats(f.second->model, st, moon)) return e;
    const Display& display = f.settings->display;
    const glm::dvec3 sun_dir = f.settings->sun_dir, moon_dir = f.second->settings->sun_dir;
    const glm::vec3 ambient = f.ambient + f.second->ambient;
    const std::size_t n = st.positions.size() / 3;
    for (std::size_t i = 0; i < n; ++i) {
        const float ndl = lit ? vertex_cosine(st, i, sun_dir) : 0.0f;
        const float ndm = lit ? vertex_cosine(st, i, moon_dir) : 0.0f;
        std::uint8_t primary[3], secondary[3];
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * i + std::size_t(c);
            const float light = sun.irradiance[k] * ndl + moon.irradiance[k] * ndm;
            primary[c] =
                lit ? to_unorm8(display_value(display, lit_value(sun.extinction[k], albedo[c], 1.0f,
                                                                 light, ambient[c])))
                    : to_unorm8(sun.extinction[k]);
            secondary[c] =
                to_unorm8(display_value(display, sun.in_scattering[k] + moon.in_scattering[k]));
        }
        store_colour(&st.primary[4 * i], ColourFormat::rgba8, primary[0], primary[1], primary[2],
                     255);
        store_colour(&st.secondary[4 * i], ColourFormat::rgba8, secondary[0], secondary[1],
                     secondary[2], 255);
    }
    return std::nullopt;
}

}  // namespace aerial::scene::detail
