// The scene renderer: traversal, frustum culling, the frame's GL state, shading and drawing with
// the cpu and arb backends (what to shade is decided in frame_plan.cpp, without GL).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <thread>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "../core/worker_pool.hpp"
#include "adaptive_node.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/cache.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/gl_state_saver.hpp"
#include "aerial/phase.hpp"
#include "aerial/scene_renderer.hpp"
#include "frame_plan.hpp"
#include "lights.hpp"

namespace aerial::scene {
namespace {

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

}  // namespace

struct SceneRenderer::Impl {
    const gl::Api* api = nullptr;
    RendererOptions options;
    gl::Path path = gl::Path::automatic;
    std::optional<gl::CombinerTexture> combiner;
    std::optional<gl::ArbVertexProgram> program_hp, program_height;
    /// The options each program was generated with (the height fidelity resolved against the
    /// driver's native limits); its parameters are computed with the same.
    ArbProgram arb_hp, arb_height;
    SkyDrawer sky = default_sky_drawer();
    SkyDrawer sun = default_sun_drawer();
    std::unordered_map<const Node*, detail::NodeState> nodes;
    detail::ValidatedMeshes validated;
    std::map<const Texture*, std::pair<std::shared_ptr<const Texture>, GLuint>> textures;
    GLuint light_texture = 0;  ///< arb backend: 1×1 lighting factor on unit 1
    detail::LightState lights;
    std::uint64_t frame_number = 0;  ///< frames rendered

    ~Impl() { release_gl(); }

