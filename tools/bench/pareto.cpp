#include "bench/pareto.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "aerial/adaptive_scene.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/batch.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/headless.hpp"
#include "aerial/mesh.hpp"
#include "aerial/validation/scene_render.hpp"
#include "bench/frame_gl.hpp"
#include "bench/methods.hpp"
#include "common/image_metrics.hpp"
#include "support/png.hpp"

namespace aerial::bench {
namespace {

using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

enum class Method { gl_fog, fg_fog, cpu_hp, arb_hp, cpu_height, arb_height, lut_texture, perpixel };

/// Every method, in the order of the CSV and the charts: its name, whether it is per vertex
/// (drawn on every tessellation; the others on the default mesh only) and the model it computes
/// (the fogs take their density and colour from `height`, the density where the eye is; the
/// per-pixel image is the `height` model without interpolation).
struct MethodInfo {
    Method method;
    const char* name;
    bool per_vertex;
    Model model;
};
constexpr MethodInfo kMethods[] = {
    {Method::gl_fog, "gl-fog", false, Model::height},
    {Method::fg_fog, "fg-fog", false, Model::height},
    {Method::cpu_hp, "cpu-hp", true, Model::hoffman_preetham},
    {Method::arb_hp, "arb-hp", true, Model::hoffman_preetham},
    {Method::cpu_height, "cpu-height", true, Model::height},
    {Method::arb_height, "arb-height", true, Model::height},
    {Method::lut_texture, "lut-texture", false, Model::hoffman_preetham},
    {Method::perpixel, "perpixel-reference", false, Model::height},
};

const MethodInfo& info(Method m) {
    for (const MethodInfo& i : kMethods) {
        if (i.method == m) return i;
    }
    return kMethods[0];  // unreachable: every Method is in the table
}
const char* method_name(Method m) { return info(m).name; }
bool per_vertex(Method m) { return info(m).per_vertex; }
Model method_model(Method m) { return info(m).model; }

bool is_per_vertex_name(const std::string& name) {
    for (const MethodInfo& i : kMethods) {
        if (name == i.name) return i.per_vertex;
    }
    return false;
}

/// One mesh of a scene, with the reference image of it.
struct MeshEntry {
    std::string tessellation;          ///< "uniform" or "adaptive"
    Model adapted_to = Model::height;  ///< adaptive: the model its colour error was measured in
    bool is_default = false;
    scene::MeshData mesh;
    std::unique_ptr<scene::Node> graph;   ///< the mesh as a scene graph (per-vertex methods)
    std::vector<std::uint8_t> reference;  ///< RGBA8, top row first
    double max_distance_m = 0.0;          ///< farthest vertex from the eye

