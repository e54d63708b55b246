// aerial-tess's scene files: see scene_list.hpp.
#include "scene_list.hpp"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "aerial/atmosphere.hpp"

namespace aerial::tess {
namespace {

using Json = nlohmann::json;

Error bad(const std::string& field, const std::string& text) {
    return Error{field, "--scenes: " + field + ": " + text};
}

std::optional<Error> number_in(const Json& o, const char* key, const std::string& path, double lo,
                               double hi, double& out) {
    const auto it = o.find(key);
    if (it == o.end()) return std::nullopt;
    const std::string field = path + "." + key;
    if (!it->is_number()) return bad(field, "expected a number, got " + it->dump());
    const double v = it->get<double>();
    if (!(v >= lo && v <= hi)) {
        char text[96];
        std::snprintf(text, sizeof text, "expected a number in [%g, %g], got %g", lo, hi, v);
        return bad(field, text);
    }
    out = v;
    return std::nullopt;
}

std::optional<Error> read_spec(const Json& o, const std::string& path, SceneSpec& s) {
    if (!o.is_object()) return bad(path, "expected an object, got " + o.dump());
    for (const auto& item : o.items()) {
        const std::string& k = item.key();
        if (k != "kind" && k != "name" && k != "preset" && k != "sun_elevation_deg" &&
            k != "mie_g" && k != "eye_m") {
            return bad(
                path + "." + k,
                "unknown field (known: kind, name, preset, sun_elevation_deg, mie_g, eye_m)");
        }
    }
    const auto kind = o.find("kind");
    if (kind == o.end() || !kind->is_string() ||
        (kind->get<std::string>() != "dome" && kind->get<std::string>() != "terrain")) {
        return bad(path + ".kind", "expected \"dome\" or \"terrain\"");
    }
    s.kind = kind->get<std::string>();
    for (const char* key : {"name", "preset"}) {
        const auto it = o.find(key);
        if (it == o.end()) continue;
        if (!it->is_string() || it->get<std::string>().empty())
            return bad(path + "." + key, "expected a non-empty string, got " + it->dump());
        (std::string(key) == "name" ? s.name : s.preset) = it->get<std::string>();
    }
    if (!s.preset.empty() && !atmosphere_preset(s.preset))
        return bad(path + ".preset", "unknown preset '" + s.preset + "'");
    if (auto e = number_in(o, "sun_elevation_deg", path, -10.0, 90.0, s.sun_elevation_deg))
        return e;
    if (auto e = number_in(o, "mie_g", path, 0.0, 0.999, s.mie_g)) return e;
    if (auto e = number_in(o, "eye_m", path, 0.5, 20000.0, s.eye_m)) return e;
    return std::nullopt;
}

}  // namespace

Result<std::vector<SceneSpec>> read_scene_list(const std::string& text) {
    const Json root = Json::parse(text, nullptr, false);
    if (root.is_discarded()) return bad("scenes", "not JSON");
    if (!root.is_object() || !root.contains("scenes") || !root["scenes"].is_array() ||
        root["scenes"].empty()) {
        return bad("scenes", "expected {\"scenes\": [ ... ]} with at least one scene");
    }
    if (root.size() != 1) return bad("scenes", "expected only the field \"scenes\"");
    std::vector<SceneSpec> specs;
    for (std::size_t i = 0; i < root["scenes"].size(); ++i) {
        SceneSpec s;
        if (auto e = read_spec(root["scenes"][i], "scenes[" + std::to_string(i) + "]", s))
            return *e;
        specs.push_back(s);
    }
    return specs;
}

std::string write_scene_list(const std::vector<SceneSpec>& specs) {
    Json list = Json::array();
    for (const SceneSpec& s : specs) {
        Json o;
        o["kind"] = s.kind;
        if (!s.name.empty()) o["name"] = s.name;
        if (!s.preset.empty()) o["preset"] = s.preset;
        o["sun_elevation_deg"] = s.sun_elevation_deg;
        if (s.kind == "dome") o["mie_g"] = s.mie_g;
        if (s.kind == "terrain") o["eye_m"] = s.eye_m;
        list.push_back(o);
    }
    return Json{{"scenes", list}}.dump(2) + "\n";
}

}  // namespace aerial::tess
