#include "render/renderer.hpp"

#include <chrono>
#include <cmath>
#include <functional>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "aerial/batch.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"

namespace aerial::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

BoundTexture::BoundTexture(const gl::Api& api, const Texture& texture) : api_(api) {
    api_.GenTextures(1, &id_);
    api_.BindTexture(GL_TEXTURE_2D, id_);
    api_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (std::size_t level = 0; level < texture.levels.size(); ++level) {
        const Texture::Level& l = texture.levels[level];
        api_.TexImage2D(GL_TEXTURE_2D, GLint(level), GL_RGB8, l.size, l.size, 0, GL_RGB,
                        GL_UNSIGNED_BYTE, l.rgb.data());
    }
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    api_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    api_.TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    api_.Enable(GL_TEXTURE_2D);
}

BoundTexture::~BoundTexture() {
    api_.Disable(GL_TEXTURE_2D);
    api_.BindTexture(GL_TEXTURE_2D, 0);
    api_.DeleteTextures(1, &id_);
}

Matrices camera_matrices(const Camera& camera, int width, int height) {
    Matrices m;
    m.projection = glm::perspective(camera.fov_y_rad, double(width) / double(height),
                                    camera.near_units, camera.far_units);
    m.view = glm::lookAt(camera.eye, camera.target, camera.up);
    return m;
}

void draw_arrays(const gl::Api& api, const Mesh& mesh) {
    if (api.ClientActiveTexture) api.ClientActiveTexture(GL_TEXTURE0);
    api.EnableClientState(GL_VERTEX_ARRAY);
    api.VertexPointer(3, GL_FLOAT, 0, mesh.positions.data());
    api.EnableClientState(GL_TEXTURE_COORD_ARRAY);
    api.TexCoordPointer(2, GL_FLOAT, 0, mesh.texcoords.data());
    api.DrawElements(GL_TRIANGLES, GLsizei(mesh.indices.size()), GL_UNSIGNED_INT,
                     mesh.indices.data());
    api.DisableClientState(GL_TEXTURE_COORD_ARRAY);
    api.DisableClientState(GL_VERTEX_ARRAY);
}

void load_matrix(const gl::Api& api, unsigned mode, const glm::dmat4& m) {
    const glm::mat4 f(m);
    api.MatrixMode(mode);
    api.LoadMatrixf(glm::value_ptr(f));
}

std::optional<Error> shade_per_pixel(const headless::Context& context, const Frame<float>& frame,
                                     const Display& display, const Matrices& matrices,
                                     std::vector<std::uint8_t>& rgba) {
    const gl::Api& api = context.api();
    const int w = context.width(), h = context.height();
    std::vector<float> depth(std::size_t(w) * std::size_t(h));
    api.PixelStorei(GL_PACK_ALIGNMENT, 1);
    api.ReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    std::vector<float> positions;
    std::vector<std::size_t> pixels;  // index into rgba / 4 (top row first)
    positions_from_depth(depth, w, h, matrices.projection, matrices.view, positions, pixels);
    std::vector<float> extinction(positions.size()), in_scattering(positions.size());
    BatchOutputs out;
    out.extinction_rgb = extinction.data();
    out.in_scattering_rgb = in_scattering.data();
    BatchSettings settings;
    settings.display = display;
    auto stats = shade_into(frame, Positions::aos(positions.data(), pixels.size()), out, settings);
    if (!stats) return stats.error();
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        std::uint8_t* px = &rgba[4 * pixels[i]];
        for (std::size_t c = 0; c < 3; ++c) {
            const float texel = float(px[c]) / 255.0f;
            px[c] = to_unorm8(texel * extinction[3 * i + c] +
                              display_value(display, in_scattering[3 * i + c]));
        }
    }
    return std::nullopt;
}

void positions_from_depth(const std::vector<float>& depth, int w, int h,
                          const glm::dmat4& projection, const glm::dmat4& view,
                          std::vector<float>& positions, std::vector<std::size_t>& pixels) {
    // GL's own matrices are the float ones it was given: invert exactly those.
    const glm::dmat4 clip_from_world =
        glm::dmat4(glm::mat4(projection)) * glm::dmat4(glm::mat4(view));
    const glm::dmat4 world_from_clip = glm::inverse(clip_from_world);
    positions.clear();
    pixels.clear();
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float d = depth[std::size_t(y) * std::size_t(w) + std::size_t(x)];
            if (!(d < 1.0f)) continue;  // background
            const glm::dvec4 ndc{2.0 * (x + 0.5) / w - 1.0, 2.0 * (y + 0.5) / h - 1.0,
                                 2.0 * double(d) - 1.0, 1.0};
            const glm::dvec4 p = world_from_clip * ndc;
            positions.insert(positions.end(),
                             {float(p.x / p.w), float(p.y / p.w), float(p.z / p.w)});
            pixels.push_back(std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x));
        }
    }
}