    bool is_adaptive_of(Model model) const {
        return tessellation == "adaptive" && adapted_to == model;
    }
};

constexpr double kNotTimed = std::numeric_limits<double>::infinity();

struct Variant {
    Method method;
    const MeshEntry* mesh;
    double best_ms = kNotTimed;
    std::vector<std::uint8_t> image;
};

/// What an engine creates once per scene: the library's renderers (cpu and arb backends: the
/// per-vertex methods draw through aerial::scene::SceneRenderer, as engines do) and the tables
/// of the lookup-texture baseline.
struct SceneGl {
    std::optional<scene::SceneRenderer> renderer[2];  ///< cpu, arb
    std::optional<LutTexture> lut;
    std::vector<float> coords;  ///< scratch reused across frames
};

// ---- Scene files ------------------------------------------------------------------------------

Error bad(const std::string& path, const std::string& field, const std::string& what) {
    return Error{field, path + ": " + field + ": " + what};
}

}  // namespace

Result<BenchScene> load_bench_scene(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Error{"path", path + ": cannot read the file"};
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    Json j;
    try {
        j = Json::parse(text);
    } catch (const Json::exception& e) {
        return Error{"json", path + ": not JSON: " + e.what()};
    }
    if (!j.is_object()) return Error{"json", path + ": expected a JSON object"};
    for (auto it = j.begin(); it != j.end(); ++it) {
        static const char* const known[] = {"scene", "description", "quick", "sky_dome_radius",
                                            "sky_dome_frequency"};
        if (std::find(std::begin(known), std::end(known), it.key()) == std::end(known))
            return bad(path, it.key(), "unknown field");
    }
    BenchScene s;
    s.name = std::filesystem::path(path).stem().string();
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& key = it.key();
        const Json& v = it.value();
        if (key == "scene") {
            if (!v.is_object()) return bad(path, "scene", "expected an object");
            auto scene = scene::scene_file_from_json(v.dump());
            if (!scene) return bad(path, "scene." + scene.error().field, scene.error().message);
            s.scene = std::move(scene.value());
        } else if (key == "description") {
            if (!v.is_string()) return bad(path, key, "expected a string");
            s.description = v.get<std::string>();
        } else if (key == "quick") {
            if (!v.is_boolean()) return bad(path, key, "expected true or false, got " + v.dump());
            s.quick = v.get<bool>();
        } else if (key == "sky_dome_radius") {
            if (!v.is_number() || !(v.get<double>() > 0.0) || !std::isfinite(v.get<double>()))
                return bad(path, key, "expected a positive number, got " + v.dump());
            s.sky_dome_radius = v.get<double>();
        } else if (key == "sky_dome_frequency") {
            if (!v.is_number_integer() || v.get<int>() < 2 || v.get<int>() > 256)
                return bad(path, key, "expected an integer in 2 .. 256, got " + v.dump());
            s.sky_dome_frequency = v.get<int>();
        }
    }
    if (!j.contains("scene")) return bad(path, "scene", "required");
    if (s.sky_dome_radius > 0.0 && s.sky_dome_radius >= s.scene.camera.far_units) {
        return bad(path, "sky_dome_radius",
                   "the dome (" + std::to_string(s.sky_dome_radius) +
                       ") must lie inside the far plane (" +
                       std::to_string(s.scene.camera.far_units) + ")");
    }
    if (s.sky_dome_radius == 0.0 && !s.scene.terrain) {
        return bad(path, "scene.terrain", "required unless sky_dome_radius is given");
    }
    return s;
}

Result<std::vector<BenchScene>> load_bench_scenes(const std::string& dir, bool quick) {
    std::vector<std::string> paths;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        if (entry.path().extension() == ".json") paths.push_back(entry.path().string());
    }
    if (ec) return Error{"--scenes", "--scenes: cannot read " + dir + ": " + ec.message()};
    std::sort(paths.begin(), paths.end());
    std::vector<BenchScene> scenes;
    for (const auto& p : paths) {
        auto s = load_bench_scene(p);
        if (!s) return Error{"--scenes", "--scenes: " + s.error().message};
        if (!quick || s->quick) scenes.push_back(std::move(s.value()));
    }
    if (scenes.empty()) {
        return Error{"--scenes", "--scenes: no" + std::string(quick ? " quick" : "") +
                                     " scene file (*.json) in " + dir};
    }
    return scenes;
}

const std::vector<std::string>& bench_method_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const MethodInfo& m : kMethods) n.emplace_back(m.name);
        return n;
    }();
    return names;
}

