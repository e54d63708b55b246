// Atmosphere JSON (docs/conventions.md, Interfaces): parsing with errors that name the field, and
// printing.
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "../common/json_text.hpp"
#include "aerial/atmosphere.hpp"
#include "format.hpp"

namespace aerial {
namespace {

using Json = nlohmann::json;
using detail::format_number;

std::string type_of(const Json& j) { return j.type_name(); }

std::optional<Error> read_number(const Json& j, const std::string& field, double& out) {
    if (!j.is_number()) {
        return Error{field, field + " must be a number, got " + type_of(j) + " " + j.dump()};
    }
    out = j.get<double>();
    return std::nullopt;
}

std::optional<Error> read_vector(const Json& j, const std::string& field, glm::dvec3& out) {
    if (!j.is_array() || j.size() != 3) {
        return Error{field, field + " must be an array of 3 numbers (R, G, B), got " + j.dump()};
    }
    for (int c = 0; c < 3; ++c) {
        const std::string element = field + "[" + std::to_string(c) + "]";
        if (auto e = read_number(j[c], element, out[c])) return e;
    }
    return std::nullopt;
}

}  // namespace

Result<Atmosphere> atmosphere_from_json(std::string_view json_text) {
    auto parsed = detail::parse_json(json_text, "atmosphere JSON");
    if (!parsed) return parsed.error();
    const Json& root = parsed.value();
    if (!root.is_object()) {
        return Error{"json", "atmosphere JSON must be an object, got " + type_of(root)};
    }
    Atmosphere a;
    for (const auto& [key, value] : root.items()) {
        std::optional<Error> e;
        if (key == "rayleigh_scattering")
            e = read_vector(value, key, a.rayleigh_scattering);
        else if (key == "mie_scattering")
            e = read_vector(value, key, a.mie_scattering);
        else if (key == "mie_absorption")
            e = read_vector(value, key, a.mie_absorption);
        else if (key == "mie_g")
            e = read_number(value, key, a.mie_g);
        else if (key == "rayleigh_scale_height_m")
            e = read_number(value, key, a.rayleigh_scale_height_m);
        else if (key == "mie_scale_height_m")
            e = read_number(value, key, a.mie_scale_height_m);
        else if (key == "planet_radius_m")
            e = read_number(value, key, a.planet_radius_m);
        else if (key == "atmosphere_radius_m")
            e = read_number(value, key, a.atmosphere_radius_m);
        else if (key == "sun_irradiance")
            e = read_vector(value, key, a.sun_irradiance);
        else {
            return Error{key, key +
                                  " is not an atmosphere field (known: rayleigh_scattering, "
                                  "mie_scattering, mie_absorption, mie_g, rayleigh_scale_height_m, "
                                  "mie_scale_height_m, planet_radius_m, atmosphere_radius_m, "
                                  "sun_irradiance)"};
        }
        if (e) return *e;
    }
    if (auto e = validate(a)) return *e;
    return a;
}

Result<Atmosphere> load_atmosphere_json(const std::string& path) {
    auto text = detail::read_text_file(path, "atmosphere file");
    if (!text) return text.error();
    auto result = atmosphere_from_json(text.value());
    if (!result) return Error{result.error().field, path + ": " + result.error().message};
    return result;
}

std::string to_json(const Atmosphere& a) {
    auto vec = [](const glm::dvec3& v) {
        return "[" + format_number(v.x) + ", " + format_number(v.y) + ", " + format_number(v.z) +
               "]";
    };
    std::string out = "{\n";
    out += "  \"rayleigh_scattering\": " + vec(a.rayleigh_scattering) + ",\n";
    out += "  \"mie_scattering\": " + vec(a.mie_scattering) + ",\n";
    out += "  \"mie_absorption\": " + vec(a.mie_absorption) + ",\n";
    out += "  \"mie_g\": " + format_number(a.mie_g) + ",\n";
    out += "  \"rayleigh_scale_height_m\": " + format_number(a.rayleigh_scale_height_m) + ",\n";
    out += "  \"mie_scale_height_m\": " + format_number(a.mie_scale_height_m) + ",\n";
    out += "  \"planet_radius_m\": " + format_number(a.planet_radius_m) + ",\n";
    out += "  \"atmosphere_radius_m\": " + format_number(a.atmosphere_radius_m) + ",\n";
    out += "  \"sun_irradiance\": " + vec(a.sun_irradiance) + "\n";
    out += "}\n";
    return out;
}

}  // namespace aerial