const char* backend_name(Backend backend) {
    switch (backend) {
        case Backend::cpu:
            return "cpu";
        case Backend::arb:
            return "arb";
        case Backend::perpixel:
            return "perpixel";
        case Backend::fog:
            return "fog";
        case Backend::none:
            return "none";
    }
    return "unknown";
}

std::optional<Backend> parse_backend(std::string_view name) {
    for (Backend b : {Backend::cpu, Backend::arb, Backend::perpixel, Backend::fog, Backend::none}) {
        if (name == backend_name(b)) return b;
    }
    return std::nullopt;
}

std::optional<Error> check_backend(const Scene& scene, const RenderOptions& options,
                                   bool path_given) {
    const std::string where = std::string("--backend ") + backend_name(options.backend) + ": ";
    if (path_given && options.backend != Backend::cpu) {
        return Error{"--path", std::string("--path: only with --backend cpu, got --backend ") +
                                   backend_name(options.backend)};
    }
    if (options.backend != Backend::arb) return std::nullopt;
    ArbProgramOptions arb;
    arb.model = scene.model;
    auto program = generate_arb_program(arb);
    if (!program) return Error{"--backend", where + program.error().message};
    auto frame = prepare_frame<float>(scene.atmosphere, scene.view(), scene.model);
    if (!frame) return Error{"scene", "scene: " + frame.error().message};
    auto parameters = arb_program_parameters(*frame, scene.display, arb);
    if (!parameters) return Error{"--backend", where + parameters.error().message};
    return std::nullopt;
}

FogParameters fog_parameters(const Frame<float>& frame, const Display& display) {
    // The model's density where the eye is: sea level for the 2002 model (its assumption
    // everywhere), the eye's altitude for `height`.
    double rayleigh_density = 1.0, mie_density = 1.0;
    if (frame.model != Model::hoffman_preetham) {
        const double h = std::max(double(frame.eye_altitude_m), double(frame.min_altitude_m));
        rayleigh_density = std::exp(-h * double(frame.inv_rayleigh_scale_height));
        mie_density = std::exp(-h * double(frame.inv_mie_scale_height));
    }
    FogParameters fog;
    for (int c = 0; c < 3; ++c) {
        const double scattering = double(frame.rayleigh_scattering[c]) * rayleigh_density +
                                  double(frame.mie_scattering[c]) * mie_density;
        const double extinction = double(frame.rayleigh_scattering[c]) * rayleigh_density +
                                  double(frame.mie_extinction[c]) * mie_density;
        // L_in of an infinitely long ray, phase averaged over the sphere (1 / 4 pi).
        const double haze = extinction > 0.0 ? double(frame.sun_irradiance_eye[c]) * scattering /
                                                   (4.0 * kPi * extinction)
                                             : 0.0;
        fog.colour[c] = display_value(display, float(haze));
        if (c == 1) fog.density = float(extinction * double(frame.meters_per_unit));
    }
    return fog;
}