namespace {

// ---- Meshes -----------------------------------------------------------------------------------

double farthest_m(const scene::MeshData& m, const scene::SceneFile& scene) {
    double far = 0.0;
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        const glm::dvec3 p(m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
        far = std::max(far, glm::length(p - scene.camera.eye));
    }
    return far * scene.meters_per_unit;
}

/// The default tessellation and the budgets (cells a side of the terrain, or the dome's
/// geodesic frequency) of a scene.
std::vector<int> budgets(const BenchScene& s, bool quick, int& default_level) {
    const bool dome = s.sky_dome_radius > 0.0;
    std::vector<int> levels;
    if (quick) {
        levels = dome ? std::vector<int>{8, 16} : std::vector<int>{16, 32};
        default_level = levels.back();
        return levels;
    }
    levels = dome ? std::vector<int>{8, 16, 32, 64} : std::vector<int>{16, 32, 64, 128};
    default_level = dome ? s.sky_dome_frequency : s.scene.terrain->resolution;
    if (std::find(levels.begin(), levels.end(), default_level) == levels.end()) {
        levels.push_back(default_level);
        std::sort(levels.begin(), levels.end());
    }
    return levels;
}

glm::vec3 brightest_texel(const scene::TextureSpec& t) {
    return glm::vec3(glm::max(t.colors[0], t.colors[1]));
}

/// Builds the uniform and adaptive meshes of a scene.
Result<std::vector<std::unique_ptr<MeshEntry>>> build_meshes(const BenchScene& s, bool quick) {
    const scene::SceneFile& scene = s.scene;
    const bool dome = s.sky_dome_radius > 0.0;
    int default_level = 0;
    const std::vector<int> levels = budgets(s, quick, default_level);
    const double repeat =
        scene.terrain ? scene.terrain->texture_repeat : scene::TerrainSpec{}.texture_repeat;
    mesh::DomeOptions dome_options;
    dome_options.centre = scene.camera.eye;
    dome_options.radius_m = s.sky_dome_radius;
    mesh::Heightfield field;
    if (!dome) {
        const scene::TerrainSpec t = *scene.terrain;
        field.height_m = [t](double x, double y) { return scene::terrain_height(t, x, y); };
        field.x0 = t.center.x - 0.5 * t.size;
        field.y0 = t.center.y - 0.5 * t.size;
        field.size_x_m = field.size_y_m = t.size;
    }
    auto uniform = [&](int level) -> Result<mesh::Mesh> {
        return dome ? mesh::geodesic_dome(level, dome_options)
                    : mesh::terrain_grid(field, level, level);
    };
    std::vector<std::unique_ptr<MeshEntry>> meshes;
    for (int level : levels) {
        auto m = uniform(level);
        if (!m) return m.error();
        auto e = std::make_unique<MeshEntry>();
        e->tessellation = "uniform";
        e->is_default = level == default_level;
        e->mesh = scene::mesh_data_from(*m, repeat);
        e->max_distance_m = farthest_m(e->mesh, scene);
        meshes.push_back(std::move(e));
    }
    // Adaptive: from a coarse base, refined for this view until every face is within 1 LSB or
    // the budget (the vertex count of the uniform mesh of the same level) is spent.
    auto base = dome ? mesh::geodesic_dome(4, dome_options) : mesh::terrain_grid(field, 8, 8);
    if (!base) return base.error();
    const mesh::Surface surface =
        dome ? mesh::Surface::sphere(dome_options) : mesh::Surface::terrain(field);
    const std::size_t uniform_count = meshes.size();
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        auto frame = prepare_frame<float>(scene.atmosphere, scene.view(), model);
        if (!frame) return frame.error();
        for (std::size_t i = 0; i < uniform_count; ++i) {
            mesh::AdaptiveSettings a;
            a.colour.display = scene.display;
            a.colour.texel = dome ? glm::vec3(0.0f) : brightest_texel(scene.texture);
            a.split_lsb = 1.0f;
            a.lock_boundary = false;
            a.max_vertices = meshes[i]->mesh.vertex_count();
            auto adaptive = mesh::AdaptiveMesh::create(*base, surface, a);
            if (!adaptive) return adaptive.error();
            mesh::AdaptiveMesh& am = adaptive.value();
            for (int pass = 0; pass < 64; ++pass) {
                const mesh::UpdateStats stats = am.update(*frame);
                if (stats.complete || stats.splits == 0) break;
            }
            am.compact();
            // Refinement that finished under a smaller budget gives the same mesh again.
            if (meshes.back()->is_adaptive_of(model) &&
                meshes.back()->mesh.vertex_count() == mesh::live_vertices(am.mesh()))
                continue;
            auto e = std::make_unique<MeshEntry>();
            e->tessellation = "adaptive";
            e->adapted_to = model;
            e->mesh = scene::mesh_data_from(am.mesh(), repeat);
            e->max_distance_m = farthest_m(e->mesh, scene);
            meshes.push_back(std::move(e));
        }
    }
    return meshes;
}

