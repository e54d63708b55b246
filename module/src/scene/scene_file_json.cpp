// The scene file (aerial/scene_file.hpp): JSON parsing with errors that name the field.
#include "aerial/scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <iterator>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "../common/error_text.hpp"
#include "../common/json_text.hpp"
#include "aerial/phase.hpp"
#include "aerial/sun.hpp"

namespace aerial::scene {
namespace {

using Json = nlohmann::json;
constexpr double kDegree = kPi / 180.0;

using aerial::detail::number;
using aerial::detail::vector;
/// Every error of the scene file is scene_file_from_json's; load_scene_file re-attributes it.
constexpr const char* kFromJson = "scene::scene_file_from_json";

std::string describe(const Json& j) { return std::string(j.type_name()) + " " + j.dump(); }

Error bad(const std::string& field, const std::string& text) {
    return aerial::detail::error(kFromJson, field, text);
}
Error invalid(const std::string& field, const std::string& expected, const std::string& got) {
    return aerial::detail::invalid(kFromJson, field, expected, got);
}

/// The fields of one JSON object, each read at most once; anything left over is unknown.
class Object {
  public:
    Object(const Json& j, std::string path) : json_(j), path_(std::move(path)) {}

    /// Null when absent.
    const Json* get(const char* key) const {
        const auto it = json_.find(key);
        return it == json_.end() ? nullptr : &*it;
    }
    std::string field(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

    /// The first key not in `known`, as an error listing the known ones.
    std::optional<Error> check_known(std::initializer_list<const char*> known) const {
        for (const auto& item : json_.items()) {
            if (std::find_if(known.begin(), known.end(),
                             [&](const char* k) { return item.key() == k; }) != known.end()) {
                continue;
            }
            std::string list;
            for (const char* k : known) list += std::string(list.empty() ? "" : ", ") + k;
            const std::string name = field(item.key().c_str());
            return bad(name, "unknown field (known here: " + list + ")");
        }
        return std::nullopt;
    }

  private:
    const Json& json_;
    std::string path_;
};

std::optional<Error> expect_object(const Json& j, const std::string& field) {
    if (!j.is_object()) return invalid(field, "an object", describe(j));
    return std::nullopt;
}

/// A finite number in [lo, hi] (bounds inclusive unless open_lo / open_hi).
std::optional<Error> read_number(const Json& j, const std::string& field, double& out, double lo,
                                 double hi, bool open_lo = false, bool open_hi = false) {
    if (!j.is_number()) return invalid(field, "a number", describe(j));
    const double v = j.get<double>();
    const bool low = open_lo ? v <= lo : v < lo;
    const bool high = open_hi ? v >= hi : v > hi;
    if (!std::isfinite(v) || low || high) {
        return invalid(field,
                       "a number in " + std::string(open_lo ? "(" : "[") + number(lo) + ", " +
                           number(hi) + (open_hi ? ")" : "]"),
                       number(v));
    }
    out = v;
    return std::nullopt;
}

std::optional<Error> read_int(const Json& j, const std::string& field, int& out, int lo, int hi) {
    if (!j.is_number_integer()) return invalid(field, "an integer", describe(j));
    const auto v = j.get<long long>();
    if (v < lo || v > hi) {
        return invalid(field, "an integer in [" + number(lo) + ", " + number(hi) + "]", number(v));
    }
    out = int(v);
    return std::nullopt;
}

std::optional<Error> read_seed(const Json& j, const std::string& field, std::uint32_t& out) {
    if (!j.is_number_integer() || j.get<long long>() < 0 || j.get<long long>() > 0xffffffffLL) {
        return invalid(field, "an integer in [0, 4294967295]", describe(j));
    }
    out = std::uint32_t(j.get<long long>());
    return std::nullopt;
}

template <int N>
std::optional<Error> read_vector(const Json& j, const std::string& field, glm::vec<N, double>& out,
                                 double lo = -INFINITY, double hi = INFINITY) {
    if (!j.is_array() || j.size() != N) {
        return invalid(field, "an array of " + number(N) + " numbers", j.dump());
    }
    for (int i = 0; i < N; ++i) {
        if (auto e = read_number(j[std::size_t(i)], field + "[" + std::to_string(i) + "]", out[i],
                                 lo, hi)) {
            return e;
        }
    }
    return std::nullopt;
}

std::optional<Error> read_colour(const Json& j, const std::string& field, glm::dvec3& out) {
    return read_vector<3>(j, field, out, 0.0, 1.0);
}

/// A name of one of the library's enums, through its parse function (the name table's error,
/// under this field).
template <class Enum, class Parse>
std::optional<Error> read_name(const Json& j, const std::string& field, Parse parse, Enum& out) {
    if (!j.is_string()) return invalid(field, "a string", describe(j));
    auto value = parse(j.get<std::string>());
    if (!value) return bad(field, std::string(aerial::detail::text_of(value.error())));
    out = *value;
    return std::nullopt;
}

std::optional<Error> read_camera(const Json& j, Camera& camera) {
    if (auto e = expect_object(j, "camera")) return e;
    const Object o(j, "camera");
    if (auto e = o.check_known({"eye", "look_at", "direction", "up", "fov_y_deg", "near", "far"}))
        return e;
    if (const Json* v = o.get("eye")) {
        if (auto e = read_vector<3>(*v, o.field("eye"), camera.eye)) return e;
    }
    const Json* look_at = o.get("look_at");
    const Json* direction = o.get("direction");
    if ((look_at == nullptr) == (direction == nullptr)) {
        return bad("camera.look_at", "give exactly one of camera.look_at and camera.direction");
    }
    if (look_at) {
        if (auto e = read_vector<3>(*look_at, o.field("look_at"), camera.target)) return e;
        if (glm::length(camera.target - camera.eye) == 0.0)
            return invalid("camera.look_at", "a point other than camera.eye",
                           vector(camera.target));
    } else {
        glm::dvec3 d;
        if (auto e = read_vector<3>(*direction, o.field("direction"), d)) return e;
        if (glm::length(d) == 0.0)
            return invalid("camera.direction", "a non-zero vector", vector(d));
        camera.target = camera.eye + glm::normalize(d);
    }
    if (const Json* v = o.get("up")) {
        if (auto e = read_vector<3>(*v, o.field("up"), camera.up)) return e;
    }
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    if (!(glm::length(glm::cross(forward, camera.up)) > 1e-6 * glm::length(camera.up))) {
        return invalid("camera.up", "a vector not zero and not parallel to the view direction",
                       vector(camera.up));
    }
    if (const Json* v = o.get("fov_y_deg")) {
        double deg = 0.0;
        if (auto e = read_number(*v, o.field("fov_y_deg"), deg, 0.0, 180.0, true, true)) return e;
        camera.fov_y_rad = deg * kDegree;
    }
    if (const Json* v = o.get("near")) {
        if (auto e = read_number(*v, o.field("near"), camera.near_units, 0.0, INFINITY, true))
            return e;
    }
    if (const Json* v = o.get("far")) {
        if (auto e = read_number(*v, o.field("far"), camera.far_units, 0.0, INFINITY, true))
            return e;
    }
    if (!(camera.far_units > camera.near_units)) {
        return invalid("camera.far", "more than camera.near (" + number(camera.near_units) + ")",
                       number(camera.far_units));
    }
    return std::nullopt;
}

std::optional<Error> read_sun(const Json& j, glm::dvec3& sun_dir) {
    if (auto e = expect_object(j, "sun")) return e;
    const Object o(j, "sun");
    if (auto e = o.check_known({"direction", "elevation_deg", "azimuth_deg"})) return e;
    const Json* direction = o.get("direction");
    const Json* elevation = o.get("elevation_deg");
    const Json* azimuth = o.get("azimuth_deg");
    if (direction) {
        if (elevation || azimuth) {
            return bad("sun.direction",
                       "give sun.direction or sun.elevation_deg and "
                       "sun.azimuth_deg, not both");
        }
        glm::dvec3 d;
        if (auto e = read_vector<3>(*direction, "sun.direction", d)) return e;
        if (glm::length(d) == 0.0) return invalid("sun.direction", "a non-zero vector", vector(d));
        sun_dir = glm::normalize(d);
        return std::nullopt;
    }
    if (!elevation || !azimuth) {
        return bad(elevation ? "sun.azimuth_deg" : "sun.elevation_deg",
                   "required (or give sun.direction)");
    }
    double el = 0.0, az = 0.0;
    if (auto e = read_number(*elevation, "sun.elevation_deg", el, -90.0, 90.0)) return e;
    if (auto e = read_number(*azimuth, "sun.azimuth_deg", az, -360.0, 360.0)) return e;
    sun_dir = {std::sin(az * kDegree) * std::cos(el * kDegree),
               std::cos(az * kDegree) * std::cos(el * kDegree), std::sin(el * kDegree)};
    return std::nullopt;
}

std::optional<Error> read_atmosphere(const Json& j, Atmosphere& atmosphere) {
    if (j.is_string()) {
        auto a = atmosphere_preset(j.get<std::string>());
        if (!a) return bad("atmosphere", std::string(aerial::detail::text_of(a.error())));
        atmosphere = *a;
        return std::nullopt;
    }
    if (!j.is_object()) {
        return invalid("atmosphere", "a preset name or an object", describe(j));
    }
    auto a = atmosphere_from_json(j.dump());
    if (!a) return aerial::detail::from(kFromJson, a.error(), "atmosphere.");
    atmosphere = *a;
    return std::nullopt;
}

std::optional<Error> read_display(const Json& j, Display& display) {
    if (auto e = expect_object(j, "display")) return e;
    const Object o(j, "display");
    if (auto e = o.check_known({"exposure", "tone"})) return e;
    if (const Json* v = o.get("exposure")) {
        double exposure = 0.0;
        if (auto e = read_number(*v, "display.exposure", exposure, 0.0, 1e30, true)) return e;
        display.exposure = float(exposure);
    }
    if (const Json* v = o.get("tone")) {
        if (auto e = read_name(*v, "display.tone", parse_tone_curve, display.tone)) return e;
    }
    return std::nullopt;
}

std::optional<Error> read_texture(const Json& j, TextureSpec& t) {
    if (auto e = expect_object(j, "texture")) return e;
    const Object o(j, "texture");
    if (auto e = o.check_known({"kind", "size", "cells", "colors", "seed"})) return e;
    if (const Json* v = o.get("kind")) {
        if (auto e = read_name(*v, "texture.kind", parse_texture_kind, t.kind)) return e;
    }
    if (const Json* v = o.get("size")) {
        if (auto e = read_int(*v, "texture.size", t.size, 2, 1024)) return e;
        if ((t.size & (t.size - 1)) != 0)
            return invalid("texture.size", "a power of two", v->dump());
    }
    if (const Json* v = o.get("cells")) {
        if (auto e = read_int(*v, "texture.cells", t.cells, 1, 1024)) return e;
    }
    if (t.size % t.cells != 0) {
        return invalid("texture.cells", "a divisor of texture.size (" + number(t.size) + ")",
                       number(t.cells));
    }
    if (const Json* v = o.get("colors")) {
        if (!v->is_array() || v->size() != 2)
            return invalid("texture.colors", "an array of 2 colours", v->dump());
        for (std::size_t i = 0; i < 2; ++i) {
            if (auto e = read_colour((*v)[i], "texture.colors[" + std::to_string(i) + "]",
                                     t.colors[i])) {
                return e;
            }
        }
    }
    if (const Json* v = o.get("seed")) {
        if (auto e = read_seed(*v, "texture.seed", t.seed)) return e;
    }
    return std::nullopt;
}

std::optional<Error> read_terrain(const Json& j, TerrainSpec& t) {
    if (auto e = expect_object(j, "terrain")) return e;
    const Object o(j, "terrain");
    if (auto e = o.check_known({"center", "size", "resolution", "height_amplitude", "feature_size",
                                "seed", "octaves", "texture_repeat"})) {
        return e;
    }
    if (const Json* v = o.get("center")) {
        if (auto e = read_vector<2>(*v, "terrain.center", t.center)) return e;
    }
    if (const Json* v = o.get("size")) {
        if (auto e = read_number(*v, "terrain.size", t.size, 0.0, INFINITY, true)) return e;
    }
    if (const Json* v = o.get("resolution")) {
        if (auto e = read_int(*v, "terrain.resolution", t.resolution, 1, 1024)) return e;
    }
    if (const Json* v = o.get("height_amplitude")) {
        if (auto e = read_number(*v, "terrain.height_amplitude", t.height_amplitude, 0.0, INFINITY))
            return e;
    }
    if (const Json* v = o.get("feature_size")) {
        if (auto e = read_number(*v, "terrain.feature_size", t.feature_size, 0.0, INFINITY, true))
            return e;
    }
    if (const Json* v = o.get("seed")) {
        if (auto e = read_seed(*v, "terrain.seed", t.seed)) return e;
    }
    if (const Json* v = o.get("octaves")) {
        if (auto e = read_int(*v, "terrain.octaves", t.octaves, 1, 12)) return e;
    }
    if (const Json* v = o.get("texture_repeat")) {
        if (auto e =
                read_number(*v, "terrain.texture_repeat", t.texture_repeat, 0.0, INFINITY, true)) {
            return e;
        }
    }
    return std::nullopt;
}

std::optional<Error> read_box(const Json& j, const std::string& path, BoxSpec& box) {
    if (auto e = expect_object(j, path)) return e;
    const Object o(j, path);
    if (auto e = o.check_known({"center", "size", "subdivisions"})) return e;
    const Json* center = o.get("center");
    const Json* size = o.get("size");
    if (!center) return bad(o.field("center"), "required");
    if (!size) return bad(o.field("size"), "required");
    if (auto e = read_vector<3>(*center, o.field("center"), box.center)) return e;
    if (auto e = read_vector<3>(*size, o.field("size"), box.size, 0.0)) return e;
    if (box.size.x <= 0.0 || box.size.y <= 0.0 || box.size.z <= 0.0)
        return invalid(o.field("size"), "every side > 0", size->dump());
    if (const Json* v = o.get("subdivisions")) {
        if (auto e = read_int(*v, o.field("subdivisions"), box.subdivisions, 1, 64)) return e;
    }
    return std::nullopt;
}

/// The largest coordinate (scene units) or texture coordinate the geometry may reach: well inside
/// a float's range, so every vertex the scene builds is finite.
constexpr double kMaxCoordinate = 1e9;

/// An error when geometry spanning `reach` (scene units, largest |coordinate|) with textures
/// repeating every `repeat` units would leave the range the vertex arrays (floats) hold.
std::optional<Error> check_reach(const std::string& field, double reach, double repeat) {
    const std::string limit = "at most " + number(kMaxCoordinate);
    if (!(reach <= kMaxCoordinate))
        return invalid(field, "geometry whose coordinates are " + limit + " units", number(reach));
    if (!(reach / repeat <= kMaxCoordinate)) {
        return invalid(field, "texture coordinates (coordinate / texture_repeat) " + limit,
                       number(reach / repeat));
    }
    return std::nullopt;
}

/// Every vertex of the scene's geometry within kMaxCoordinate (procedural heights are at most
/// the terrain's amplitude above 0).
std::optional<Error> check_geometry_reach(const SceneFile& s) {
    const double repeat = s.terrain ? s.terrain->texture_repeat : TerrainSpec{}.texture_repeat;
    if (s.terrain) {
        const TerrainSpec& t = *s.terrain;
        const double reach = std::max({std::abs(t.center.x) + 0.5 * t.size,
                                       std::abs(t.center.y) + 0.5 * t.size, t.height_amplitude});
        if (auto e = check_reach("terrain", reach, repeat)) return e;
    }
    for (std::size_t i = 0; i < s.boxes.size(); ++i) {
        const glm::dvec3 reach = glm::abs(s.boxes[i].center) + 0.5 * s.boxes[i].size;
        const std::string field = "boxes[" + std::to_string(i) + "]";
        if (auto e = check_reach(field, std::max({reach.x, reach.y, reach.z}), repeat)) return e;
    }
    return std::nullopt;
}

std::optional<Error> read_scene(const Json& root, SceneFile& s) {
    if (!root.is_object()) return invalid("scene", "a JSON object", describe(root));
    const Object o(root, "");
    if (auto e = o.check_known({"camera", "sun", "atmosphere", "model", "display",
                                "meters_per_unit", "background", "texture", "terrain", "boxes"})) {
        return e;
    }
    const Json* camera = o.get("camera");
    if (!camera) return bad("camera", "required");
    if (auto e = read_camera(*camera, s.camera)) return e;
    const Json* sun = o.get("sun");
    if (!sun) return bad("sun", "required");
    if (auto e = read_sun(*sun, s.sun_dir)) return e;
    if (const Json* v = o.get("atmosphere")) {
        if (auto e = read_atmosphere(*v, s.atmosphere)) return e;
    }
    if (const Json* v = o.get("model")) {
        if (auto e = read_name(*v, "model", parse_model, s.model)) return e;
        if (is_numerical(s.model))
            return invalid("model",
                           "hoffman-preetham or height (the numerical models are too slow to "
                           "render)",
                           std::string(model_name(s.model)));
    }
    if (const Json* v = o.get("display")) {
        if (auto e = read_display(*v, s.display)) return e;
    }
    if (const Json* v = o.get("meters_per_unit")) {
        if (auto e = read_number(*v, "meters_per_unit", s.meters_per_unit, 0.0, INFINITY, true))
            return e;
    }
    if (const Json* v = o.get("background")) {
        if (auto e = read_colour(*v, "background", s.background)) return e;
    }
    if (const Json* v = o.get("texture")) {
        if (auto e = read_texture(*v, s.texture)) return e;
    }
    if (const Json* v = o.get("terrain")) {
        s.terrain.emplace();
        if (auto e = read_terrain(*v, *s.terrain)) return e;
    }
    if (const Json* v = o.get("boxes")) {
        if (!v->is_array()) return invalid("boxes", "an array", describe(*v));
        for (std::size_t i = 0; i < v->size(); ++i) {
            BoxSpec box;
            if (auto e = read_box((*v)[i], "boxes[" + std::to_string(i) + "]", box)) return e;
            s.boxes.push_back(box);
        }
    }
    if (!s.terrain && s.boxes.empty())
        return bad("terrain",
                   "the scene has no geometry: give "
                   "terrain or boxes");
    if (auto e = check_geometry_reach(s)) return e;
    if (auto e = validate(s.view())) return aerial::detail::from(kFromJson, *e);
    return std::nullopt;
}

}  // namespace

Camera SceneFile::default_camera() {
    Camera c;
    c.eye = {0.0, 0.0, 300.0};
    c.target = {0.0, 1.0, 300.0};
    c.up = {0.0, 0.0, 1.0};
    c.fov_y_rad = 50.0 * kDegree;
    c.aspect = 1.0;
    c.near_units = 10.0;
    c.far_units = 100000.0;
    return c;
}

View SceneFile::view() const {
    View v;
    v.eye = camera.eye;
    v.sun_dir = sun_dir;
    v.up = {0.0, 0.0, 1.0};
    v.meters_per_unit = meters_per_unit;
    return v;
}

Camera SceneFile::camera_for(int width, int height) const {
    Camera c = camera;
    c.aspect = double(width) / double(height);
    return c;
}

FrameSettings SceneFile::frame_settings() const {
    FrameSettings settings;
    settings.atmosphere = atmosphere;
    settings.sun_dir = sun_dir;
    settings.up = view().up;
    settings.meters_per_unit = meters_per_unit;
    settings.display = display;
    settings.model = model;
    settings.policy = false;
    return settings;
}

Result<SceneFile> scene_file_from_json(std::string_view json_text) {
    auto root = aerial::detail::parse_json(kFromJson, json_text);
    if (!root) return root.error();
    SceneFile scene;
    if (auto e = read_scene(root.value(), scene)) return *e;
    return scene;
}

Result<SceneFile> load_scene_file(const std::string& path) {
    auto text = aerial::detail::read_text_file("scene::load_scene_file", path, "scene file");
    if (!text) return text.error();
    auto scene = scene_file_from_json(text.value());
    if (!scene) return aerial::detail::from_file("scene::load_scene_file", path, scene.error());
    return scene;
}

}  // namespace aerial::scene
