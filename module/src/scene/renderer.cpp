// The scene renderer: traversal, frustum culling, the update policy, the cpu and arb backends.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "../common/names.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/cache.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state_saver.hpp"
#include "aerial/phase.hpp"
#include "aerial/scene_renderer.hpp"

namespace aerial::scene {
namespace {

/// Vertices of a node compared between the 2002 model and the frame's model (besides the 8
/// corners of its box) when the policy chooses a method.
constexpr std::size_t kMethodSampleVertices = 25;
/// Directions (cosine-weighted, stratified) averaged for the ambient sky irradiance.
constexpr int kAmbientStrata = 6;
/// The ambient sky light is estimated again when the sun has turned this much (rad) since the
/// last estimate (or the atmosphere or model changed); between estimates it stays the same, so
/// that small sun moves keep the colour caches (any change of the ambient invalidates them).
constexpr double kAmbientSunStepRad = 0.25 * kPi / 180.0;
/// Distance of the sky points of the ambient estimate, m.
constexpr double kAmbientSkyDistanceM = 200e3;

bool same_atmosphere(const Atmosphere& a, const Atmosphere& b) {
    return a.rayleigh_scattering == b.rayleigh_scattering && a.mie_scattering == b.mie_scattering &&
           a.mie_absorption == b.mie_absorption && a.mie_g == b.mie_g &&
           a.rayleigh_scale_height_m == b.rayleigh_scale_height_m &&
           a.mie_scale_height_m == b.mie_scale_height_m && a.planet_radius_m == b.planet_radius_m &&
           a.atmosphere_radius_m == b.atmosphere_radius_m && a.sun_irradiance == b.sun_irradiance;
}

double max3(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

/// The planes of the view frustum (a x + b y + c z + d >= 0 inside), world space.
std::array<glm::dvec4, 6> frustum_planes(const glm::dmat4& clip_from_world) {
    const glm::dmat4 m = glm::transpose(clip_from_world);  // rows of clip_from_world as columns
    std::array<glm::dvec4, 6> planes{m[3] + m[0], m[3] - m[0], m[3] + m[1],
                                     m[3] - m[1], m[3] + m[2], m[3] - m[2]};
    for (auto& p : planes) p /= glm::length(glm::dvec3(p));
    return planes;
}

bool sphere_outside(const std::array<glm::dvec4, 6>& planes, const glm::dvec3& c, double r) {
    for (const auto& p : planes) {
        if (glm::dot(glm::dvec3(p), c) + p.w < -r) return true;
    }
    return false;
}

void load_matrix(const gl::Api& api, GLenum mode, const glm::dmat4& m) {
    const glm::mat4 f(m);
    api.MatrixMode(mode);
    api.LoadMatrixf(glm::value_ptr(f));
}

/// Saves the client vertex array (enable, pointer, buffer) and puts it back.
class VertexArraySaver {
  public:
    explicit VertexArraySaver(const gl::Api& api) : api_(api) {
        enabled_ = api.IsEnabled(GL_VERTEX_ARRAY);
        api.GetIntegerv(GL_VERTEX_ARRAY_SIZE, &size_);
        api.GetIntegerv(GL_VERTEX_ARRAY_TYPE, &type_);
        api.GetIntegerv(GL_VERTEX_ARRAY_STRIDE, &stride_);
        api.GetPointerv(GL_VERTEX_ARRAY_POINTER, &pointer_);
        if (api.BindBuffer) api.GetIntegerv(GL_VERTEX_ARRAY_BUFFER_BINDING, &buffer_);
    }
    ~VertexArraySaver() {
        GLint current = 0;
        if (api_.BindBuffer) {
            api_.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &current);
            api_.BindBuffer(GL_ARRAY_BUFFER, GLuint(buffer_));
        }
        api_.VertexPointer(size_, GLenum(type_), stride_, pointer_);
        if (api_.BindBuffer) api_.BindBuffer(GL_ARRAY_BUFFER, GLuint(current));
        (enabled_ ? api_.EnableClientState : api_.DisableClientState)(GL_VERTEX_ARRAY);
    }
    VertexArraySaver(const VertexArraySaver&) = delete;
    VertexArraySaver& operator=(const VertexArraySaver&) = delete;

  private:
    const gl::Api& api_;
    GLboolean enabled_ = GL_FALSE;
    GLint size_ = 4, type_ = GL_FLOAT, stride_ = 0, buffer_ = 0;
    void* pointer_ = nullptr;
};

/// What the renderer keeps per mesh node between frames.
struct NodeState {
    std::shared_ptr<const MeshData> mesh;  ///< the mesh the arrays below were made from
    glm::dmat4 world{0.0};
    std::vector<float> positions;  ///< world space
    std::vector<float> normals;    ///< world space, unit
    MeshBounds bounds;
    std::vector<std::uint8_t> primary, secondary;  ///< RGBA8 colours (cpu backend)
    bool has_colours = false;
    Model model = Model::height;  ///< what the colours (or the arb choice) were computed with
    bool has_choice = false;      ///< arb backend: a method chosen and its cache valid
    ShadingCache cache;
    /// The colours of a skipped node were made for these (lighting only).
    bool skip_colours = false;
    glm::dvec3 skip_sun{0.0};
    glm::vec3 skip_light{-1.0f};
    std::uint64_t last_frame = 0;
};

struct SkyAmbientCache {
    bool valid = false;
    Atmosphere atmosphere;
    glm::dvec3 sun_dir{0.0};
    glm::dvec3 up{0.0};
    Model model = Model::height;
    glm::vec3 ambient{0.0f};
};

}  // namespace

struct SceneRenderer::Impl {
    const gl::Api* api = nullptr;
    RendererOptions options;
    gl::Path path = gl::Path::automatic;
    std::optional<gl::CombinerTexture> combiner;
    std::optional<gl::ArbVertexProgram> program_hp, program_height;
    /// The options each program was generated with (the height fidelity resolved against the
    /// driver's native limits); its parameters are computed with the same.
    ArbProgramOptions arb_hp, arb_height;
    SkyDrawer sky = default_sky_drawer();
    SkyDrawer sun = default_sun_drawer();
    std::unordered_map<const Node*, NodeState> nodes;
    std::map<const Texture*, std::pair<std::shared_ptr<const Texture>, GLuint>> textures;
    GLuint light_texture = 0;  ///< arb backend: 1×1 lighting factor on unit 1
    SkyAmbientCache ambient;
    std::uint64_t frame = 0;