// ---- Frames -----------------------------------------------------------------------------------

void begin_frame(const gl::Api& api, const scene::SceneFile& scene, const Matrices& m) {
    api.ClearColor(float(scene.background.r), float(scene.background.g), float(scene.background.b),
                   1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    load_matrix(api, GL_PROJECTION, m.projection);
    load_matrix(api, GL_MODELVIEW, m.view);
    api.Color4f(1.0f, 1.0f, 1.0f, 1.0f);
}

Error framed(const char* method, const Error& e) {
    return Error{e.field, std::string(method) + ": " + e.message};
}

/// One frame of a variant, from the per-frame constants to glFinish (per-pixel: to its
/// composited image). The image is left in the colour buffer or, per-pixel, in `pixels`.
std::optional<Error> render_frame(const headless::Context& context, const scene::SceneFile& scene,
                                  const Matrices& matrices, Variant& v, SceneGl& sgl,
                                  std::vector<std::uint8_t>& pixels) {
    const gl::Api& api = context.api();
    const scene::MeshData& mesh = v.mesh->mesh;
    const char* name = method_name(v.method);
    const std::function<void()> draw = [&] { draw_arrays(api, mesh); };
    begin_frame(api, scene, matrices);
    auto frame = prepare_frame<float>(scene.atmosphere, scene.view(), method_model(v.method));
    if (!frame) return framed(name, frame.error());
    const std::size_t n = mesh.vertex_count();
    switch (v.method) {
        case Method::gl_fog: {
            const validation::FogParameters fog = validation::fog_parameters(*frame, scene.display);
            api.Fogi(GL_FOG_MODE, GL_EXP);
            api.Fogf(GL_FOG_DENSITY, fog.density);
            api.Fogfv(GL_FOG_COLOR, fog.colour);
            api.Enable(GL_FOG);
            draw();
            api.Disable(GL_FOG);
            break;
        }
        case Method::fg_fog: {
            const FlightGearFog fog = flightgear_fog(*frame, scene.display);
            flightgear_fog_coordinates(fog, *frame, mesh.positions.data(), n, sgl.coords);
            if (auto e = draw_with_flightgear_fog(api, fog, sgl.coords.data(), draw))
                return framed(name, *e);
            break;
        }
        case Method::cpu_hp:
        case Method::cpu_height:
        case Method::arb_hp:
        case Method::arb_height: {
            const bool arb = v.method == Method::arb_hp || v.method == Method::arb_height;
            scene::FrameSettings settings = scene.frame_settings();
            settings.model = method_model(v.method);
            auto report = sgl.renderer[arb ? 1 : 0]->render(
                *v.mesh->graph, scene.camera_for(context.width(), context.height()), settings);
            if (!report) return framed(name, report.error());
            break;
        }
        case Method::lut_texture: {
            sgl.lut->texcoords(*frame, mesh.positions.data(), n, sgl.coords);
            sgl.lut->draw(sgl.coords.data(), draw);
            break;
        }
        case Method::perpixel: {
            draw();
            api.Finish();
            pixels = context.read_rgba8();
            if (auto e = validation::shade_per_pixel(context, *frame, scene.display,
                                                     matrices.projection, matrices.view, pixels))
                return framed(name, *e);
            return std::nullopt;
        }
    }
    api.Finish();
    return std::nullopt;
}

/// The per-pixel image of the `reference` model on this mesh.
Result<std::vector<std::uint8_t>> reference_image(const headless::Context& context,
                                                  const scene::SceneFile& scene,
                                                  const Matrices& matrices,
                                                  const scene::MeshData& mesh) {
    const gl::Api& api = context.api();
    auto frame = prepare_frame<float>(scene.atmosphere, scene.view(), Model::reference);
    if (!frame) return frame.error();
    begin_frame(api, scene, matrices);
    draw_arrays(api, mesh);
    api.Finish();
    std::vector<std::uint8_t> pixels = context.read_rgba8();
    if (auto e = validation::shade_per_pixel(context, *frame, scene.display, matrices.projection,
                                             matrices.view, pixels))
        return *e;
    return pixels;
}

/// The per-pixel image of the `reference` model on the sphere a sky dome stands for: each
/// pixel's ray from the eye (the dome's centre) to the sphere of `radius`; below the horizon
/// (where the open dome draws nothing) the background. Independent of the dome's tessellation.
Result<std::vector<std::uint8_t>> dome_reference_image(const scene::SceneFile& scene,
                                                       const Matrices& matrices, int w, int h,
                                                       double radius) {
    auto frame = prepare_frame<float>(scene.atmosphere, scene.view(), Model::reference);
    if (!frame) return frame.error();
    const glm::dmat4 world_from_clip = glm::inverse(glm::dmat4(glm::mat4(matrices.projection)) *
                                                    glm::dmat4(glm::mat4(matrices.view)));
    std::vector<std::uint8_t> rgba(4 * std::size_t(w) * std::size_t(h), 255);
    std::vector<float> positions;
    std::vector<std::size_t> pixels;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t pixel = std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x);
            const glm::dvec4 p = world_from_clip * glm::dvec4(2.0 * (x + 0.5) / w - 1.0,
                                                              2.0 * (y + 0.5) / h - 1.0, 1.0, 1.0);
            const glm::dvec3 dir = glm::normalize(glm::dvec3(p) / p.w - scene.camera.eye);
            if (glm::dot(dir, scene.camera.up) < 0.0) {
                for (int c = 0; c < 3; ++c)
                    rgba[4 * pixel + std::size_t(c)] = to_unorm8(float(scene.background[c]));
                continue;
            }
            const glm::dvec3 q = scene.camera.eye + radius * dir;
            positions.insert(positions.end(), {float(q.x), float(q.y), float(q.z)});
            pixels.push_back(pixel);
        }
    }
    std::vector<float> extinction(positions.size()), in_scattering(positions.size());
    BatchOutputs out;
    out.extinction_rgb = extinction.data();
    out.in_scattering_rgb = in_scattering.data();
    BatchSettings settings;
    settings.display = scene.display;
    auto stats = shade_into(*frame, Positions::aos(positions.data(), pixels.size()), out, settings);
    if (!stats) return stats.error();
    // The dome's texture is black: the sky shows L_in alone (validation::shade_per_pixel's rule
    // with a texel of 0).
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        for (std::size_t c = 0; c < 3; ++c) {
            rgba[4 * pixels[i] + c] =
                to_unorm8(display_value(scene.display, in_scattering[3 * i + c]));
        }
    }
    return rgba;
}