namespace {

/// The scene as the library's scene graph: one mesh node with the scene's texture.
std::unique_ptr<scene::Node> scene_graph(const Mesh& mesh, const Texture& texture) {
    auto data = std::make_shared<scene::MeshData>();
    data->positions = mesh.positions;
    data->texcoords = mesh.texcoords;
    data->indices = mesh.indices;
    auto image = std::make_shared<scene::Texture>();
    image->width = image->height = texture.levels.front().size;
    image->rgb = texture.levels.front().rgb;
    auto root = scene::make_group("scene");
    root->add(scene::make_mesh("geometry", std::move(data), std::move(image)));
    return root;
}

/// The cpu and arb backends: one frame of aerial::scene::SceneRenderer (no policy, no sky).
std::optional<Error> render_with_scene_renderer(const headless::Context& context, const Scene& s,
                                                const RenderOptions& options, const Mesh& mesh,
                                                const Texture& texture, RenderedImage& image) {
    const std::string where = std::string("--backend ") + backend_name(options.backend) + ": ";
    scene::RendererOptions renderer_options;
    renderer_options.backend =
        options.backend == Backend::arb ? scene::Backend::arb : scene::Backend::cpu;
    renderer_options.path = options.path;
    auto renderer = scene::SceneRenderer::create(context.api(), renderer_options);
    if (!renderer) return Error{renderer.error().field, where + renderer.error().message};
    scene::Camera camera;
    camera.eye = s.camera.eye;
    camera.target = s.camera.target;
    camera.up = s.camera.up;
    camera.fov_y_rad = s.camera.fov_y_rad;
    camera.aspect = double(context.width()) / double(context.height());
    camera.near_units = s.camera.near_units;
    camera.far_units = s.camera.far_units;
    scene::FrameSettings settings;
    settings.atmosphere = s.atmosphere;
    settings.sun_dir = s.sun_dir;
    settings.up = s.view().up;
    settings.meters_per_unit = s.meters_per_unit;
    settings.display = s.display;
    settings.model = s.model;
    settings.policy = false;
    const auto root = scene_graph(mesh, texture);
    auto report = renderer.value().render(*root, camera, settings);
    if (!report) return Error{report.error().field, where + report.error().message};
    image.path_used = report->path;
    if (const ArbProgram* program = renderer->arb_program(s.model)) {
        image.program = std::string(model_name(s.model)) + ":";
        if (s.model == Model::height) {
            image.program +=
                std::string(arb_height_fidelity_name(program->options.height_fidelity)) + ":";
        }
        image.program += std::to_string(program->instruction_count);
    }
    return std::nullopt;
}

}  // namespace

Result<RenderedImage> render_scene(const headless::Context& context, const Scene& scene,
                                   const RenderOptions& options) {
    const gl::Api& api = context.api();
    const int w = context.width(), h = context.height();
    const Mesh mesh = build_geometry(scene);
    const Texture texture = build_texture(scene.texture);
    const Matrices matrices = camera_matrices(scene.camera, w, h);
    const std::string where = std::string("--backend ") + backend_name(options.backend) + ": ";

    api.Viewport(0, 0, w, h);
    api.ClearColor(float(scene.background.r), float(scene.background.g), float(scene.background.b),
                   1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    api.Enable(GL_DEPTH_TEST);
    api.DepthFunc(GL_LEQUAL);
    load_matrix(api, GL_PROJECTION, matrices.projection);
    load_matrix(api, GL_MODELVIEW, matrices.view);
    const BoundTexture bound(api, texture);

    const std::function<void()> draw_mesh = [&] { draw_arrays(api, mesh); };

    RenderedImage image;
    image.width = w;
    image.height = h;
    const auto start = std::chrono::steady_clock::now();
    auto frame = prepare_frame<float>(scene.atmosphere, scene.view(), scene.model);
    if (!frame) return Error{frame.error().field, "scene: " + frame.error().message};

    switch (options.backend) {
        case Backend::none:
        case Backend::perpixel: {
            api.Color4f(1.0f, 1.0f, 1.0f, 1.0f);
            draw_mesh();
            break;
        }
        case Backend::fog: {
            const FogParameters fog = fog_parameters(*frame, scene.display);
            api.Fogi(GL_FOG_MODE, GL_EXP);
            api.Fogf(GL_FOG_DENSITY, fog.density);
            api.Fogfv(GL_FOG_COLOR, fog.colour);
            api.Enable(GL_FOG);
            api.Color4f(1.0f, 1.0f, 1.0f, 1.0f);
            draw_mesh();
            api.Disable(GL_FOG);
            break;
        }
        case Backend::cpu:
        case Backend::arb: {
            if (auto e =
                    render_with_scene_renderer(context, scene, options, mesh, texture, image)) {
                return *e;
            }
            break;
        }
    }
    api.Finish();
    image.rgba = context.read_rgba8();
    if (options.backend == Backend::perpixel) {
        if (auto e = shade_per_pixel(context, *frame, scene.display, matrices, image.rgba)) {
            return Error{e->field, where + e->message};
        }
    }
    image.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const GLenum error = api.GetError();
    if (error != GL_NO_ERROR) return Error{"GL", where + "GL error " + gl::gl_error_name(error)};
    return image;
}

}  // namespace aerial::render
