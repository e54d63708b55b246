// The scenes aerial-tess grades meshes on: see aerial/validation/tess_scenes.hpp.
#include "aerial/validation/tess_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "aerial/atmosphere.hpp"
#include "common/error_text.hpp"

namespace aerial::validation {
namespace {

using Json = nlohmann::json;
constexpr const char* kRead = "validation::read_tess_scenes";
constexpr const char* kMake = "validation::make_tess_scene";
constexpr double kPi = 3.14159265358979323846;

/// The range of each number of a spec: one table for reading a file and checking a spec.
struct NumberField {
    const char* key;
    double lo, hi;
    double TessSceneSpec::*value;
};
constexpr NumberField kNumbers[] = {
    {"sun_elevation_deg", -10.0, 90.0, &TessSceneSpec::sun_elevation_deg},
    {"mie_g", 0.0, 0.999, &TessSceneSpec::mie_g},
    {"eye_m", 0.5, 20000.0, &TessSceneSpec::eye_m},
};

std::string range(const NumberField& f) {
    char text[64];
    std::snprintf(text, sizeof text, "a number in [%g, %g]", f.lo, f.hi);
    return text;
}

/// The ranges of a path's numbers.
struct PathField {
    const char* key;
    double lo, hi;
};
constexpr PathField kSunElevationEnd{"sun_elevation_end_deg", -10.0, 90.0};
constexpr PathField kSunAzimuthEnd{"sun_azimuth_end_deg", -360.0, 360.0};
constexpr PathField kEyeMove{"eye_move_m", -10000.0, 10000.0};

std::string range(const PathField& f) {
    char text[64];
    std::snprintf(text, sizeof text, "a number in [%g, %g]", f.lo, f.hi);
    return text;
}

std::optional<Error> check_path(const char* function, const TessSceneSpec& s,
                                const std::string& path) {
    const TessPath& p = s.path;
    if (p.frames == 0) return std::nullopt;
    if (p.frames < 2 || p.frames > 10000)
        return aerial::detail::invalid(function, path + "frames", "0 (no path) or 2 .. 10000",
                                       aerial::detail::number(p.frames));
    const std::pair<const PathField*, double> numbers[] = {
        {&kSunElevationEnd, p.sun_elevation_end_deg},
        {&kSunAzimuthEnd, p.sun_azimuth_end_deg},
        {&kEyeMove, p.eye_move_m[0]},
        {&kEyeMove, p.eye_move_m[1]}};
    for (const auto& [field, v] : numbers) {
        if (!(v >= field->lo && v <= field->hi))
            return aerial::detail::invalid(function, path + field->key, range(*field),
                                           aerial::detail::number(v));
    }
    if (s.kind == "dome" && (p.eye_move_m[0] != 0.0 || p.eye_move_m[1] != 0.0))
        return aerial::detail::error(function, path + "eye_move_m",
                                     "a dome moves with its eye: only terrain paths move it");
    return std::nullopt;
}

/// The first field of `s` out of range, as FUNCTION(): PATH.FIELD: ...
std::optional<Error> check_spec(const char* function, const TessSceneSpec& s,
                                const std::string& path) {
    if (s.kind != "dome" && s.kind != "terrain")
        return aerial::detail::invalid(function, path + "kind", "\"dome\" or \"terrain\"",
                                       "\"" + s.kind + "\"");
    for (const NumberField& f : kNumbers) {
        const double v = s.*f.value;
        if (!(v >= f.lo && v <= f.hi))
            return aerial::detail::invalid(function, path + f.key, range(f),
                                           aerial::detail::number(v));
    }
    if (!s.preset.empty() && !atmosphere_preset(s.preset))
        return aerial::detail::invalid(function, path + "preset", "a preset name",
                                       "'" + s.preset + "'");
    return check_path(function, s, path + "path.");
}

std::optional<Error> read_path(const Json& o, const std::string& path, TessPath& p) {
    if (!o.is_object()) return aerial::detail::invalid(kRead, path, "an object", o.dump());
    for (const auto& item : o.items()) {
        const std::string& k = item.key();
        if (k != "frames" && k != kSunElevationEnd.key && k != kSunAzimuthEnd.key &&
            k != kEyeMove.key)
            return aerial::detail::error(kRead, path + "." + k,
                                         "unknown field (known: frames, sun_elevation_end_deg, "
                                         "sun_azimuth_end_deg, eye_move_m)");
    }
    const auto frames = o.find("frames");
    if (frames == o.end() || !frames->is_number_integer())
        return aerial::detail::invalid(kRead, path + ".frames", "a whole number of frames",
                                       frames == o.end() ? "nothing" : frames->dump());
    p.frames = frames->get<int>();
    for (const PathField* f : {&kSunElevationEnd, &kSunAzimuthEnd}) {
        const auto it = o.find(f->key);
        if (it == o.end()) continue;
        if (!it->is_number())
            return aerial::detail::invalid(kRead, path + "." + f->key, range(*f), it->dump());
        (f == &kSunElevationEnd ? p.sun_elevation_end_deg : p.sun_azimuth_end_deg) =
            it->get<double>();
    }
    if (const auto it = o.find(kEyeMove.key); it != o.end()) {
        if (!it->is_array() || it->size() != 2 || !(*it)[0].is_number() || !(*it)[1].is_number())
            return aerial::detail::invalid(kRead, path + "." + kEyeMove.key, "[x, y] in metres",
                                           it->dump());
        p.eye_move_m[0] = (*it)[0].get<double>();
        p.eye_move_m[1] = (*it)[1].get<double>();
    }
    return std::nullopt;
}

std::optional<Error> read_spec(const Json& o, const std::string& path, TessSceneSpec& s) {
    if (!o.is_object()) return aerial::detail::invalid(kRead, path, "an object", o.dump());
    for (const auto& item : o.items()) {
        const std::string& k = item.key();
        if (k != "kind" && k != "name" && k != "preset" && k != "sun_elevation_deg" &&
            k != "mie_g" && k != "eye_m" && k != "path") {
            return aerial::detail::error(
                kRead, path + "." + k,
                "unknown field (known: kind, name, preset, sun_elevation_deg, mie_g, eye_m, path)");
        }
    }
    const auto kind = o.find("kind");
    if (kind == o.end() || !kind->is_string())
        return aerial::detail::invalid(kRead, path + ".kind", "\"dome\" or \"terrain\"",
                                       kind == o.end() ? "nothing" : kind->dump());
    s.kind = kind->get<std::string>();
    for (const char* key : {"name", "preset"}) {
        const auto it = o.find(key);
        if (it == o.end()) continue;
        if (!it->is_string() || it->get<std::string>().empty())
            return aerial::detail::invalid(kRead, path + "." + key, "a non-empty string",
                                           it->dump());
        (std::string(key) == "name" ? s.name : s.preset) = it->get<std::string>();
    }
    for (const NumberField& f : kNumbers) {
        const auto it = o.find(f.key);
        if (it == o.end()) continue;
        if (!it->is_number())
            return aerial::detail::invalid(kRead, path + "." + f.key, range(f), it->dump());
        s.*f.value = it->get<double>();
    }
    if (const auto p = o.find("path"); p != o.end()) {
        if (auto e = read_path(*p, path + ".path", s.path)) return e;
    }
    return check_spec(kRead, s, path + ".");
}

glm::dvec3 direction(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * kPi / 180.0, a = azimuth_deg * kPi / 180.0;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

float brightest(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

Result<Frame<float>> make_frame(const std::string& preset, double mie_g, const glm::dvec3& eye,
                                const glm::dvec3& sun) {
    auto found = atmosphere_preset(preset);
    if (!found) return aerial::detail::from(kMake, found.error());
    Atmosphere atmosphere = *found;
    if (mie_g > 0.0) atmosphere.mie_g = mie_g;
    View view;
    view.eye = eye;
    view.sun_dir = sun;
    auto frame = prepare_frame<float>(atmosphere, view, Model::height);
    if (!frame) return aerial::detail::from(kMake, frame.error());
    return frame;
}

/// Where the sun and the eye are at a frame of the spec's path (the start without a path).
struct Placement {
    double sun_elevation_deg = 0.0, sun_azimuth_deg = 0.0;
    double eye_x_m = 0.0, eye_y_m = 0.0;
};

Placement placement(const TessSceneSpec& spec, int frame) {
    Placement p;
    p.sun_elevation_deg = spec.sun_elevation_deg;
    if (spec.path.frames < 2) return p;
    const double t = double(frame) / double(spec.path.frames - 1);
    p.sun_elevation_deg += t * (spec.path.sun_elevation_end_deg - spec.sun_elevation_deg);
    p.sun_azimuth_deg = t * spec.path.sun_azimuth_end_deg;
    p.eye_x_m = t * spec.path.eye_move_m[0];
    p.eye_y_m = t * spec.path.eye_move_m[1];
    return p;
}

Result<TessScene> dome_scene(const TessSceneSpec& spec, int frame) {
    TessScene s;
    char name[64];
    std::snprintf(name, sizeof name, "dome-sun%02d-g%.2f", int(spec.sun_elevation_deg), spec.mie_g);
    s.name = name;
    s.dome = true;
    s.dome_options.centre = {0.0, 0.0, 2.0};
    const std::string preset = spec.preset.empty() ? "earth" : spec.preset;
    const Placement start = placement(spec, 0), now = placement(spec, frame);
    auto first = make_frame(preset, spec.mie_g, s.dome_options.centre,
                            direction(start.sun_elevation_deg, start.sun_azimuth_deg));
    auto current = make_frame(preset, spec.mie_g, s.dome_options.centre,
                              direction(now.sun_elevation_deg, now.sun_azimuth_deg));
    if (!first) return first.error();
    if (!current) return current.error();
    GradeSetting& g = s.setting;
    g.frame = std::move(current).value();
    g.colour.texel = glm::vec3(0.0f);
    // The sky 30 degrees up, 90 degrees from the sun in azimuth, at 0.5.
    const glm::dvec3 probe = s.dome_options.centre + s.dome_options.radius_m * direction(30, 90);
    g.colour.display.tone = ToneCurve::exponential;
    g.colour.display.exposure =
        float(std::log(2.0)) / brightest(scatter(*first, glm::vec3(probe)).in_scattering);
    g.options.dome = s.dome_options;
    g.options.near_m = 100.0;
    g.options.far_m = 4.0 * s.dome_options.radius_m;
    return s;
}

Result<TessScene> terrain_scene(const TessSceneSpec& spec, int frame) {
    TessScene s;
    char name[64];
    std::snprintf(name, sizeof name, "terrain-eye%d-sun%02d", int(spec.eye_m),
                  int(spec.sun_elevation_deg));
    s.name = name;
    s.dome = false;
    s.field = mesh::rolling_hills(-10000, -10000, 20000, 100, 3000);
    const std::string preset = spec.preset.empty() ? "hazy" : spec.preset;
    const Placement start = placement(spec, 0), now = placement(spec, frame);
    const auto eye_at = [&](const Placement& p) {
        return glm::dvec3{p.eye_x_m, p.eye_y_m,
                          s.field.height_m(p.eye_x_m, p.eye_y_m) + spec.eye_m};
    };
    auto first = make_frame(preset, 0.0, eye_at(start),
                            direction(start.sun_elevation_deg, start.sun_azimuth_deg));
    auto current =
        make_frame(preset, 0.0, eye_at(now), direction(now.sun_elevation_deg, now.sun_azimuth_deg));
    if (!first) return first.error();
    if (!current) return current.error();
    GradeSetting& g = s.setting;
    g.frame = std::move(current).value();
    g.colour.texel = glm::vec3(0.6f);
    // L_in of the ground 10 km from the start towards the sun at 0.4: F_ex x texel + L_in stays
    // below 1 (no clipping).
    const glm::dvec3 probe{10000.0, 0.0, s.field.height_m(10000.0, 0.0)};
    g.colour.display.tone = ToneCurve::exponential;
    g.colour.display.exposure =
        float(-std::log(1.0 - 0.4)) / brightest(scatter(*first, glm::vec3(probe)).in_scattering);
    // Depth precision: the near plane at 0.4 times the eye's height above the ground.
    g.options.near_m = 0.4 * spec.eye_m;
    g.options.far_m = 40000.0;
    return s;
}

}  // namespace

Result<std::vector<TessSceneSpec>> read_tess_scenes(const std::string& text) {
    const Json root = Json::parse(text, nullptr, false);
    if (root.is_discarded()) return aerial::detail::error(kRead, "scenes", "not JSON");
    if (!root.is_object() || !root.contains("scenes") || !root["scenes"].is_array() ||
        root["scenes"].empty()) {
        return aerial::detail::error(kRead, "scenes",
                                     "expected {\"scenes\": [ ... ]} with at least one scene");
    }
    if (root.size() != 1)
        return aerial::detail::error(kRead, "scenes", "expected only the field \"scenes\"");
    std::vector<TessSceneSpec> specs;
    for (std::size_t i = 0; i < root["scenes"].size(); ++i) {
        TessSceneSpec s;
        if (auto e = read_spec(root["scenes"][i], "scenes[" + std::to_string(i) + "]", s))
            return *e;
        specs.push_back(s);
    }
    return specs;
}

std::string write_tess_scenes(const std::vector<TessSceneSpec>& specs) {
    Json list = Json::array();
    for (const TessSceneSpec& s : specs) {
        Json o;
        o["kind"] = s.kind;
        if (!s.name.empty()) o["name"] = s.name;
        if (!s.preset.empty()) o["preset"] = s.preset;
        o["sun_elevation_deg"] = s.sun_elevation_deg;
        if (s.kind == "dome") o["mie_g"] = s.mie_g;
        if (s.kind == "terrain") o["eye_m"] = s.eye_m;
        if (s.path.frames > 0) {
            Json p;
            p["frames"] = s.path.frames;
            p[kSunElevationEnd.key] = s.path.sun_elevation_end_deg;
            p[kSunAzimuthEnd.key] = s.path.sun_azimuth_end_deg;
            if (s.kind == "terrain") p[kEyeMove.key] = {s.path.eye_move_m[0], s.path.eye_move_m[1]};
            o["path"] = p;
        }
        list.push_back(o);
    }
    return Json{{"scenes", list}}.dump(2) + "\n";
}

namespace {

TessSceneSpec spec_of(const char* kind, double sun_elevation_deg, double mie_g, double eye_m) {
    TessSceneSpec s;
    s.kind = kind;
    s.sun_elevation_deg = sun_elevation_deg;
    s.mie_g = mie_g;
    s.eye_m = eye_m;
    return s;
}

}  // namespace

std::vector<TessSceneSpec> builtin_tess_paths() {
    TessSceneSpec dome = spec_of("dome", 10.0, 0.9, 300.0);
    dome.path.frames = 48;
    dome.path.sun_elevation_end_deg = 2.0;
    TessSceneSpec terrain = spec_of("terrain", 10.0, 0.0, 300.0);
    terrain.path.frames = 48;
    terrain.path.sun_elevation_end_deg = 10.0;
    terrain.path.eye_move_m[0] = 1200.0;
    return {dome, terrain};
}

std::vector<TessSceneSpec> builtin_tess_scenes(bool quick) {
    std::vector<TessSceneSpec> specs;
    const auto dome = [&](double sun, double g) {
        specs.push_back(spec_of("dome", sun, g, 300.0));
    };
    const auto terrain = [&](double eye, double sun) {
        specs.push_back(spec_of("terrain", sun, 0.0, eye));
    };
    if (quick) {
        dome(10, 0.76);
        dome(10, 0.90);
        terrain(300, 10);
        return specs;
    }
    for (double g : {0.76, 0.90})
        for (double sun : {2.0, 10.0, 30.0, 60.0}) dome(sun, g);
    for (double eye : {2.0, 300.0, 3000.0})
        for (double sun : {10.0, 60.0}) terrain(eye, sun);
    return specs;
}

Result<TessScene> make_tess_scene(const TessSceneSpec& spec, int frame) {
    if (auto e = check_spec(kMake, spec, "")) return *e;
    if (frame < 0 || frame >= std::max(spec.path.frames, 1))
        return aerial::detail::invalid(kMake, "frame",
                                       "0 .. " + std::to_string(std::max(spec.path.frames, 1) - 1),
                                       aerial::detail::number(frame));
    auto made = spec.kind == "dome" ? dome_scene(spec, frame) : terrain_scene(spec, frame);
    if (!made) return made.error();
    TessScene scene = std::move(made).value();
    if (!spec.name.empty()) scene.name = spec.name;
    return scene;
}

bool tess_scene_fits(const TessScene& scene, const scene::MeshData& data) {
    bool on_sphere = true;
    const glm::dvec3 centre = scene.dome_options.centre;
    const double radius = scene.dome_options.radius_m;
    for (std::size_t i = 0; i < data.vertex_count() && on_sphere; ++i) {
        const glm::dvec3 p(data.positions[3 * i], data.positions[3 * i + 1],
                           data.positions[3 * i + 2]);
        on_sphere = std::abs(glm::length(p - centre) - radius) <= 0.01 * radius;
    }
    return scene.dome == on_sphere;
}

}  // namespace aerial::validation