std::optional<Error> write_image(const std::string& dir, const std::string& name, int w, int h,
                                 const std::vector<std::uint8_t>& rgba) {
    if (dir.empty()) return std::nullopt;
    if (auto e = tools::write_png(dir + "/" + name + ".png", tools::rgb_from_rgba8(w, h, rgba)))
        return Error{"--out", "--out: " + *e};
    return std::nullopt;
}

Result<std::vector<BenchRow>> run_scene(const headless::Context& context, const BenchScene& bs,
                                        const BenchOptions& options, std::FILE* progress) {
    const gl::Api& api = context.api();
    const scene::SceneFile& scene = bs.scene;
    const int w = context.width(), h = context.height();
    const auto start = Clock::now();
    auto built = build_meshes(bs, options.quick);
    if (!built) return Error{built.error().field, bs.name + ": " + built.error().message};
    std::vector<std::unique_ptr<MeshEntry>>& meshes = built.value();
    std::fprintf(progress, "%s: %zu meshes built in %.1f s\n", bs.name.c_str(), meshes.size(),
                 ms_since(start) / 1000.0);

    api.Viewport(0, 0, w, h);
    api.Enable(GL_DEPTH_TEST);
    api.DepthFunc(GL_LEQUAL);
    const Matrices matrices = camera_matrices(scene.camera_for(w, h));
    const BoundTexture texture(api, scene::scene_texture(scene.texture));

    // The reference image of each mesh (of a dome: of the sphere, shared by all).
    std::optional<std::vector<std::uint8_t>> dome_reference;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const auto t = Clock::now();
        if (bs.sky_dome_radius > 0.0 && dome_reference) {
            meshes[i]->reference = *dome_reference;
            continue;
        }
        auto ref = bs.sky_dome_radius > 0.0
                       ? dome_reference_image(scene, matrices, w, h, bs.sky_dome_radius)
                       : reference_image(context, scene, matrices, meshes[i]->mesh);
        if (ref && bs.sky_dome_radius > 0.0) dome_reference = *ref;
        if (!ref) return Error{ref.error().field, bs.name + ": reference: " + ref.error().message};
        meshes[i]->reference = std::move(ref.value());
        std::fprintf(progress, "%s: reference image %zu/%zu (%s, %zu vertices) in %.1f s\n",
                     bs.name.c_str(), i + 1, meshes.size(),
                     bs.sky_dome_radius > 0.0 ? "the sphere" : meshes[i]->tessellation.c_str(),
                     meshes[i]->mesh.vertex_count(), ms_since(t) / 1000.0);
        if (meshes[i]->is_default || bs.sky_dome_radius > 0.0) {
            if (auto e = write_image(options.images_dir, bs.name + "-reference", w, h,
                                     meshes[i]->reference))
                return *e;
        }
    }

    // What an engine creates once: programs, tables, the combiner path's texture.
    SceneGl sgl;
    for (int i = 0; i < 2; ++i) {
        scene::RendererOptions renderer_options;
        renderer_options.backend = i == 0 ? scene::Backend::cpu : scene::Backend::arb;
        auto renderer = scene::SceneRenderer::create(api, renderer_options);
        if (!renderer)
            return Error{renderer.error().field, bs.name + ": " + renderer.error().message};
        sgl.renderer[i].emplace(std::move(renderer.value()));
    }
    const auto texture_data = std::make_shared<scene::Texture>(scene::scene_texture(scene.texture));
    for (const auto& m : meshes) {
        m->graph = scene::make_group(bs.name);
        m->graph->add(scene::make_mesh(m->tessellation, std::make_shared<scene::MeshData>(m->mesh),
                                       texture_data));
    }
    const MeshEntry* default_mesh = nullptr;
    for (const auto& m : meshes)
        if (m->is_default) default_mesh = m.get();
    {
        // The tables span the default mesh's distances; built once per sun position.
        auto frame = prepare_frame<float>(scene.atmosphere, scene.view(), Model::hoffman_preetham);
        if (!frame) return Error{frame.error().field, bs.name + ": " + frame.error().message};
        auto lut = LutTexture::create(api, *frame, scene.display, default_mesh->max_distance_m);
        if (!lut) return Error{lut.error().field, bs.name + ": " + lut.error().message};
        sgl.lut.emplace(std::move(lut.value()));
    }

    std::vector<Variant> variants;
    for (const MethodInfo& method : kMethods) {
        const Method m = method.method;
        for (const auto& mesh : meshes) {
            const bool take = per_vertex(m) ? (mesh->tessellation == "uniform" ||
                                               mesh->adapted_to == method_model(m))
                                            : mesh->is_default;
            if (take) variants.push_back(Variant{m, mesh.get(), kNotTimed, {}});
        }
    }
    // Interleaved repetitions: every variant once per round; the best time is kept and the
    // last round's image graded.
    std::vector<std::uint8_t> pixels;
    for (int r = 0; r < options.repetitions; ++r) {
        for (Variant& v : variants) {
            const auto t = Clock::now();
            if (auto e = render_frame(context, scene, matrices, v, sgl, pixels))
                return Error{e->field, bs.name + ": " + e->message};
            v.best_ms = std::min(v.best_ms, ms_since(t));
            if (r + 1 == options.repetitions) {
                v.image = v.method == Method::perpixel ? pixels : context.read_rgba8();
            }
        }
        std::fprintf(progress, "%s: timing round %d/%d done\n", bs.name.c_str(), r + 1,
                     options.repetitions);
    }
    if (const GLenum error = api.GetError(); error != GL_NO_ERROR) {
        return Error{"GL", bs.name + ": GL error " + gl::gl_error_name(error)};
    }

    std::vector<BenchRow> rows;
    for (const Variant& v : variants) {
        const tools::Rgb8Image a = tools::rgb_from_rgba8(w, h, v.image);
        const tools::Rgb8Image b = tools::rgb_from_rgba8(w, h, v.mesh->reference);
        const tools::ImageDifferences d = tools::compare_images(a, b);
        BenchRow row;
        row.scene = bs.name;
        row.method = method_name(v.method);
        row.tessellation = v.mesh->tessellation;
        row.vertices = v.mesh->mesh.vertex_count();
        row.ms_per_frame = v.best_ms;
        row.max_lsb = d.max_lsb;
        row.p99_lsb = d.p99_lsb;
        row.rmse_lsb = d.rmse_lsb;
        row.de2000_mean = d.de2000_mean;
        row.default_mesh = v.mesh->is_default;
        std::fprintf(progress, "%s: %-18s %-8s %7zu vertices %8.2f ms  rmse %6.2f  p99 %3d LSB\n",
                     bs.name.c_str(), row.method.c_str(), row.tessellation.c_str(), row.vertices,
                     row.ms_per_frame, row.rmse_lsb, row.p99_lsb);
        if (v.mesh->is_default) {
            if (auto e = write_image(options.images_dir, bs.name + "-" + row.method, w, h, v.image))
                return *e;
        }
        rows.push_back(row);
    }
    std::fprintf(progress, "%s: done in %.1f s\n", bs.name.c_str(), ms_since(start) / 1000.0);
    return rows;
}

}  // namespace

