// Atmosphere JSON (docs/conventions.md, Interfaces): parsing with errors that name the field, and
// printing.
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "../common/error_text.hpp"
#include "../common/json_text.hpp"
#include "aerial/atmosphere.hpp"

namespace aerial {
namespace {

using Json = nlohmann::json;
using detail::invalid;
using detail::number;
constexpr const char* kFromJson = "atmosphere_from_json";

std::string type_of(const Json& j) { return j.type_name(); }

std::optional<Error> read_number(const Json& j, const std::string& field, double& out) {
    if (!j.is_number()) {
        return invalid(kFromJson, field, "a number", type_of(j) + " " + j.dump());
    }
    out = j.get<double>();
    return std::nullopt;
}

std::optional<Error> read_vector(const Json& j, const std::string& field, glm::dvec3& out) {
    if (!j.is_array() || j.size() != 3) {
        return invalid(kFromJson, field, "an array of 3 numbers (R, G, B)", j.dump());
    }
    for (int c = 0; c < 3; ++c) {
        const std::string element = field + "[" + std::to_string(c) + "]";
        if (auto e = read_number(j[c], element, out[c])) return e;
    }
    return std::nullopt;
}

/// A number for every channel, or an array of 3 (ground_albedo).
std::optional<Error> read_grey_or_vector(const Json& j, const std::string& field, glm::dvec3& out) {
    if (j.is_number()) {
        out = glm::dvec3(j.get<double>());
        return std::nullopt;
    }
    if (!j.is_array() || j.size() != 3) {
        return invalid(kFromJson, field,
                       "a number (every channel) or an array of 3 numbers (R, G, B)", j.dump());
    }
    return read_vector(j, field, out);
}

}  // namespace

Result<Atmosphere> atmosphere_from_json(std::string_view json_text) {
    auto parsed = detail::parse_json(kFromJson, json_text);
    if (!parsed) return parsed.error();
    const Json& root = parsed.value();
    if (!root.is_object()) return invalid(kFromJson, "json", "an object", type_of(root));
    Atmosphere a;
    // Absorbers and the ground are 0 unless the file gives them (mie_absorption is 0 in `earth`).
    a.ozone_absorption = glm::dvec3(0.0);
    a.ground_albedo = glm::dvec3(0.0);
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
        else if (key == "ozone_absorption")
            e = read_vector(value, key, a.ozone_absorption);
        else if (key == "ozone_center_altitude_m")
            e = read_number(value, key, a.ozone_center_altitude_m);
        else if (key == "ozone_width_m")
            e = read_number(value, key, a.ozone_width_m);
        else if (key == "planet_radius_m")
            e = read_number(value, key, a.planet_radius_m);
        else if (key == "atmosphere_radius_m")
            e = read_number(value, key, a.atmosphere_radius_m);
        else if (key == "ground_albedo")
            e = read_grey_or_vector(value, key, a.ground_albedo);
        else if (key == "sun_irradiance")
            e = read_vector(value, key, a.sun_irradiance);
        else {
            return detail::error(kFromJson, key,
                                 "not an atmosphere field (known: rayleigh_scattering, "
                                 "mie_scattering, mie_absorption, mie_g, rayleigh_scale_height_m, "
                                 "mie_scale_height_m, ozone_absorption, ozone_center_altitude_m, "
                                 "ozone_width_m, planet_radius_m, atmosphere_radius_m, "
                                 "ground_albedo, sun_irradiance)");
        }
        if (e) return *e;
    }
    if (auto e = validate(a)) return detail::from(kFromJson, *e);
    return a;
}

Result<Atmosphere> load_atmosphere_json(const std::string& path) {
    constexpr const char* kFunction = "load_atmosphere_json";
    auto text = detail::read_text_file(kFunction, path, "atmosphere file");
    if (!text) return text.error();
    auto result = atmosphere_from_json(text.value());
    if (!result) return detail::from_file(kFunction, path, result.error());
    return result;
}

std::string to_json(const Atmosphere& a) {
    auto vec = [](const glm::dvec3& v) {
        return "[" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + "]";
    };
    std::string out = "{\n";
    out += "  \"rayleigh_scattering\": " + vec(a.rayleigh_scattering) + ",\n";
    out += "  \"mie_scattering\": " + vec(a.mie_scattering) + ",\n";
    out += "  \"mie_absorption\": " + vec(a.mie_absorption) + ",\n";
    out += "  \"mie_g\": " + number(a.mie_g) + ",\n";
    out += "  \"rayleigh_scale_height_m\": " + number(a.rayleigh_scale_height_m) + ",\n";
    out += "  \"mie_scale_height_m\": " + number(a.mie_scale_height_m) + ",\n";
    out += "  \"ozone_absorption\": " + vec(a.ozone_absorption) + ",\n";
    out += "  \"ozone_center_altitude_m\": " + number(a.ozone_center_altitude_m) + ",\n";
    out += "  \"ozone_width_m\": " + number(a.ozone_width_m) + ",\n";
    out += "  \"planet_radius_m\": " + number(a.planet_radius_m) + ",\n";
    out += "  \"atmosphere_radius_m\": " + number(a.atmosphere_radius_m) + ",\n";
    out += "  \"ground_albedo\": " + vec(a.ground_albedo) + ",\n";
    out += "  \"sun_irradiance\": " + vec(a.sun_irradiance) + "\n";
    out += "}\n";
    return out;
}

}  // namespace aerial
