// One frame of a scene file through SceneRenderer, the per-pixel reference and the fog baseline
// (aerial/validation/scene_render.hpp).
#include "aerial/validation/scene_render.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/matrix.hpp>

#include "aerial/batch.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/phase.hpp"
#include "aerial/scene_renderer.hpp"
#include "common/error_text.hpp"
#include "common/names.hpp"

namespace aerial::validation {
namespace {

constexpr detail::NameTable<RenderBackend, 5> kRenderBackendNames{
    {{RenderBackend::cpu, "cpu"},
     {RenderBackend::arb, "arb"},
     {RenderBackend::perpixel, "perpixel"},
     {RenderBackend::fog, "fog"},
     {RenderBackend::none, "none"}}};

/// The library backend a frame of `backend` is drawn with (perpixel and fog: the texture alone).
scene::Backend scene_backend(RenderBackend backend) {
    switch (backend) {
        case RenderBackend::cpu:
            return scene::Backend::cpu;
        case RenderBackend::arb:
            return scene::Backend::arb;
        case RenderBackend::perpixel:
        case RenderBackend::fog:
        case RenderBackend::none:
            break;
    }
    return scene::Backend::none;
}

constexpr const char* kRender = "validation::render_scene_file";

/// An error of a call render_scene_file made, as its own, naming the backend.
Error render_error(RenderBackend backend, const Error& e) {
    Error error = detail::from(kRender, e);
    error.message += std::string(" (--backend ") + render_backend_name(backend) + ")";
    return error;
}

/// An error of `function` about the result of a call it made: under `field`, the call's field
/// and text ("--backend: model: expected ..."), then `context`.
Error under(const char* function, std::string field, const Error& e, const std::string& context) {
    return detail::error(function, std::move(field),
                         e.field + ": " + std::string(detail::text_of(e)) + context);
}

/// "MODEL:INSTRUCTIONS" or "height:FIDELITY:INSTRUCTIONS" of the renderer's program for `model`.
std::string program_text(const scene::SceneRenderer& renderer, Model model) {
    const ArbProgram* program = renderer.arb_program(model);
    if (!program) return "-";
    std::string text = std::string(model_name(model)) + ":";
    if (model == Model::height) {
        text += std::string(arb_height_fidelity_name(program->options.height_fidelity)) + ":";
    }
    return text + std::to_string(program->instruction_count);
}

/// Sets GL_FOG (GL_EXP) with the file's fog parameters; the destructor turns it off again.
class FogState {
  public:
    FogState(const gl::Api& api, const FogParameters& fog) : api_(api) {
        api.Fogi(GL_FOG_MODE, GL_EXP);
        api.Fogf(GL_FOG_DENSITY, fog.density);
        api.Fogfv(GL_FOG_COLOR, fog.colour);
        api.Enable(GL_FOG);
    }
    ~FogState() { api_.Disable(GL_FOG); }
    FogState(const FogState&) = delete;
    FogState& operator=(const FogState&) = delete;

  private:
    const gl::Api& api_;
};

}  // namespace

const char* render_backend_name(RenderBackend backend) {
    return detail::name_in(kRenderBackendNames, backend);
}

Result<RenderBackend> parse_render_backend(std::string_view name, std::string_view field) {
    return detail::parse_in("validation::parse_render_backend", kRenderBackendNames,
                            std::string(field), name);
}

std::optional<Error> check_backend(const scene::SceneFile& file, const RenderOptions& options,
                                   bool path_given) {
    constexpr const char* kFunction = "validation::check_backend";
    if (path_given && options.backend != RenderBackend::cpu) {
        return detail::invalid(kFunction, "--path", "--backend cpu with it",
                               std::string("--backend ") + render_backend_name(options.backend));
    }
    if (options.backend != RenderBackend::arb) return std::nullopt;
    ArbProgramOptions arb;
    arb.model = file.model;
    auto program = generate_arb_program(arb);
    const std::string arb_backend = " (--backend arb)";
    if (!program) return under(kFunction, "--backend", program.error(), arb_backend);
    auto frame = prepare_frame<float>(file.atmosphere, file.view(), file.model);
    if (!frame) return under(kFunction, "scene", frame.error(), "");
    auto parameters = arb_program_parameters(*frame, file.display, arb);
    if (!parameters) return under(kFunction, "--backend", parameters.error(), arb_backend);
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

std::optional<Error> shade_per_pixel(const headless::Context& context, const Frame<float>& frame,
                                     const Display& display, const glm::dmat4& projection,
                                     const glm::dmat4& view, std::vector<std::uint8_t>& rgba) {
    const gl::Api& api = context.api();
    const int w = context.width(), h = context.height();
    std::vector<float> depth(std::size_t(w) * std::size_t(h));
    GLint alignment = 4;
    api.GetIntegerv(GL_PACK_ALIGNMENT, &alignment);
    api.PixelStorei(GL_PACK_ALIGNMENT, 1);
    api.ReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    api.PixelStorei(GL_PACK_ALIGNMENT, alignment);
    std::vector<float> positions;
    std::vector<std::size_t> pixels;  // index into rgba / 4 (top row first)
    positions_from_depth(depth, w, h, projection, view, positions, pixels);
    std::vector<float> extinction(positions.size()), in_scattering(positions.size());
    BatchOutputs out;
    out.extinction_rgb = extinction.data();
    out.in_scattering_rgb = in_scattering.data();
    BatchSettings settings;
    settings.display = display;
    auto stats = shade_into(frame, Positions::aos(positions.data(), pixels.size()), out, settings);
    if (!stats) return detail::from("validation::shade_per_pixel", stats.error());
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

Result<RenderedImage> render_scene_file(const headless::Context& context,
                                        const scene::SceneFile& file,
                                        const RenderOptions& options) {
    const gl::Api& api = context.api();
    const int w = context.width(), h = context.height();
    const RenderBackend backend = options.backend;
    scene::RendererOptions renderer_options;
    renderer_options.backend = scene_backend(backend);
    renderer_options.path = backend == RenderBackend::arb ? gl::Path::automatic : options.path;
    auto renderer = scene::SceneRenderer::create(api, renderer_options);
    if (!renderer) return render_error(backend, renderer.error());
    const auto frame = prepare_frame<float>(file.atmosphere, file.view(), file.model);
    if (!frame) return detail::from(kRender, frame.error());
    const auto root = scene::scene_graph(file);
    const scene::Camera camera = file.camera_for(w, h);

    api.Viewport(0, 0, w, h);
    api.ClearColor(float(file.background.r), float(file.background.g), float(file.background.b),
                   1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    RenderedImage image;
    image.width = w;
    image.height = h;
    const auto start = std::chrono::steady_clock::now();
    {
        std::optional<FogState> fog;
        if (backend == RenderBackend::fog) fog.emplace(api, fog_parameters(*frame, file.display));
        auto report = renderer.value().render(*root, camera, file.frame_settings());
        if (!report) return render_error(backend, report.error());
        image.path_used = report->path;
    }
    image.program = program_text(*renderer, file.model);
    api.Finish();
    image.rgba = context.read_rgba8();
    if (backend == RenderBackend::perpixel) {
        if (auto e =
                shade_per_pixel(context, *frame, file.display, scene::projection_matrix(camera),
                                scene::view_matrix(camera), image.rgba)) {
            return render_error(backend, *e);
        }
    }
    image.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const GLenum error = api.GetError();
    if (error != GL_NO_ERROR) {
        return render_error(backend,
                            detail::error(kRender, "GL", "GL error " + gl::gl_error_name(error)));
    }
    return image;
}

}  // namespace aerial::validation