    /// A visible node of this frame: its state, and what planning and shading it gave.
    struct Visible {
        const Node* node = nullptr;
        detail::NodeState* state = nullptr;
        std::size_t report_index = 0;  ///< in FrameReport::nodes
        detail::NodePlan plan;
        FrameReport counts;  ///< shade_node's counts, merged in traversal order
        std::optional<Error> error;
    };
    /// Updates one mesh or terrain node's geometry and culls it: the visible ones are returned
    /// to be planned, shaded and drawn.
    std::optional<Error> prepare_node(const Node& node, const glm::dmat4& world,
                                      const detail::FrameInputs& frame,
                                      const std::array<glm::dvec4, 6>& planes, FrameReport& report,
                                      std::vector<Visible>& visible);
    /// Plans and shades the visible nodes, spread over the worker threads (each node is
    /// independent; the frame's shading keys are prepared first so that planning only reads it).
    void plan_and_shade(detail::FrameInputs& frame, std::vector<Visible>& visible);
    /// The node's colours as planned: lighting only (skipped), shade_into (cpu), none (cached,
    /// arb); counts them in the report.
    std::optional<Error> shade_node(const Node& node, detail::NodeState& st,
                                    const detail::NodePlan& plan, const detail::FrameInputs& frame,
                                    FrameReport& report);
    /// Binds the node's texture on unit 0 (sets apply.textured) and returns its draw call.
    std::function<void()> node_draw(const Node& node, const detail::NodeState& st,
                                    gl::ApplyOptions& apply);
    /// Draws the node with its colours (cpu, skipped) or through its model's ARB program.
    std::optional<Error> draw_node(const Node& node, const detail::NodeState& st,
                                   const detail::NodePlan& plan, const detail::FrameInputs& frame,
                                   const gl::ApplyOptions& apply, int units);
    /// arb backend: draws through the program of `model` with the parameters of `light` (the
    /// sun's frame or the moon's), then turns unit 1's lighting factor off when `light_unit`.
    std::optional<Error> draw_program(const Node& node, Model model, const Frame<float>& light,
                                      const Display& display, const std::function<void()>& draw,
                                      const gl::ApplyOptions& apply, bool light_unit);
    /// arb backend: a lighting factor (display values) as a 1x1 texture on unit 1.
    void set_light_unit(const std::array<std::uint8_t, 3>& texel);
    /// arb backend, frames with both lights: the node again through its program with the
    /// moon's parameters, added (blend ONE, ONE at equal depth); unlit nodes with a black
    /// lighting factor, so that only the moon's L_in is added (needs two texture units).
    std::optional<Error> draw_second_light(const Node& node, const detail::NodeState& st,
                                           const detail::NodePlan& plan,
                                           const detail::FrameInputs& frame,
                                           const gl::ApplyOptions& apply, int units);

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

constexpr aerial::detail::NameTable<Backend, 3> kBackendNames{
    {{Backend::cpu, "cpu"}, {Backend::arb, "arb"}, {Backend::none, "none"}}};

const char* backend_name(Backend backend) {
    return aerial::detail::name_in(kBackendNames, backend);
}

Result<Backend> parse_backend(std::string_view name) {
    return aerial::detail::parse_in("scene::parse_backend", kBackendNames, "backend", name);
}

constexpr aerial::detail::NameTable<Method, 7> kMethodNames{
    {{Method::culled, "culled"},
     {Method::skipped, "skipped"},
     {Method::cached, "cached"},
     {Method::hoffman_preetham, "hoffman-preetham"},
     {Method::height, "height"},
     {Method::reference, "reference"},
     {Method::unshaded, "unshaded"}}};

const char* method_name(Method method) { return aerial::detail::name_in(kMethodNames, method); }

constexpr aerial::detail::NameTable<Lights, 3> kLightsNames{
    {{Lights::sun, "sun"}, {Lights::moon, "moon"}, {Lights::both, "both"}}};

const char* lights_name(Lights lights) { return aerial::detail::name_in(kLightsNames, lights); }

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
    if (vertices[Method::unshaded] > 0) return "unshaded";
    return "none";
}

// ---- Camera ------------------------------------------------------------------------------------

std::optional<Error> validate(const Camera& camera) {
    const auto finite3 = [](const glm::dvec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    using aerial::detail::invalid;
    using aerial::detail::number;
    using aerial::detail::vector;
    constexpr const char* kFunction = "scene::validate";
    if (!finite3(camera.eye))
        return invalid(kFunction, "camera.eye", "finite coordinates", vector(camera.eye));
    if (!finite3(camera.target) || camera.target == camera.eye) {
        return invalid(kFunction, "camera.target", "a finite point other than camera.eye",
                       vector(camera.target));
    }
    const glm::dvec3 forward = camera.target - camera.eye;
    if (!finite3(camera.up) || glm::length(glm::cross(forward, camera.up)) <=
                                   1e-9 * glm::length(forward) * glm::length(camera.up)) {
        return invalid(kFunction, "camera.up", "a finite vector not parallel to the view",
                       vector(camera.up));
    }
    if (!(camera.fov_y_rad > 0.0 && camera.fov_y_rad < 3.14159))
        return invalid(kFunction, "camera.fov_y_rad", "a value in (0, pi)",
                       number(camera.fov_y_rad));
    if (!(camera.aspect > 0.0) || !std::isfinite(camera.aspect))
        return invalid(kFunction, "camera.aspect", "a finite value > 0", number(camera.aspect));
    if (!(camera.near_units > 0.0) || !(camera.far_units > camera.near_units) ||
        !std::isfinite(camera.far_units)) {
        return invalid(kFunction, "camera.near_units", "0 < near_units < far_units (finite)",
                       number(camera.near_units) + " and " + number(camera.far_units));
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

const ArbProgram* SceneRenderer::arb_program(Model model) const {
    if (impl_->options.backend != Backend::arb) return nullptr;
    if (model == Model::hoffman_preetham) return &impl_->arb_hp;
    if (model == Model::height) return &impl_->arb_height;
    return nullptr;
}
void SceneRenderer::set_sky_drawer(SkyDrawer drawer) { impl_->sky = std::move(drawer); }
void SceneRenderer::set_sun_drawer(SkyDrawer drawer) { impl_->sun = std::move(drawer); }
const SkyDrawer& SceneRenderer::sun_drawer() const { return impl_->sun; }
void SceneRenderer::clear_caches() {
    impl_->nodes.clear();
    impl_->textures.clear();
    impl_->light_texture = 0;
    impl_->lights = detail::LightState{};
}

Result<SceneRenderer> SceneRenderer::create(const gl::Api& api, const RendererOptions& options) {
    constexpr const char* kFunction = "scene::SceneRenderer::create";
    using aerial::detail::from;
    if (auto e = gl::no_current_context(api)) return from(kFunction, *e);
    auto impl = std::make_unique<Impl>();
    impl->api = &api;
    impl->options = options;
    if (options.backend != Backend::arb) {
        auto path = gl::choose_path(api.caps, options.path);
        if (!path) return from(kFunction, path.error());
        impl->path = *path;
        if (*path == gl::Path::combiner) {
            auto combiner = gl::CombinerTexture::create(api);
            if (!combiner) return from(kFunction, combiner.error());
            impl->combiner.emplace(std::move(combiner.value()));
        }
    } else {
        if (options.path != gl::Path::automatic) {
            return aerial::detail::invalid(kFunction, "path",
                                           "automatic with the arb backend (only the cpu backend "
                                           "takes a fixed-function path)",
                                           gl::path_name(options.path));
        }
        auto path = gl::choose_path(api.caps, gl::Path::automatic);
        if (!path) return from(kFunction, path.error());
        impl->path = *path;  // for nodes drawn without the program (skipped by the policy)
        if (*path == gl::Path::combiner) {
            auto combiner = gl::CombinerTexture::create(api);
            if (!combiner) return from(kFunction, combiner.error());
            impl->combiner.emplace(std::move(combiner.value()));
        }
        for (Model model : {Model::hoffman_preetham, Model::height}) {
            ArbProgramOptions arb;
            arb.model = model;
            arb.limits = gl::native_arb_limits(api);  // the most accurate height program it takes
            auto text = generate_arb_program(arb);
            if (!text) return from(kFunction, text.error());
            auto program = gl::ArbVertexProgram::create(api, *text);
            if (!program) return from(kFunction, program.error());
            (model == Model::height ? impl->program_height : impl->program_hp)
                .emplace(std::move(program.value()));
            (model == Model::height ? impl->arb_height : impl->arb_hp) = std::move(text.value());
        }
    }
    return SceneRenderer(std::move(impl));
}

namespace {

/// The GL state of a frame: everything the renderer's draws change is saved on construction and
/// put back on destruction, and the frame's matrices, unpack alignment, texture units, arrays and
/// depth test are set.
class FrameGlState {
  public:
    FrameGlState(const gl::Api& api, const glm::dmat4& projection, const glm::dmat4& view)
        : api_(api), saver_(api), vertex_array_(api) {
        api.GetIntegerv(GL_MATRIX_MODE, &matrix_mode_);
        api.MatrixMode(GL_PROJECTION);
        api.PushMatrix();
        api.MatrixMode(GL_MODELVIEW);
        api.PushMatrix();
        load_matrix(api, GL_PROJECTION, projection);
        load_matrix(api, GL_MODELVIEW, view);
        api.GetIntegerv(GL_UNPACK_ALIGNMENT, &unpack_alignment_);
        api.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
        units_ = std::min(2, std::max(1, api.caps.max_texture_units));
        // The saver records a change only when the value differs: switching each enable both
        // ways records the engine's value whatever it was, so the raw changes of the draws are
        // undone too.
        for (int u = 0; u < units_; ++u) {
            saver_.bind_texture(u, GL_TEXTURE_2D, 0);
            saver_.unit_enable(u, GL_TEXTURE_2D, true);
            saver_.unit_enable(u, GL_TEXTURE_2D, false);
            saver_.tex_env(u, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        }
        saver_.select_unit(0);
        saver_.texcoord_array(0, 2, GL_FLOAT, 0, nullptr);
        api.DisableClientState(GL_TEXTURE_COORD_ARRAY);
        saver_.color_array(4, GL_UNSIGNED_BYTE, 0, nullptr);
        api.DisableClientState(GL_COLOR_ARRAY);
        saver_.enable(GL_DEPTH_TEST, true);
        saver_.enable(GL_DEPTH_TEST, false);
        saver_.depth_mask(false);
        saver_.depth_func(GL_LEQUAL);
        saver_.enable(GL_LIGHTING, false);
        api.EnableClientState(GL_VERTEX_ARRAY);
    }
    ~FrameGlState() {
        api_.PixelStorei(GL_UNPACK_ALIGNMENT, unpack_alignment_);
        api_.MatrixMode(GL_PROJECTION);
        api_.PopMatrix();
        api_.MatrixMode(GL_MODELVIEW);
        api_.PopMatrix();
        api_.MatrixMode(GLenum(matrix_mode_));
    }
    FrameGlState(const FrameGlState&) = delete;
    FrameGlState& operator=(const FrameGlState&) = delete;

    /// Texture units the frame uses (unit 1 carries the arb backend's lighting factor).
    int units() const { return units_; }
    /// The arb backend's second light: drawn over the first at equal depth, added.
    void additive() {
        saver_.enable(GL_BLEND, true);
        saver_.blend_func(GL_ONE, GL_ONE);
        saver_.depth_mask(false);
    }

  private:
    const gl::Api& api_;
    gl::StateSaver saver_;
    VertexArraySaver vertex_array_;
    GLint matrix_mode_ = GL_MODELVIEW, unpack_alignment_ = 4;
    int units_ = 1;
};

/// An error of drawing `node`: render()'s, naming the node.
Error node_error(const Node& node, const Error& e) {
    Error error = aerial::detail::from(detail::kRender, e);
    error.message += " (in node '" + node.name + "')";
    return error;
}

}  // namespace

std::optional<Error> SceneRenderer::Impl::shade_node(const Node& node, detail::NodeState& st,
                                                     const detail::NodePlan& plan,
                                                     const detail::FrameInputs& frame,
                                                     FrameReport& report) {
    const std::size_t n = st.positions.size() / 3;
    const bool cpu = options.backend == Backend::cpu;
    if (plan.method == Method::skipped || plan.method == Method::unshaded) {
        if (plan.method == Method::skipped) ++report.skipped;
        detail::skipped_colours(frame, st, plan.lit, node.albedo);
    } else if (cpu && frame.second) {
        if (auto e = detail::shade_two_lights(frame, st, plan.lit, node.albedo))
            return node_error(node, *e);
        if (node.adaptive) detail::morph_adaptive_colours(st, node);
        st.has_colours = true;
        st.skip_colours = false;
        report.vertices_shaded += 2 * n;
    } else if (cpu && plan.method != Method::cached) {
        BatchOutputs out;
        Lighting lighting;
        if (plan.lit) {
            lighting.normals = st.normals.data();
            lighting.ambient = frame.ambient;
            lighting.albedo = node.albedo;
            out.lit_rgba8 = st.primary.data();
        } else {
            out.extinction_rgba8 = st.primary.data();
        }
        out.in_scattering_rgba8 = st.secondary.data();
        BatchSettings bs;
        bs.display = frame.settings->display;
        bs.lighting = plan.lit ? &lighting : nullptr;
        auto stats = shade_into(frame.frame_for(plan.model), Positions::aos(st.positions.data(), n),
                                out, bs);
        if (!stats) return node_error(node, stats.error());
        if (node.adaptive) detail::morph_adaptive_colours(st, node);
        st.has_colours = true;
        st.skip_colours = false;
        report.vertices_shaded += n;
    } else if (options.backend == Backend::arb) {
        report.vertices_shaded += frame.second ? 2 * n : n;
    }
    if (plan.method == Method::cached) ++report.cache_hits;
    if (plan.method == Method::hoffman_preetham) ++report.shaded_hoffman_preetham;
    if (plan.method == Method::height) ++report.shaded_height;
    if (plan.method == Method::reference) ++report.shaded_reference;
    report.vertices_drawn += n;
    return std::nullopt;
}

namespace {

/// The arb backend's lighting factor of a lit node: level ground (the programs carry no
/// normals) of the node's albedo under a light of E `e` at the eye along `dir`, plus `ambient`.
std::array<std::uint8_t, 3> light_texel(const FrameSettings& settings, const Node& node,
                                        const glm::vec3& e, const glm::dvec3& dir,
                                        const glm::vec3& ambient) {
    const float cosine = std::max(0.0f, float(glm::dot(dir, settings.up)));
    std::array<std::uint8_t, 3> texel{};
    for (int c = 0; c < 3; ++c) {
        texel[std::size_t(c)] = to_unorm8(display_value(
            settings.display, lit_value(1.0f, node.albedo[c], e[c], cosine, ambient[c])));
    }
    return texel;
}

}  // namespace

void SceneRenderer::Impl::set_light_unit(const std::array<std::uint8_t, 3>& texel) {
    api->ActiveTexture(GL_TEXTURE1);
    if (!light_texture) api->GenTextures(1, &light_texture);
    api->BindTexture(GL_TEXTURE_2D, light_texture);
    api->TexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, 1, 1, 0, GL_RGB, GL_UNSIGNED_BYTE, texel.data());
    api->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    api->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    api->Enable(GL_TEXTURE_2D);
    api->ActiveTexture(GL_TEXTURE0);
}

std::function<void()> SceneRenderer::Impl::node_draw(const Node& node, const detail::NodeState& st,
                                                     gl::ApplyOptions& apply) {
    const gl::Api& gl = *api;
    const MeshData& mesh = *st.mesh;
    const bool textured = node.texture && !mesh.texcoords.empty();
    if (gl.ActiveTexture) gl.ActiveTexture(GL_TEXTURE0);
    if (textured) {
        gl.BindTexture(GL_TEXTURE_2D, texture_id(node.texture));
        gl.Enable(GL_TEXTURE_2D);
    } else {
        gl.Disable(GL_TEXTURE_2D);
    }
    apply.textured = textured;
    return [&gl, &mesh, &st, textured] {
        if (gl.ClientActiveTexture) gl.ClientActiveTexture(GL_TEXTURE0);
        gl.VertexPointer(3, GL_FLOAT, 0, st.positions.data());
        if (textured) {
            gl.TexCoordPointer(2, GL_FLOAT, 0, mesh.texcoords.data());
            gl.EnableClientState(GL_TEXTURE_COORD_ARRAY);
        }
        gl.DrawElements(GL_TRIANGLES, GLsizei(mesh.indices.size()), GL_UNSIGNED_INT,
                        mesh.indices.data());
        if (textured) gl.DisableClientState(GL_TEXTURE_COORD_ARRAY);
    };
}

std::optional<Error> SceneRenderer::Impl::draw_node(const Node& node, const detail::NodeState& st,
                                                    const detail::NodePlan& plan,
                                                    const detail::FrameInputs& frame,
                                                    const gl::ApplyOptions& apply, int units) {
    const gl::Api& gl = *api;
    const std::size_t n = st.positions.size() / 3;
    gl::ApplyOptions node_apply = apply;
    const std::function<void()> draw = node_draw(node, st, node_apply);
    if (options.backend != Backend::arb || plan.method == Method::skipped) {
        gl::VertexColours colours{st.primary.data(), st.secondary.data(), 0, 0, n};
        auto drawn = gl::draw_with_colours(gl, node_apply, colours, draw);
        if (!drawn) return node_error(node, drawn.error());
        return std::nullopt;
    }
    // arb: the program computes F_ex and L_in; lighting is one factor per node on unit 1.
    const bool light_unit = plan.lit && units > 1;
    if (light_unit) {
        set_light_unit(light_texel(*frame.settings, node, frame.hoffman_preetham.sun_irradiance_eye,
                                   frame.settings->sun_dir, frame.ambient));
    }
    return draw_program(node, plan.model, frame.frame_for(plan.model), frame.settings->display,
                        draw, node_apply, light_unit);
}

std::optional<Error> SceneRenderer::Impl::draw_program(
    const Node& node, Model model, const Frame<float>& light, const Display& display,
    const std::function<void()>& draw, const gl::ApplyOptions& apply, bool light_unit) {
    const bool hp = model == Model::hoffman_preetham;
    gl::ArbVertexProgram& program = hp ? *program_hp : *program_height;
    auto parameters = arb_program_parameters(light, display, (hp ? arb_hp : arb_height).options);
    if (!parameters) return node_error(node, parameters.error());
    if (auto e = program.set_parameters(*parameters)) return node_error(node, *e);
    auto drawn = program.draw(draw, apply);
    if (light_unit) {
        api->ActiveTexture(GL_TEXTURE1);
        api->Disable(GL_TEXTURE_2D);
        api->ActiveTexture(GL_TEXTURE0);
    }
    if (!drawn) return node_error(node, drawn.error());
    return std::nullopt;
}

std::optional<Error> SceneRenderer::Impl::draw_second_light(
    const Node& node, const detail::NodeState& st, const detail::NodePlan& plan,
    const detail::FrameInputs& frame, const gl::ApplyOptions& apply, int units) {
    if (plan.method != Method::hoffman_preetham && plan.method != Method::height)
        return std::nullopt;             // skipped: its colours have both lights' lighting
    if (units < 2) return std::nullopt;  // no unit for the lighting factor: the sun's pass only
    const detail::SecondLight& moon = *frame.second;
    const std::array<std::uint8_t, 3> black{0, 0, 0};
    set_light_unit(plan.lit ? light_texel(*frame.settings, node, moon.model.sun_irradiance_eye,
                                          moon.settings->sun_dir, moon.ambient)
                            : black);
    gl::ApplyOptions node_apply = apply;
    const std::function<void()> draw = node_draw(node, st, node_apply);
    return draw_program(node, plan.model, moon.model, frame.settings->display, draw, node_apply,
                        true);
}

std::optional<Error> SceneRenderer::Impl::prepare_node(const Node& node, const glm::dmat4& world,
                                                       const detail::FrameInputs& frame,
                                                       const std::array<glm::dvec4, 6>& planes,
                                                       FrameReport& report,
                                                       std::vector<Visible>& visible) {
    detail::NodeState& st = nodes[&node];
    st.last_frame = frame_number;
    if (node.adaptive) {
        if (auto e = detail::refine_adaptive_node(st, node, world, frame.model)) return e;
    }
    detail::update_geometry(st, node, world);
    NodeReport nr;
    nr.name = node.name;
    nr.vertices = st.positions.size() / 3;
    if (st.bounds.radius < 0.0 || sphere_outside(planes, st.bounds.centre, st.bounds.radius)) {
        nr.method = Method::culled;
        ++report.culled;
    } else {
        Visible v;
        v.node = &node;
        v.state = &st;
        v.report_index = report.nodes.size();
        visible.push_back(std::move(v));
    }
    report.nodes.push_back(nr);
    return std::nullopt;
}

void SceneRenderer::Impl::plan_and_shade(detail::FrameInputs& frame,
                                         std::vector<Visible>& visible) {
    detail::prepare_shading_keys(frame);
    const auto task = [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            Visible& v = visible[i];
            v.plan = detail::plan_node(frame, *v.state, *v.node);
            v.error = shade_node(*v.node, *v.state, v.plan, frame, v.counts);
        }
    };
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    aerial::detail::WorkerPool::instance().run(threads, visible.size(), 1, task);
}

Result<FrameReport> SceneRenderer::render(const Node& root, const Camera& camera,
                                          const FrameSettings& settings) {
    const auto start = std::chrono::steady_clock::now();
    Impl& im = *impl_;
    const gl::Api& api = *im.api;
    if (auto e = gl::no_current_context(api)) return aerial::detail::from(detail::kRender, *e);
    if (auto e = detail::validate_moon(settings)) return *e;
    const detail::FrameLights lights = detail::choose_lights(im.lights, settings, camera.eye);
    auto inputs =
        detail::prepare_frame_inputs(root, camera, *lights.first, im.options.backend, im.validated);
    if (!inputs) return inputs.error();
    detail::FrameInputs& frame = inputs.value();
    frame.ambient = lights.first_ambient;
    if (lights.second) {
        if (auto e = detail::prepare_second_light(frame, *lights.second, lights.second_ambient))
            return *e;
    }

    FrameReport report;
    report.path = im.path;
    report.ambient = lights.first_ambient + lights.second_ambient;
    report.lights = lights.lights;
    ++im.frame_number;

    const glm::dmat4 projection = projection_matrix(camera);
    const glm::dmat4 view = view_matrix(camera);
    const auto planes = frustum_planes(projection * view);
    std::optional<Error> failure;
    {
        FrameGlState gl_state(api, projection, view);
        gl::ApplyOptions apply;
        apply.path = im.path;
        apply.combiner = im.combiner ? &*im.combiner : nullptr;

        // Sky and sun behind everything, without depth.
        SkyDrawContext sky_context;
        sky_context.api = &api;
        sky_context.settings = &settings;
        sky_context.lights = {lights.first};
        if (lights.second) sky_context.lights.push_back(lights.second);
        sky_context.camera = &camera;
        sky_context.hoffman_preetham = &frame.hoffman_preetham;
        sky_context.model = &frame.model;
        sky_context.apply = &apply;
        if (im.sky && detail::has_kind(root, NodeKind::sky_dome)) im.sky(sky_context);
        if (im.sun && detail::has_kind(root, NodeKind::sun)) im.sun(sky_context);

        std::vector<Impl::Visible> visible;
        traverse(root, [&](const Node& node, const glm::dmat4& world) {
            if (failure || (node.kind != NodeKind::mesh && node.kind != NodeKind::terrain)) return;
            failure = im.prepare_node(node, world, frame, planes, report, visible);
        });
        if (!failure) {
            const auto shading_start = std::chrono::steady_clock::now();
            im.plan_and_shade(frame, visible);
            report.shading_milliseconds = std::chrono::duration<double, std::milli>(
                                              std::chrono::steady_clock::now() - shading_start)
                                              .count();
        }
        api.Enable(GL_DEPTH_TEST);
        api.DepthMask(GL_TRUE);
        for (const Impl::Visible& v : visible) {
            if (failure) break;
            failure = v.error;
            if (failure) break;
            report.nodes[v.report_index].method = v.plan.method;
            detail::add_counts(report, v.counts);
            failure = im.draw_node(*v.node, *v.state, v.plan, frame, apply, gl_state.units());
        }
        if (!failure && frame.second && im.options.backend == Backend::arb) {
            gl_state.additive();
            for (const Impl::Visible& v : visible) {
                failure =
                    im.draw_second_light(*v.node, *v.state, v.plan, frame, apply, gl_state.units());
                if (failure) break;
            }
        }
    }
    if (failure) return *failure;

    // Forget nodes that were not in this frame's graph.
    for (auto it = im.nodes.begin(); it != im.nodes.end();) {
        it = it->second.last_frame == im.frame_number ? std::next(it) : im.nodes.erase(it);
    }
    report.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return report;
}

}  // namespace aerial::scene