    ~Impl() { release_gl(); }

    void release_gl() {
        if (!api) return;
        for (auto& entry : textures) api->DeleteTextures(1, &entry.second.second);
        textures.clear();
        if (light_texture) api->DeleteTextures(1, &light_texture);
        light_texture = 0;
    }

    GLuint texture_id(const std::shared_ptr<const Texture>& texture) {
        auto it = textures.find(texture.get());
        if (it != textures.end()) return it->second.second;
        GLuint id = 0;
        api->GenTextures(1, &id);
        api->BindTexture(GL_TEXTURE_2D, id);
        const auto levels = mipmap_levels(*texture);
        int w = texture->width, h = texture->height;
        for (std::size_t l = 0; l < levels.size(); ++l) {
            api->TexImage2D(GL_TEXTURE_2D, GLint(l), GL_RGB8, w, h, 0, GL_RGB, GL_UNSIGNED_BYTE,
                            levels[l].data());
            w = std::max(1, w / 2);
            h = std::max(1, h / 2);
        }
        api->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        api->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        api->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
        api->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
        textures.emplace(texture.get(), std::make_pair(texture, id));
        return id;
    }
};

// ---- Names -------------------------------------------------------------------------------------

constexpr aerial::detail::NameTable<Backend, 2> kBackendNames{
    {{Backend::cpu, "cpu"}, {Backend::arb, "arb"}}};

const char* backend_name(Backend backend) {
    return aerial::detail::name_in(kBackendNames, backend);
}

Result<Backend> parse_backend(std::string_view name) {
    return aerial::detail::parse_in(kBackendNames, "backend", name);
}

constexpr aerial::detail::NameTable<Method, 6> kMethodNames{
    {{Method::culled, "culled"},
     {Method::skipped, "skipped"},
     {Method::cached, "cached"},
     {Method::hoffman_preetham, "hoffman-preetham"},
     {Method::height, "height"},
     {Method::reference, "reference"}}};

const char* method_name(Method method) { return aerial::detail::name_in(kMethodNames, method); }

std::string FrameReport::main_method() const {
    std::map<Method, std::size_t> vertices;
    for (const NodeReport& n : nodes) {
        if (n.method != Method::culled) vertices[n.method] += n.vertices;
    }
    Method best = Method::culled;
    std::size_t most = 0;
    for (Method m : {Method::hoffman_preetham, Method::height, Method::reference}) {
        if (vertices[m] > most) {
            most = vertices[m];
            best = m;
        }
    }
    if (most > 0) return method_name(best);
    if (vertices[Method::cached] > 0) return "cached";
    if (vertices[Method::skipped] > 0) return "skipped";
    return "none";
}

// ---- Camera ------------------------------------------------------------------------------------

std::optional<Error> validate(const Camera& camera) {
    const auto finite3 = [](const glm::dvec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    if (!finite3(camera.eye)) return Error{"camera.eye", "camera.eye: not finite"};
    if (!finite3(camera.target) || camera.target == camera.eye) {
        return Error{"camera.target", "camera.target: must be finite and differ from camera.eye"};
    }
    const glm::dvec3 forward = camera.target - camera.eye;
    if (!finite3(camera.up) || glm::length(glm::cross(forward, camera.up)) <=
                                   1e-9 * glm::length(forward) * glm::length(camera.up)) {
        return Error{"camera.up", "camera.up: must be finite and not parallel to the view"};
    }
    if (!(camera.fov_y_rad > 0.0 && camera.fov_y_rad < 3.14159)) {
        return Error{"camera.fov_y_rad", "camera.fov_y_rad: expected a value in (0, pi), got " +
                                             std::to_string(camera.fov_y_rad)};
    }
    if (!(camera.aspect > 0.0) || !std::isfinite(camera.aspect)) {
        return Error{"camera.aspect", "camera.aspect: expected a finite value > 0"};
    }
    if (!(camera.near_units > 0.0) || !(camera.far_units > camera.near_units) ||
        !std::isfinite(camera.far_units)) {
        return Error{"camera.near_units",
                     "camera.near_units: expected 0 < near_units < far_units (finite), got " +
                         std::to_string(camera.near_units) + " and " +
                         std::to_string(camera.far_units)};
    }
    return std::nullopt;
}

glm::dmat4 projection_matrix(const Camera& camera) {
    return glm::perspective(camera.fov_y_rad, camera.aspect, camera.near_units, camera.far_units);
}

glm::dmat4 view_matrix(const Camera& camera) {
    return glm::lookAt(camera.eye, camera.target, camera.up);
}

// ---- The renderer ------------------------------------------------------------------------------

SceneRenderer::SceneRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SceneRenderer::SceneRenderer(SceneRenderer&&) noexcept = default;
SceneRenderer& SceneRenderer::operator=(SceneRenderer&&) noexcept = default;
SceneRenderer::~SceneRenderer() = default;

const RendererOptions& SceneRenderer::options() const { return impl_->options; }
void SceneRenderer::set_sky_drawer(SkyDrawer drawer) { impl_->sky = std::move(drawer); }
void SceneRenderer::set_sun_drawer(SkyDrawer drawer) { impl_->sun = std::move(drawer); }
void SceneRenderer::clear_caches() {
    impl_->nodes.clear();
    impl_->textures.clear();
    impl_->light_texture = 0;
    impl_->ambient.valid = false;
}

Result<SceneRenderer> SceneRenderer::create(const gl::Api& api, const RendererOptions& options) {
    if (auto e = gl::no_current_context(api)) return *e;
    auto impl = std::make_unique<Impl>();
    impl->api = &api;
    impl->options = options;
    const std::string where = std::string("backend ") + backend_name(options.backend) + ": ";
    if (options.backend == Backend::cpu) {
        auto path = gl::choose_path(api.caps, options.path);
        if (!path) return Error{path.error().field, where + path.error().message};
        impl->path = *path;
        if (*path == gl::Path::combiner) {
            auto combiner = gl::CombinerTexture::create(api);
            if (!combiner) return Error{combiner.error().field, where + combiner.error().message};
            impl->combiner.emplace(std::move(combiner.value()));
        }
    } else {
        if (options.path != gl::Path::automatic) {
            return Error{"path", where + "path: only the cpu backend takes a fixed-function path"};
        }
        auto path = gl::choose_path(api.caps, gl::Path::automatic);
        if (!path) return Error{path.error().field, where + path.error().message};
        impl->path = *path;  // for nodes drawn without the program (skipped by the policy)
        if (*path == gl::Path::combiner) {
            auto combiner = gl::CombinerTexture::create(api);
            if (!combiner) return Error{combiner.error().field, where + combiner.error().message};
            impl->combiner.emplace(std::move(combiner.value()));
        }
        for (Model model : {Model::hoffman_preetham, Model::height}) {
            ArbProgramOptions arb;
            arb.model = model;
            arb.limits = gl::native_arb_limits(api);  // the most accurate height program it takes
            auto text = generate_arb_program(arb);
            if (!text) return Error{text.error().field, where + text.error().message};
            auto program = gl::ArbVertexProgram::create(api, *text);
            if (!program) return Error{program.error().field, where + program.error().message};
            (model == Model::height ? impl->program_height : impl->program_hp)
                .emplace(std::move(program.value()));
            (model == Model::height ? impl->arb_height : impl->arb_hp) = text->options;
        }
    }
    return SceneRenderer(std::move(impl));
}

namespace {

/// Sky irradiance on a level surface at sea level below the eye: pi times the cosine-weighted
/// mean of L_in over the upper hemisphere (terrain occlusion ignored). Sea level, not the eye,
/// so that it changes only with the sun and the atmosphere (a flying eye keeps cached colours).
glm::vec3 sky_ambient(const FrameSettings& s) {
    View view;
    view.up = s.up;
    view.sun_dir = s.sun_dir;
    view.meters_per_unit = 1.0;
    view.eye = s.up * 2.0;
    auto frame = prepare_frame<double>(s.atmosphere, view, s.model);
    if (!frame) return glm::vec3(0.0f);
    glm::dvec3 e1 = glm::normalize(
        glm::cross(s.up, std::abs(s.up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    glm::dvec3 e2 = glm::cross(s.up, e1);
    glm::dvec3 sum{0.0};
    for (int i = 0; i < kAmbientStrata; ++i) {
        for (int j = 0; j < kAmbientStrata; ++j) {
            const double r = std::sqrt((i + 0.5) / kAmbientStrata);
            const double phi = 2.0 * kPi * (j + 0.5) / kAmbientStrata;
            const glm::dvec3 dir =
                r * std::cos(phi) * e1 + r * std::sin(phi) * e2 + std::sqrt(1.0 - r * r) * s.up;
            sum += scatter(*frame, view.eye + dir * kAmbientSkyDistanceM).in_scattering;
        }
    }
    return glm::vec3(kPi * sum / double(kAmbientStrata * kAmbientStrata));
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
            primary = display_value(
                display, s.extinction[c] * albedo[c] * (s.sun_irradiance[c] * ndl + ambient[c]));
        }
        out.primary[c] = 255.0f * std::clamp(primary, 0.0f, 1.0f);
        out.secondary[c] = 255.0f * display_value(display, s.in_scattering[c]);
    }
    return out;
}

/// The largest 8-bit difference between the 2002 model and `frame`'s over the node's samples.
double model_difference_lsb(const Frame<float>& hp, const Frame<float>& frame, const NodeState& st,
                            bool lit, const glm::vec3& albedo, const glm::vec3& ambient,
                            const Display& display) {
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
    }
    return worst;
}

Method method_of(Model model) {
    switch (model) {
        case Model::hoffman_preetham:
            return Method::hoffman_preetham;
        case Model::height:
            return Method::height;
        case Model::reference:
            return Method::reference;
    }
    return Method::height;
}

/// World-space arrays and bounds of a node, rebuilt when its mesh or world transform changed.
void update_geometry(NodeState& st, const Node& node, const glm::dmat4& world) {
    if (st.mesh == node.mesh && st.world == world) return;
    st.mesh = node.mesh;
    st.world = world;
    const MeshData& mesh = *node.mesh;
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

}  // namespace

Result<FrameReport> SceneRenderer::render(const Node& root, const Camera& camera,
                                          const FrameSettings& settings) {
    const auto start = std::chrono::steady_clock::now();
    Impl& im = *impl_;
    const gl::Api& api = *im.api;
    if (auto e = gl::no_current_context(api)) return *e;
    if (auto e = validate(root)) return Error{e->field, "scene: " + e->message};
    if (auto e = validate(camera)) return *e;
    if (!(settings.error_target_lsb >= 0.0)) {
        return Error{"error_target_lsb", "error_target_lsb: expected a value >= 0"};
    }
    if (im.options.backend == Backend::arb && settings.model == Model::reference) {
        return Error{"model",
                     "model: the arb backend has programs for hoffman-preetham and "
                     "height, not reference"};
    }
    if (im.options.backend == Backend::arb && settings.display.tone != ToneCurve::clamp) {
        return Error{"display.tone", "display.tone: the arb backend has only the clamp tone curve"};
    }
    if (!(settings.display.exposure > 0.0f) || !std::isfinite(settings.display.exposure)) {
        return Error{"display.exposure", "display.exposure: expected a finite value > 0"};
    }
    View view;
    view.eye = camera.eye;
    view.sun_dir = settings.sun_dir;
    view.up = settings.up;
    view.meters_per_unit = settings.meters_per_unit;
    auto hp = prepare_frame<float>(settings.atmosphere, view, Model::hoffman_preetham);
    if (!hp) return Error{hp.error().field, "settings: " + hp.error().message};
    auto quality = prepare_frame<float>(settings.atmosphere, view, settings.model);
    if (!quality) return Error{quality.error().field, "settings: " + quality.error().message};
    auto bound_frame = prepare_frame<double>(settings.atmosphere, view, settings.model);
    if (!bound_frame) return bound_frame.error();
    const Frame<float>& frame_of_model_hp = *hp;
    const auto frame_for = [&](Model m) -> const Frame<float>& {
        return m == Model::hoffman_preetham ? frame_of_model_hp : *quality;
    };

    FrameReport report;
    report.path = im.path;
    ++im.frame;

    // Ambient sky light, recomputed only when sun, atmosphere or model change.
    glm::vec3 ambient = settings.ambient;
    if (ambient.r < 0.0f || ambient.g < 0.0f || ambient.b < 0.0f) {
        if (!im.ambient.valid ||
            glm::dot(im.ambient.sun_dir, settings.sun_dir) < std::cos(kAmbientSunStepRad) ||
            im.ambient.up != settings.up || im.ambient.model != settings.model ||
            !same_atmosphere(im.ambient.atmosphere, settings.atmosphere)) {
            im.ambient.ambient = sky_ambient(settings);
            im.ambient.atmosphere = settings.atmosphere;
            im.ambient.sun_dir = settings.sun_dir;
            im.ambient.up = settings.up;
            im.ambient.model = settings.model;
            im.ambient.valid = true;
        }
        ambient = im.ambient.ambient;
    }
    report.ambient = ambient;

    // Cache keys, one per model, prepared once (the albedo is set per node on a copy).
    std::map<Model, PreparedShadingKey> keys;
    const auto key_for = [&](Model m, const glm::vec3& albedo, bool lit) -> PreparedShadingKey {
        auto it = keys.find(m);
        if (it == keys.end()) {
            ShadingKey key{settings.atmosphere, view, m, settings.display};
            key.ambient = ambient;
            auto prepared = prepare_shading_key(key);
            it = keys.emplace(m, std::move(prepared.value())).first;
        }
        PreparedShadingKey k = it->second;
        k.key.albedo = lit ? albedo : glm::vec3(1.0f);
        if (!lit) k.key.ambient = glm::vec3(0.0f);
        return k;
    };

    // GL state: saved here, restored when `saver` and `vertex_array` go out of scope.
    const glm::dmat4 projection = projection_matrix(camera);
    const glm::dmat4 view_m = view_matrix(camera);
    const auto planes = frustum_planes(projection * view_m);
    gl::StateSaver saver(api);
    VertexArraySaver vertex_array(api);
    GLint matrix_mode = GL_MODELVIEW;
    api.GetIntegerv(GL_MATRIX_MODE, &matrix_mode);
    api.MatrixMode(GL_PROJECTION);
    api.PushMatrix();
    api.MatrixMode(GL_MODELVIEW);
    api.PushMatrix();
    struct MatrixRestore {
        const gl::Api& api;
        GLint mode;
        ~MatrixRestore() {
            api.MatrixMode(GL_PROJECTION);
            api.PopMatrix();
            api.MatrixMode(GL_MODELVIEW);
            api.PopMatrix();
            api.MatrixMode(GLenum(mode));
        }
    } matrix_restore{api, matrix_mode};
    load_matrix(api, GL_PROJECTION, projection);
    load_matrix(api, GL_MODELVIEW, view_m);
    GLint unpack_alignment = 4;
    api.GetIntegerv(GL_UNPACK_ALIGNMENT, &unpack_alignment);
    api.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const int units = std::min(2, std::max(1, api.caps.max_texture_units));
    // The saver records a change only when the value differs: switching each enable both ways
    // records the engine's value whatever it was, so the raw changes below are undone too.
    for (int u = 0; u < units; ++u) {
        saver.bind_texture(u, GL_TEXTURE_2D, 0);
        saver.unit_enable(u, GL_TEXTURE_2D, true);
        saver.unit_enable(u, GL_TEXTURE_2D, false);
        saver.tex_env(u, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    }
    saver.select_unit(0);
    saver.texcoord_array(0, 2, GL_FLOAT, 0, nullptr);
    api.DisableClientState(GL_TEXTURE_COORD_ARRAY);
    saver.color_array(4, GL_UNSIGNED_BYTE, 0, nullptr);
    api.DisableClientState(GL_COLOR_ARRAY);
    saver.enable(GL_DEPTH_TEST, true);
    saver.enable(GL_DEPTH_TEST, false);
    saver.depth_mask(false);
    saver.depth_func(GL_LEQUAL);
    saver.enable(GL_LIGHTING, false);
    api.EnableClientState(GL_VERTEX_ARRAY);

    gl::ApplyOptions apply;
    apply.path = im.path;
    apply.combiner = im.combiner ? &*im.combiner : nullptr;

    // Sky and sun behind everything, without depth.
    SkyDrawContext sky_context;
    sky_context.api = &api;
    sky_context.settings = &settings;
    sky_context.camera = &camera;
    sky_context.hoffman_preetham = &*hp;
    sky_context.model = &*quality;
    sky_context.apply = &apply;
    if (im.sky && has_kind(root, NodeKind::sky_dome)) im.sky(sky_context);
    if (im.sun && has_kind(root, NodeKind::sun)) im.sun(sky_context);

    api.Enable(GL_DEPTH_TEST);
    api.DepthMask(GL_TRUE);
    const float light_scale = settings.display.exposure;

    std::optional<Error> failure;
    traverse(root, [&](const Node& node, const glm::dmat4& world) {
        if (failure || (node.kind != NodeKind::mesh && node.kind != NodeKind::terrain)) return;
        NodeState& st = im.nodes[&node];
        st.last_frame = im.frame;
        update_geometry(st, node, world);
        NodeReport nr;
        nr.name = node.name;
        const std::size_t n = st.positions.size() / 3;
        nr.vertices = n;
        if (st.bounds.radius < 0.0 || sphere_outside(planes, st.bounds.centre, st.bounds.radius)) {
            nr.method = Method::culled;
            ++report.culled;
            report.nodes.push_back(nr);
            return;
        }
        const auto shading_start = std::chrono::steady_clock::now();
        const bool lit = node.kind == NodeKind::terrain;
        const glm::vec3 albedo = node.albedo;
        const double lit_max =
            lit ? double(light_scale) * max3(glm::dvec3(albedo)) *
                      (max3(settings.atmosphere.sun_irradiance) + max3(glm::dvec3(ambient)))
                : 1.0;
        // 1. Negligible scattering.
        Method method = method_of(settings.model);
        bool decided = false;
        if (settings.policy && scattering_bound_lsb(*bound_frame, st.bounds, settings.display,
                                                    lit_max) < kSkipBelowLsb) {
            method = Method::skipped;
            decided = true;
        }
        // 2. Cached colours (cpu) or a cached choice (arb).
        if (!decided && settings.policy &&
            (im.options.backend == Backend::cpu ? st.has_colours : st.has_choice)) {
            const PreparedShadingKey key = key_for(st.model, albedo, lit);
            if (!st.cache.needs_update(key)) {
                method = im.options.backend == Backend::cpu ? Method::cached : method_of(st.model);
                decided = true;
                if (im.options.backend == Backend::cpu) ++report.cache_hits;
            }
        }
        // 3. The cheapest model meeting the target.
        Model model = st.model;
        if (!decided) {
            model = settings.model;
            if (settings.policy && settings.model != Model::hoffman_preetham &&
                model_difference_lsb(*hp, *quality, st, lit, albedo, ambient, settings.display) <=
                    settings.error_target_lsb) {
                model = Model::hoffman_preetham;
            }
            method = method_of(model);
            st.model = model;
            st.cache.mark_shaded(key_for(model, albedo, lit));
            if (im.options.backend == Backend::arb) st.has_choice = true;
        }
        nr.method = method;
        report.nodes.push_back(nr);

        // Colours.
        const bool cpu = im.options.backend == Backend::cpu;
        if (method == Method::skipped) {
            ++report.skipped;
            const glm::vec3 sun_e = hp->sun_irradiance_eye;
            if (!st.skip_colours || st.skip_sun != settings.sun_dir || st.skip_light != ambient) {
                for (std::size_t i = 0; i < n; ++i) {
                    for (int c = 0; c < 3; ++c) {
                        float v = 1.0f;
                        if (lit) {
                            const float ndl =
                                st.normals.empty()
                                    ? 1.0f
                                    : std::max(
                                          0.0f,
                                          st.normals[3 * i] * float(settings.sun_dir.x) +
                                              st.normals[3 * i + 1] * float(settings.sun_dir.y) +
                                              st.normals[3 * i + 2] * float(settings.sun_dir.z));
                            v = display_value(settings.display,
                                              albedo[c] * (sun_e[c] * ndl + ambient[c]));
                        }
                        st.primary[4 * i + std::size_t(c)] = to_unorm8(v);
                        st.secondary[4 * i + std::size_t(c)] = 0;
                    }
                }
                st.skip_colours = true;
                st.skip_sun = settings.sun_dir;
                st.skip_light = ambient;
            }
            st.has_colours = false;  // the scattering colours are gone
            st.has_choice = false;
            st.cache.invalidate();
        } else if (cpu && method != Method::cached) {
            BatchOutputs out;
            Lighting lighting;
            if (lit) {
                lighting.normals = st.normals.data();
                lighting.ambient = ambient;
                lighting.albedo = albedo;
                out.lit_rgba8 = st.primary.data();
            } else {
                out.extinction_rgba8 = st.primary.data();
            }
            out.in_scattering_rgba8 = st.secondary.data();
            BatchSettings bs;
            bs.display = settings.display;
            bs.lighting = lit ? &lighting : nullptr;
            auto stats =
                shade_into(frame_for(model), Positions::aos(st.positions.data(), n), out, bs);
            if (!stats) {
                failure = Error{stats.error().field, node.name + ": " + stats.error().message};
                return;
            }
            st.has_colours = true;
            st.skip_colours = false;
            report.vertices_shaded += n;
        } else if (!cpu) {
            report.vertices_shaded += n;
        }
        if (method == Method::hoffman_preetham) ++report.shaded_hoffman_preetham;
        if (method == Method::height) ++report.shaded_height;
        if (method == Method::reference) ++report.shaded_reference;
        report.vertices_drawn += n;
        report.shading_milliseconds += std::chrono::duration<double, std::milli>(
                                           std::chrono::steady_clock::now() - shading_start)
                                           .count();

        // Draw.
        const MeshData& mesh = *node.mesh;
        const bool textured = node.texture && !mesh.texcoords.empty();
        if (api.ActiveTexture) api.ActiveTexture(GL_TEXTURE0);
        if (textured) {
            api.BindTexture(GL_TEXTURE_2D, im.texture_id(node.texture));
            api.Enable(GL_TEXTURE_2D);
        } else {
            api.Disable(GL_TEXTURE_2D);
        }
        const std::function<void()> draw = [&] {
            if (api.ClientActiveTexture) api.ClientActiveTexture(GL_TEXTURE0);
            api.VertexPointer(3, GL_FLOAT, 0, st.positions.data());
            if (textured) {
                api.TexCoordPointer(2, GL_FLOAT, 0, mesh.texcoords.data());
                api.EnableClientState(GL_TEXTURE_COORD_ARRAY);
            }
            api.DrawElements(GL_TRIANGLES, GLsizei(mesh.indices.size()), GL_UNSIGNED_INT,
                             mesh.indices.data());
            if (textured) api.DisableClientState(GL_TEXTURE_COORD_ARRAY);
        };
        gl::ApplyOptions node_apply = apply;
        node_apply.textured = textured;
        if (cpu || method == Method::skipped) {
            gl::VertexColours colours{st.primary.data(), st.secondary.data(), 0, 0, n};
            auto drawn = gl::draw_with_colours(api, node_apply, colours, draw);
            if (!drawn)
                failure = Error{drawn.error().field, node.name + ": " + drawn.error().message};
            return;
        }
        // arb: the program computes F_ex and L_in; lighting is one factor per node on unit 1.
        const bool light_unit = lit && units > 1;
        if (light_unit) {
            const glm::vec3 sun_e = hp->sun_irradiance_eye;
            const float cos_sun = std::max(0.0f, float(glm::dot(settings.sun_dir, settings.up)));
            std::uint8_t texel[3];
            for (int c = 0; c < 3; ++c) {
                texel[c] = to_unorm8(
                    display_value(settings.display, albedo[c] * (sun_e[c] * cos_sun + ambient[c])));
            }
            api.ActiveTexture(GL_TEXTURE1);
            if (!im.light_texture) api.GenTextures(1, &im.light_texture);
            api.BindTexture(GL_TEXTURE_2D, im.light_texture);
            api.TexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, 1, 1, 0, GL_RGB, GL_UNSIGNED_BYTE, texel);
            api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            api.Enable(GL_TEXTURE_2D);
            api.ActiveTexture(GL_TEXTURE0);
        }
        gl::ArbVertexProgram& program =
            model == Model::hoffman_preetham ? *im.program_hp : *im.program_height;
        const ArbProgramOptions& arb = model == Model::hoffman_preetham ? im.arb_hp : im.arb_height;
        auto parameters = arb_program_parameters(frame_for(model), settings.display, arb);
        if (!parameters) {
            failure =
                Error{parameters.error().field, node.name + ": " + parameters.error().message};
            return;
        }
        if (auto e = program.set_parameters(*parameters)) {
            failure = Error{e->field, node.name + ": " + e->message};
            return;
        }
        auto drawn = program.draw(draw, node_apply);
        if (light_unit) {
            api.ActiveTexture(GL_TEXTURE1);
            api.Disable(GL_TEXTURE_2D);
            api.ActiveTexture(GL_TEXTURE0);
        }
        if (!drawn) failure = Error{drawn.error().field, node.name + ": " + drawn.error().message};
    });
    api.PixelStorei(GL_UNPACK_ALIGNMENT, unpack_alignment);
    if (failure) return *failure;

    // Forget nodes that were not in this frame's graph.
    for (auto it = im.nodes.begin(); it != im.nodes.end();) {
        it = it->second.last_frame == im.frame ? std::next(it) : im.nodes.erase(it);
    }
    report.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace aerial::scene
