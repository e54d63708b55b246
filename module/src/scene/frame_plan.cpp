// The GL-free half of a frame of the scene renderer (frame_plan.hpp).
#include "frame_plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "../common/error_text.hpp"
#include "aerial/phase.hpp"
#include "aerial/sun.hpp"

namespace aerial::scene::detail {
namespace {

/// Vertices of a node compared between the 2002 model and the frame's model (besides the 8
/// corners of its box) when the policy chooses a method.
constexpr std::size_t kMethodSampleVertices = 25;
/// The ambient sky light is estimated again when the sun has turned this much (rad) since the
/// last estimate (or the atmosphere or up axis changed); between estimates it stays the same, so
/// that small sun moves keep the colour caches (any change of the ambient invalidates them).
constexpr double kAmbientSunStepRad = 0.25 * kPi / 180.0;
double max3(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

/// Sky irradiance on a level surface at sea level below the eye: aerial::sky_ambient (the
/// height-chained sky integrated with the cosine weight over the upper hemisphere; terrain
/// occlusion ignored). Sea level, not the eye, so that it changes only with the sun and the
/// atmosphere (a flying eye keeps cached colours). 8 x 16 directions (the sample game's): within
/// 7 % of a 64 x 128 integral from the zenith sun to below the horizon, about 2.3 ms a call.
glm::vec3 sea_level_sky_ambient(const FrameSettings& s) {
    SkyAmbientOptions options;
    options.elevation_steps = 8;
    options.azimuth_steps = 16;
    const double sin_elevation = glm::dot(glm::normalize(s.sun_dir), glm::normalize(s.up));
    auto ambient = aerial::sky_ambient(s.atmosphere, 0.0,
                                       std::asin(std::clamp(sin_elevation, -1.0, 1.0)), options);
    return ambient ? glm::vec3(*ambient) : glm::vec3(0.0f);
}

/// Upper bound, in 8-bit steps, on how much scattering changes any output of a node inside
/// `bounds` (F_ex against 1, L_in against 0): from the largest optical depth.
double scattering_bound_lsb(const Frame<double>& frame, const MeshBounds& bounds,
                            const Display& display, double lit_factor_max) {
    const glm::dvec3 eye = frame.view.eye;
    const glm::dvec3 up = frame.view.up;
    const double mpu = frame.view.meters_per_unit;
    const glm::dvec3 lo = bounds.box_min, hi = bounds.box_max;
    double distance_m = 0.0, lowest = glm::dot(eye, up) * mpu;
    const bool box = std::isfinite(lo.x) && std::isfinite(hi.x);
    if (box) {
        for (int c = 0; c < 8; ++c) {
            const glm::dvec3 p{(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
            distance_m = std::max(distance_m, glm::length(p - eye) * mpu);
            lowest = std::min(lowest, glm::dot(p, up) * mpu);
        }
    } else {
        distance_m = (glm::length(bounds.centre - eye) + bounds.radius) * mpu;
        lowest = std::min(lowest, (glm::dot(bounds.centre, up) - bounds.radius) * mpu);
    }
    if (!std::isfinite(distance_m)) return std::numeric_limits<double>::infinity();
    // The sphere falls away below the tangent plane: the lowest altitude is lower still.
    lowest -= distance_m * distance_m / (2.0 * frame.atmosphere.planet_radius_m);
    const double h = std::max(lowest, frame.min_altitude_m);
    const Atmosphere& a = frame.atmosphere;
    // Densities relative to sea level, at least 1 (the 2002 model uses sea level everywhere).
    const double rho_r = std::max(1.0, std::exp(-h / a.rayleigh_scale_height_m));
    const double rho_m = std::max(1.0, std::exp(-h / a.mie_scale_height_m));
    const double g = std::abs(a.mie_g);
    const double rayleigh_phase_max = 3.0 / (8.0 * kPi);
    const double mie_phase_max = (1.0 + g) / (4.0 * kPi * (1.0 - g) * (1.0 - g));
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double tau =
            (a.rayleigh_scattering[c] * rho_r + a.mie_extinction()[c] * rho_m) * distance_m;
        const double extinction = 255.0 * tau * std::max(1.0, lit_factor_max);
        const double in_scattering = 255.0 * double(display.exposure) * a.sun_irradiance[c] *
                                     (a.rayleigh_scattering[c] * rho_r * rayleigh_phase_max +
                                      a.mie_scattering[c] * rho_m * mie_phase_max) *
                                     distance_m;
        worst = std::max(worst, std::max(extinction, in_scattering));
    }
    return worst;
}

/// 8-bit display outputs of one point: primary (F_ex, or the lit colour) and L_in.
struct PointOutputs {
    glm::vec3 primary, secondary;
};

PointOutputs point_outputs(const Frame<float>& frame, const glm::vec3& p, const glm::vec3* normal,
                           bool lit, const glm::vec3& albedo, const glm::vec3& ambient,
                           const Display& display) {
    const Scattering<float> s = scatter(frame, p);
    PointOutputs out;
    for (int c = 0; c < 3; ++c) {
        float primary = s.extinction[c];
        if (lit) {
            const float ndl =
                normal ? std::max(0.0f, glm::dot(*normal, frame.sun_dir)) : 1.0f;  // corners: 1
            primary = display_value(display, lit_value(s.extinction[c], albedo[c],
                                                       s.sun_irradiance[c], ndl, ambient[c]));
        }
        out.primary[c] = 255.0f * std::clamp(primary, 0.0f, 1.0f);
        out.secondary[c] = 255.0f * display_value(display, s.in_scattering[c]);
    }
    return out;
}

/// The largest 8-bit difference between the 2002 model and `frame`'s over the node's samples,
/// or the first one above `stop_above` (the policy only asks whether it is within its target).
double model_difference_lsb(const Frame<float>& hp, const Frame<float>& frame, const NodeState& st,
                            bool lit, const glm::vec3& albedo, const glm::vec3& ambient,
                            const Display& display, double stop_above) {
    double worst = 0.0;
    const auto compare = [&](const glm::vec3& p, const glm::vec3* n) {
        const PointOutputs a = point_outputs(hp, p, n, lit, albedo, ambient, display);
        const PointOutputs b = point_outputs(frame, p, n, lit, albedo, ambient, display);
        for (int c = 0; c < 3; ++c) {
            worst = std::max(worst, double(std::abs(a.primary[c] - b.primary[c])));
            worst = std::max(worst, double(std::abs(a.secondary[c] - b.secondary[c])));
        }
    };
    const glm::dvec3 lo = st.bounds.box_min, hi = st.bounds.box_max;
    for (int c = 0; c < 8; ++c) {
        compare(glm::vec3((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z),
                nullptr);
        if (worst > stop_above) return worst;
    }
    const std::size_t n = st.positions.size() / 3;
    const std::size_t step = std::max<std::size_t>(1, n / kMethodSampleVertices);
    for (std::size_t i = 0; i < n; i += step) {
        const glm::vec3 p(st.positions[3 * i], st.positions[3 * i + 1], st.positions[3 * i + 2]);
        const glm::vec3 normal =
            st.normals.empty()
                ? glm::vec3(0.0f)
                : glm::vec3(st.normals[3 * i], st.normals[3 * i + 1], st.normals[3 * i + 2]);
        compare(p, st.normals.empty() ? nullptr : &normal);
        if (worst > stop_above) return worst;
    }
    return worst;
}

/// The cache key of `m` for a node, prepared once per frame and model (the albedo is set per
/// node on a copy; unlit nodes have albedo 1 and no ambient).
PreparedShadingKey key_for(FrameInputs& f, Model m, const glm::vec3& albedo, bool lit) {
    auto it = f.keys.find(m);
    if (it == f.keys.end()) {
        ShadingKey key{f.settings->atmosphere, f.view, m, f.settings->display};
        key.ambient = f.ambient;
        auto prepared = prepare_shading_key(key);
        it = f.keys.emplace(m, std::move(prepared.value())).first;
    }
    PreparedShadingKey k = it->second;
    k.key.albedo = lit ? albedo : glm::vec3(1.0f);
    if (!lit) k.key.ambient = glm::vec3(0.0f);
    return k;
}

}  // namespace

Result<FrameInputs> prepare_frame_inputs(const Node& root, const Camera& camera,
                                         const FrameSettings& settings, Backend backend,
                                         ValidatedMeshes& validated) {
    using aerial::detail::from;
    using aerial::detail::invalid;
    using aerial::detail::number;
    if (auto e = validate(root, validated)) return from(kRender, *e);
    if (auto e = validate(camera)) return from(kRender, *e);
    if (!(settings.error_target_lsb >= 0.0)) {
        return invalid(kRender, "error_target_lsb", "a value >= 0",
                       number(settings.error_target_lsb));
    }
    if (backend == Backend::arb && is_numerical(settings.model)) {
        return invalid(kRender, "model",
                       "hoffman-preetham or height (the models the arb backend has programs for)",
                       std::string(model_name(settings.model)));
    }
    if (backend == Backend::arb && settings.display.tone != ToneCurve::clamp) {
        return invalid(kRender, "display.tone", "clamp (the only tone curve of the arb backend)",
                       std::string(tone_curve_name(settings.display.tone)));
    }
    if (!(settings.display.exposure > 0.0f) || !std::isfinite(settings.display.exposure)) {
        return invalid(kRender, "display.exposure", "a finite value > 0",
                       number(settings.display.exposure));
    }
    FrameInputs f;
    f.settings = &settings;
    f.backend = backend;
    f.view.eye = camera.eye;
    f.view.sun_dir = settings.sun_dir;
    f.view.up = settings.up;
    f.view.meters_per_unit = settings.meters_per_unit;
    auto hp = prepare_frame<float>(settings.atmosphere, f.view, Model::hoffman_preetham);
    if (!hp) return from(kRender, hp.error());
    auto quality = prepare_frame<float>(settings.atmosphere, f.view, settings.model);
    if (!quality) return from(kRender, quality.error());
    auto bound = prepare_frame<double>(settings.atmosphere, f.view, settings.model);
    if (!bound) return from(kRender, bound.error());
    f.hoffman_preetham = std::move(hp).value();
    f.model = std::move(quality).value();
    f.bound = std::move(bound).value();
    return f;
}

glm::vec3 frame_ambient(SkyAmbientCache& cache, const FrameSettings& settings) {
    const glm::vec3 given = settings.ambient;
    if (given.r >= 0.0f && given.g >= 0.0f && given.b >= 0.0f) return given;
    if (!cache.valid || glm::dot(cache.sun_dir, settings.sun_dir) < std::cos(kAmbientSunStepRad) ||
        cache.up != settings.up || cache.atmosphere != settings.atmosphere) {
        cache.ambient = sea_level_sky_ambient(settings);
        cache.atmosphere = settings.atmosphere;
        cache.sun_dir = settings.sun_dir;
        cache.up = settings.up;
        cache.valid = true;
    }
    return cache.ambient;
}

void prepare_shading_keys(FrameInputs& f) {
    if (f.backend == Backend::none) return;
    key_for(f, Model::hoffman_preetham, glm::vec3(1.0f), false);
    key_for(f, f.settings->model, glm::vec3(1.0f), false);
}

void add_counts(FrameReport& total, const FrameReport& part) {
    total.vertices_shaded += part.vertices_shaded;
    total.vertices_drawn += part.vertices_drawn;
    total.culled += part.culled;
    total.skipped += part.skipped;
    total.cache_hits += part.cache_hits;
    total.shaded_hoffman_preetham += part.shaded_hoffman_preetham;
    total.shaded_height += part.shaded_height;
    total.shaded_reference += part.shaded_reference;
}

NodePlan plan_node(FrameInputs& f, NodeState& st, const Node& node) {
    const FrameSettings& settings = *f.settings;
    NodePlan plan;
    plan.lit = node.kind == NodeKind::terrain;
    const glm::vec3 albedo = node.albedo;
    double light_max = max3(settings.atmosphere.sun_irradiance) + max3(glm::dvec3(f.ambient));
    if (f.second) {
        light_max += max3(f.second->settings->atmosphere.sun_irradiance) +
                     max3(glm::dvec3(f.second->ambient));
    }
    const double lit_max =
        plan.lit ? double(settings.display.exposure) * max3(glm::dvec3(albedo)) * light_max : 1.0;
    // 0. The none backend computes no scattering at all.
    if (f.backend == Backend::none) {
        plan.method = Method::unshaded;
        plan.model = settings.model;
        return plan;
    }
    // 1. Negligible scattering.
    double bound = scattering_bound_lsb(f.bound, st.bounds, settings.display, lit_max);
    if (f.second)
        bound += scattering_bound_lsb(f.second->bound, st.bounds, settings.display, lit_max);
    if (settings.policy && bound < kSkipBelowLsb) {
        plan.method = Method::skipped;
        plan.model = st.model;
        return plan;
    }
    // 2. Cached colours (cpu) or a cached choice (arb).
    const bool cpu = f.backend == Backend::cpu;
    if (f.second) {
        // Two lights: shaded with settings.model for each, nothing kept for the next frame.
        st.model = settings.model;
        st.cache.invalidate();
        st.has_choice = false;
        plan.method = method_of(settings.model);
        plan.model = settings.model;
        return plan;
    }
    // (Never for adaptive nodes: their colours morph from one update to the next.)
    if (settings.policy && !node.adaptive && (cpu ? st.has_colours : st.has_choice)) {
        if (!st.cache.needs_update(key_for(f, st.model, albedo, plan.lit))) {
            plan.method = cpu ? Method::cached : method_of(st.model);
            plan.model = st.model;
            return plan;
        }
    }
    // 3. The cheapest model meeting the target.
    Model model = settings.model;
    if (settings.policy && settings.model != Model::hoffman_preetham &&
        model_difference_lsb(f.hoffman_preetham, f.model, st, plan.lit, albedo, f.ambient,
                             settings.display,
                             settings.error_target_lsb) <= settings.error_target_lsb) {
        model = Model::hoffman_preetham;
    }
    st.model = model;
    st.cache.mark_shaded(key_for(f, model, albedo, plan.lit));
    if (!cpu) st.has_choice = true;
    plan.method = method_of(model);
    plan.model = model;
    return plan;
}

float vertex_cosine(const NodeState& st, std::size_t i, const glm::dvec3& light_dir) {
    if (st.normals.empty()) return 1.0f;
    return std::max(0.0f, st.normals[3 * i] * float(light_dir.x) +
                              st.normals[3 * i + 1] * float(light_dir.y) +
                              st.normals[3 * i + 2] * float(light_dir.z));
}

void skipped_colours(const FrameInputs& f, NodeState& st, bool lit, const glm::vec3& albedo) {
    const FrameSettings& settings = *f.settings;
    const glm::vec3 sun_e = f.hoffman_preetham.sun_irradiance_eye;
    // The second light: its direction and E at the eye, and its skylight.
    const glm::dvec3 moon_dir = f.second ? f.second->settings->sun_dir : glm::dvec3(0.0);
    const glm::vec3 moon_e = f.second ? f.second->model.sun_irradiance_eye : glm::vec3(0.0f);
    const glm::vec3 ambient = f.ambient + (f.second ? f.second->ambient : glm::vec3(0.0f));
    const glm::dvec3 moon_key = moon_dir * double(moon_e.g);
    if (!st.skip_colours || st.skip_sun != settings.sun_dir || st.skip_light != ambient ||
        st.skip_moon != moon_key) {
        const std::size_t n = st.positions.size() / 3;
        for (std::size_t i = 0; i < n; ++i) {
            const float ndl = lit ? vertex_cosine(st, i, settings.sun_dir) : 1.0f;
            const float ndm = lit && f.second ? vertex_cosine(st, i, moon_dir) : 0.0f;
            for (int c = 0; c < 3; ++c) {
                const float light = sun_e[c] * ndl + moon_e[c] * ndm;
                const float v =
                    lit ? display_value(settings.display,
                                        lit_value(1.0f, albedo[c], 1.0f, light, ambient[c]))
                        : 1.0f;
                st.primary[4 * i + std::size_t(c)] = to_unorm8(v);
                st.secondary[4 * i + std::size_t(c)] = 0;
            }
        }
        st.skip_colours = true;
        st.skip_sun = settings.sun_dir;
        st.skip_light = ambient;
        st.skip_moon = moon_key;
    }
    st.has_colours = false;  // the scattering colours are gone
    st.has_choice = false;
    st.cache.invalidate();
}

Method method_of(Model model) {
    switch (model) {
        case Model::hoffman_preetham:
            return Method::hoffman_preetham;
        case Model::height:
            return Method::height;
        case Model::single_scattering:
        case Model::reference:
            return Method::reference;
    }
    return Method::height;
}

void update_geometry(NodeState& st, const Node& node, const glm::dmat4& world) {
    const std::shared_ptr<const MeshData>& source = node.adaptive ? st.adaptive_data : node.mesh;
    if (st.mesh == source && st.world == world) return;
    st.mesh = source;
    st.world = world;
    const MeshData& mesh = *source;
    const std::size_t n = mesh.vertex_count();
    st.positions.resize(3 * n);
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec4 p = world * glm::dvec4(mesh.positions[3 * i], mesh.positions[3 * i + 1],
                                                mesh.positions[3 * i + 2], 1.0);
        st.positions[3 * i] = float(p.x);
        st.positions[3 * i + 1] = float(p.y);
        st.positions[3 * i + 2] = float(p.z);
    }
    st.normals.clear();
    if (!mesh.normals.empty()) {
        st.normals.resize(3 * n);
        for (std::size_t i = 0; i < n; ++i) {
            glm::dvec3 v = normal_matrix * glm::dvec3(mesh.normals[3 * i], mesh.normals[3 * i + 1],
                                                      mesh.normals[3 * i + 2]);
            const double length = glm::length(v);
            v = length > 0.0 ? v / length : glm::dvec3(0.0, 0.0, 1.0);
            st.normals[3 * i] = float(v.x);
            st.normals[3 * i + 1] = float(v.y);
            st.normals[3 * i + 2] = float(v.z);
        }
    }
    st.bounds = mesh_bounds(Positions::aos(st.positions.data(), n));
    st.primary.assign(4 * n, 255);
    st.secondary.assign(4 * n, 0);
    st.has_colours = false;
    st.has_choice = false;
    st.skip_colours = false;
    st.cache.invalidate();
    st.cache.bounds = st.bounds;
}

bool has_kind(const Node& root, NodeKind kind) {
    bool found = false;
    traverse(root, [&](const Node& n, const glm::dmat4&) { found = found || n.kind == kind; });
    return found;
}

}  // namespace aerial::scene::detail
