// The cases (cases.hpp). Each kind is one function; they share the context, the scene and the
// comparison helpers at the top.
#include "regress/cases.hpp"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <vector>

#include "aerial/batch.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/scene_file.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/validation/scene_render.hpp"
#include "common/image_metrics.hpp"
#include "support/png.hpp"

namespace aerial::regress {

namespace fs = std::filesystem;

namespace {

CaseResult result(Status status, std::string reason = {}) {
    CaseResult r;
    r.status = status;
    r.reason = std::move(reason);
    return r;
}

/// not-supported for an error of that kind, fail otherwise.
CaseResult from_error(const Error& e) {
    return result(e.kind == ErrorKind::not_supported ? Status::not_supported : Status::fail,
                  e.message);
}

void add_metrics(CaseResult& r, const tools::LsbDifferences& d) {
    r.metrics["max_lsb"] = std::to_string(d.max_lsb);
    r.metrics["p99_lsb"] = std::to_string(d.p99_lsb);
    char text[32];
    std::snprintf(text, sizeof text, "%.4f", d.rmse_lsb);
    r.metrics["rmse_lsb"] = text;
    std::snprintf(text, sizeof text, "%.6f", d.over1);
    r.metrics["over1"] = text;
    std::snprintf(text, sizeof text, "%.6f", d.over2);
    r.metrics["over2"] = text;
}

/// pass or fail by the case's tolerance, with the metrics.
CaseResult judged(const Case& c, const tools::LsbDifferences& d, const std::string& what) {
    const std::string over = c.tolerance.violations(d);
    CaseResult r =
        over.empty()
            ? result(Status::pass)
            : result(Status::fail, what + ": " + over + " (bounds " + c.tolerance.text() + ")");
    add_metrics(r, d);
    return r;
}

struct Bench {
    headless::Context context;
    scene::SceneFile file;
};

Result<Bench> open_bench(const Suite& suite, const Case& c, const CaseSettings& settings) {
    auto file = scene::load_scene_file(suite.scene_path(c.scene));
    if (!file) return file.error();
    auto context = headless::Context::create({settings.platform, suite.width, suite.height});
    if (!context) return context.error();
    return Bench{std::move(context).value(), std::move(file).value()};
}

Result<tools::Rgb8Image> render(const Bench& bench, const std::string& backend,
                                const std::string& path) {
    validation::RenderOptions options;
    const auto b = validation::parse_render_backend(backend);
    if (!b) return b.error();
    options.backend = *b;
    if (!path.empty()) options.path = *gl::parse_path(path);
    if (auto e = validation::check_backend(bench.file, options, !path.empty())) return *e;
    auto image = validation::render_scene_file(bench.context, bench.file, options);
    if (!image) return image.error();
    return tools::rgb_from_rgba8(image->width, image->height, image->rgba);
}

/// Compares `fresh` with `reference`, writing both and the diff image for triage.
tools::LsbDifferences compare_and_keep(const CaseSettings& settings, const Case& c,
                                       const tools::Rgb8Image& fresh,
                                       const tools::Rgb8Image& reference) {
    tools::Rgb8Image diff;
    const auto d = tools::compare_images(fresh, reference, &diff);
    const fs::path base = fs::path(settings.images_dir) / case_file_name(c.name);
    tools::write_png(base.string() + "-fresh.png", fresh);
    tools::write_png(base.string() + "-reference.png", reference);
    tools::write_png(base.string() + "-diff.png", diff);
    return d;
}

// ---- the kinds ------------------------------------------------------------------------------

CaseResult run_context(const Suite& suite, const CaseSettings& settings) {
    auto context = headless::Context::create({settings.platform, suite.width, suite.height});
    if (!context) return from_error(context.error());
    const gl::Caps& caps = context->api().caps;
    CaseResult r = result(Status::pass);
    r.metrics["GL_VENDOR"] = caps.vendor;
    r.metrics["GL_RENDERER"] = caps.renderer;
    r.metrics["GL_VERSION"] = caps.version;
    r.metrics["simd_target"] = simd_target();
    return r;
}

/// cross, fog and paths: the case's backend (and path) against a second rendering.
CaseResult run_pair(const Suite& suite, const Case& c, const CaseSettings& settings,
                    const std::string& reference_backend, const std::string& reference_path) {
    auto bench = open_bench(suite, c, settings);
    if (!bench) return from_error(bench.error());
    const auto fresh = render(*bench, c.backend, c.path);
    if (!fresh) return from_error(fresh.error());
    const auto reference = render(*bench, reference_backend, reference_path);
    if (!reference) return from_error(reference.error());
    const auto d = compare_and_keep(settings, c, *fresh, *reference);
    const std::string what = c.backend + (c.path.empty() ? "" : " " + c.path) + " against " +
                             reference_backend +
                             (reference_path.empty() ? "" : " " + reference_path);
    return judged(c, d, what);
}

CaseResult run_state(const Suite& suite, const Case& c, const CaseSettings& settings) {
    auto bench = open_bench(suite, c, settings);
    if (!bench) return from_error(bench.error());
    const gl::Api& api = bench->context.api();
    scene::RendererOptions options;
    options.backend = c.backend == "arb" ? scene::Backend::arb : scene::Backend::cpu;
    if (!c.path.empty()) options.path = *gl::parse_path(c.path);
    auto renderer = scene::SceneRenderer::create(api, options);
    if (!renderer) return from_error(renderer.error());
    const auto root = scene::scene_graph(bench->file);
    const scene::Camera camera = bench->file.camera_for(suite.width, suite.height);
    api.Viewport(0, 0, suite.width, suite.height);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const auto before = gl::capture_state(api);
    auto report = renderer.value().render(*root, camera, bench->file.frame_settings());
    if (!report) return from_error(report.error());
    const auto changed = gl::state_differences(before, gl::capture_state(api));
    CaseResult r = result(Status::pass);
    r.metrics["changed"] = std::to_string(changed.size());
    if (!changed.empty()) {
        r.status = Status::fail;
        r.reason = std::to_string(changed.size()) + " piece(s) of GL state not restored: ";
        for (std::size_t i = 0; i < changed.size() && i < 3; ++i) {
            r.reason += (i ? "; " : "") + changed[i];
        }
    }
    const GLenum error = api.GetError();
    if (error != GL_NO_ERROR && r.status == Status::pass) {
        r = result(Status::fail, "GL error " + gl::gl_error_name(error) + " after the frame");
    }
    return r;
}

/// The CPU's vertex colours of a scene's geometry, as SceneRenderer's cpu backend computes them
/// (shade_into, the SIMD kernel): F_ex and L_in codes per vertex.
struct VertexCodes {
    std::vector<std::uint8_t> extinction, in_scattering;  // RGBA8 per vertex
};

Result<VertexCodes> cpu_codes(const scene::SceneFile& file, const scene::MeshData& mesh) {
    const auto frame = prepare_frame<float>(file.atmosphere, file.view(), file.model);
    if (!frame) return frame.error();
    VertexCodes codes;
    codes.extinction.resize(mesh.vertex_count() * 4);
    codes.in_scattering.resize(mesh.vertex_count() * 4);
    BatchOutputs outputs;
    outputs.extinction_rgba8 = codes.extinction.data();
    outputs.in_scattering_rgba8 = codes.in_scattering.data();
    BatchSettings batch;
    batch.display = file.display;
    batch.threads = 1;
    const auto shaded = shade_into(
        *frame, Positions::aos(mesh.positions.data(), mesh.vertex_count()), outputs, batch);
    if (!shaded) return shaded.error();
    return codes;
}

/// Vertex codes as an RGB image: F_ex in the top half, L_in in the bottom, 64 vertices a row.
tools::Rgb8Image codes_image(const VertexCodes& codes) {
    constexpr int kRow = 64;
    const std::size_t n = codes.extinction.size() / 4;
    const int rows = static_cast<int>((n + kRow - 1) / kRow);
    tools::Rgb8Image image;
    image.width = kRow;
    image.height = 2 * rows;
    image.rgb.assign(std::size_t(image.width) * image.height * 3, 0);
    for (std::size_t i = 0; i < n; ++i) {
        for (int ch = 0; ch < 3; ++ch) {
            image.rgb[3 * i + ch] = codes.extinction[4 * i + ch];
            image.rgb[3 * (i + std::size_t(rows) * kRow) + ch] = codes.in_scattering[4 * i + ch];
        }
    }
    return image;
}

CaseResult run_cpu_model(const Suite& suite, const Case& c) {
    const auto file = scene::load_scene_file(suite.scene_path(c.scene));
    if (!file) return from_error(file.error());
    const scene::MeshData mesh = scene::scene_geometry(*file);
    const auto codes = cpu_codes(*file, mesh);
    if (!codes) return from_error(codes.error());
    const auto frame = prepare_frame<double>(file->atmosphere, file->view(), file->model);
    if (!frame) return from_error(frame.error());
    tools::LsbHistogram histogram;
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        const glm::dvec3 p(mesh.positions[3 * i], mesh.positions[3 * i + 1],
                           mesh.positions[3 * i + 2]);
        const Scattering<double> s = scatter(*frame, p);
        std::uint8_t fex[3], lin[3];
        for (int ch = 0; ch < 3; ++ch) {
            fex[ch] = to_unorm8(static_cast<float>(s.extinction[ch]));
            lin[ch] =
                to_unorm8(display_value(file->display, static_cast<float>(s.in_scattering[ch])));
        }
        histogram.add(&codes->extinction[4 * i], fex);
        histogram.add(&codes->in_scattering[4 * i], lin);
    }
    CaseResult r = judged(
        c, histogram.differences(),
        "shade_into (" + std::string(simd_target()) + ") against the double-precision model");
    r.metrics["vertices"] = std::to_string(mesh.vertex_count());
    return r;
}

/// golden and cpu-golden: `fresh` against the stored image at `stored`, or written there.
CaseResult against_stored(const Case& c, const CaseSettings& settings,
                          const tools::Rgb8Image& fresh, const fs::path& stored, bool bless,
                          const std::string& bless_flag) {
    if (bless) {
        if (auto e = tools::make_parent_directories(stored.string())) {
            return result(Status::fail, *e);
        }
        if (auto e = tools::write_png(stored.string(), fresh)) return result(Status::fail, *e);
        return result(Status::pass, "blessed: " + stored.string());
    }
    if (!fs::exists(stored)) {
        return result(Status::fail, "no stored image " + stored.string() + " (run aerial-regress " +
                                        bless_flag + " on this device to make one)");
    }
    const auto reference = tools::read_png(stored.string());
    if (!reference) return result(Status::fail, reference.error().message);
    if (reference->width != fresh.width || reference->height != fresh.height) {
        return result(Status::fail, stored.string() + " has another size than the fresh image");
    }
    return judged(c, compare_and_keep(settings, c, fresh, *reference),
                  "against " + stored.string());
}

CaseResult run_golden(const Suite& suite, const Case& c, const CaseSettings& settings) {
    auto bench = open_bench(suite, c, settings);
    if (!bench) return from_error(bench.error());
    const auto fresh = render(*bench, c.backend, c.path);
    if (!fresh) return from_error(fresh.error());
    const fs::path stored =
        fs::path(suite.directory) / settings.device / (c.name.substr(7) + ".png");
    return against_stored(c, settings, *fresh, stored, settings.bless, "--bless");
}

CaseResult run_cpu_golden(const Suite& suite, const Case& c, const CaseSettings& settings) {
    const auto file = scene::load_scene_file(suite.scene_path(c.scene));
    if (!file) return from_error(file.error());
    const auto codes = cpu_codes(*file, scene::scene_geometry(*file));
    if (!codes) return from_error(codes.error());
    const fs::path stored = fs::path(suite.directory) / "cpu" / (c.scene + ".png");
    CaseResult r =
        against_stored(c, settings, codes_image(*codes), stored, settings.bless_cpu, "--bless-cpu");
    r.metrics["simd_target"] = simd_target();
    return r;
}

CaseResult run_selftest(const Case& c) {
    if (c.backend == "crash") std::abort();
    if (c.backend == "hang") {
        for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
    }
    return result(Status::fail, "selftest: fails on purpose");
}

}  // namespace

std::string case_file_name(const std::string& case_name) {
    std::string name = case_name;
    for (char& ch : name) {
        if (ch == '/') ch = '.';
    }
    return name;
}

CaseResult run_case(const Suite& suite, const Case& c, const CaseSettings& settings) {
    switch (c.kind) {
        case CaseKind::context:
            return run_context(suite, settings);
        case CaseKind::cross:
            return run_pair(suite, c, settings, "perpixel", "");
        case CaseKind::fog:
            return run_pair(suite, c, settings, "perpixel", "");
        case CaseKind::paths:
            return run_pair(suite, c, settings, "cpu", "secondary-color");
        case CaseKind::state:
            return run_state(suite, c, settings);
        case CaseKind::cpu_model:
            return run_cpu_model(suite, c);
        case CaseKind::golden:
            return run_golden(suite, c, settings);
        case CaseKind::cpu_golden:
            return run_cpu_golden(suite, c, settings);
        case CaseKind::selftest:
            return run_selftest(c);
    }
    return result(Status::fail, "unknown case kind");
}

}  // namespace aerial::regress