Result<std::vector<BenchRow>> run_bench(const std::vector<BenchScene>& scenes,
                                        const BenchOptions& options, std::FILE* progress) {
    headless::ContextOptions co;
    co.width = options.width;
    co.height = options.height;
    auto context = headless::Context::create(co);
    if (!context) return Error{context.error().field, "context: " + context.error().message};
    std::fprintf(progress, "GL_RENDERER %s, %dx%d, best of %d\n",
                 context->api().caps.renderer.c_str(), options.width, options.height,
                 options.repetitions);
    std::vector<BenchRow> rows;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        std::fprintf(progress, "[scene %zu/%zu] %s: %s\n", i + 1, scenes.size(),
                     scenes[i].name.c_str(), scenes[i].description.c_str());
        auto r = run_scene(context.value(), scenes[i], options, progress);
        if (!r) return r.error();
        rows.insert(rows.end(), r->begin(), r->end());
    }
    return rows;
}

std::optional<std::string> write_bench_csv(const std::string& path,
                                           const std::vector<BenchRow>& rows) {
    if (auto e = tools::make_parent_directories(path)) return e;
    std::ofstream csv(path);
    if (!csv) return "cannot write " + path;
    csv << "scene,method,tessellation,vertices,ms_per_frame,max_lsb,p99_lsb,rmse_lsb,de2000_mean\n";
    for (const BenchRow& r : rows) {
        char line[512];
        std::snprintf(line, sizeof line, "%s,%s,%s,%zu,%.4f,%d,%d,%.4f,%.4f\n", r.scene.c_str(),
                      r.method.c_str(), r.tessellation.c_str(), r.vertices, r.ms_per_frame,
                      r.max_lsb, r.p99_lsb, r.rmse_lsb, r.de2000_mean);
        csv << line;
    }
    csv.close();
    if (!csv) return "cannot write " + path;
    return std::nullopt;
}

namespace {

/// No row of the scene is at least as fast and at least as accurate (rmse), and better in one.
bool on_pareto_front(const std::vector<BenchRow>& rows, const BenchRow& row) {
    for (const auto& r : rows) {
        if (r.scene != row.scene || &r == &row) continue;
        if (r.ms_per_frame <= row.ms_per_frame && r.rmse_lsb <= row.rmse_lsb &&
            (r.ms_per_frame < row.ms_per_frame || r.rmse_lsb < row.rmse_lsb))
            return false;
    }
    return true;
}

}  // namespace

std::vector<std::string> summarise(const std::vector<BenchRow>& rows) {
    std::vector<std::string> scenes;
    for (const auto& r : rows)
        if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end())
            scenes.push_back(r.scene);
    std::vector<std::string> lines;
    int speed_ok = 0, error_ok = 0, method_front = 0, row_front = 0;
    char buffer[640];
    for (const auto& s : scenes) {
        const BenchRow *fog = nullptr, *arb = nullptr, *best = nullptr;
        for (const auto& r : rows) {
            if (r.scene != s) continue;
            if (r.method == "gl-fog") fog = &r;
            if (r.method == "arb-hp" && r.tessellation == "uniform" && r.default_mesh) arb = &r;
            if (is_per_vertex_name(r.method) && (!best || r.rmse_lsb < best->rmse_lsb)) best = &r;
        }
        if (!fog || !arb || !best) continue;
        // Our best method: the per-vertex method of the most accurate per-vertex row; it is on
        // the front when one of its rows (tessellations) is.
        int rows_of_best = 0, on_front = 0;
        for (const auto& r : rows) {
            if (r.scene != s || r.method != best->method) continue;
            ++rows_of_best;
            on_front += on_pareto_front(rows, r);
        }
        const bool best_row_on_front = on_pareto_front(rows, *best);
        const double ratio = arb->ms_per_frame / fog->ms_per_frame;
        speed_ok += ratio <= 1.25;
        error_ok += best->rmse_lsb < fog->rmse_lsb;
        method_front += on_front > 0;
        row_front += best_row_on_front;
        std::snprintf(buffer, sizeof buffer,
                      "%s: arb-hp/gl-fog frame time %.2f (%.2f / %.2f ms, %zu vertices); best "
                      "per-vertex %s (rmse %.2f LSB at %s %zu vertices) against gl-fog %.2f; "
                      "%d of its %d rows on the Pareto front, its most accurate row %s",
                      s.c_str(), ratio, arb->ms_per_frame, fog->ms_per_frame, arb->vertices,
                      best->method.c_str(), best->rmse_lsb, best->tessellation.c_str(),
                      best->vertices, fog->rmse_lsb, on_front, rows_of_best,
                      best_row_on_front ? "on it" : "not");
        lines.emplace_back(buffer);
    }
    const int n = int(scenes.size());
    std::snprintf(buffer, sizeof buffer, "arb-hp <= 1.25x gl-fog frame time: %d of %d scenes",
                  speed_ok, n);
    lines.emplace_back(buffer);
    std::snprintf(buffer, sizeof buffer,
                  "a per-vertex method with lower rmse than gl-fog: %d of %d scenes", error_ok, n);
    lines.emplace_back(buffer);
    std::snprintf(buffer, sizeof buffer,
                  "best per-vertex method with a row on the Pareto front: %d of %d scenes",
                  method_front, n);
    lines.emplace_back(buffer);
    std::snprintf(buffer, sizeof buffer,
                  "its most accurate row on the Pareto front: %d of %d scenes", row_front, n);
    lines.emplace_back(buffer);
    return lines;
}

}  // namespace aerial::bench
