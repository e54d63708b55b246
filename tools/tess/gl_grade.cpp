#include "tess/gl_grade.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "aerial/batch.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/headless.hpp"
#include "aerial/validation/scene_render.hpp"

namespace aerial::tess {
namespace {
constexpr double kHalfPi = 1.57079632679489661923;  // the faces' field of view
}  // namespace

struct GlGrader::Impl {
    headless::Context context;
    gl::ApplyOptions apply;
    std::optional<gl::CombinerTexture> combiner;
    GLuint texture = 0;
    std::uint8_t texel[3] = {0, 0, 0};  // what the texture holds now

    explicit Impl(headless::Context c) : context(std::move(c)) {}
    ~Impl() {
        combiner.reset();
        if (texture) context.api().DeleteTextures(1, &texture);
    }
};

GlGrader::GlGrader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GlGrader::GlGrader(GlGrader&&) noexcept = default;
GlGrader& GlGrader::operator=(GlGrader&&) noexcept = default;
GlGrader::~GlGrader() = default;

Result<GlGrader> GlGrader::create(int face_pixels) {
    if (face_pixels < 16 || face_pixels > 2048)
        return Error{"face_pixels",
                     "face_pixels: expected 16 .. 2048, got " + std::to_string(face_pixels)};
    auto context = headless::Context::create({headless::Backend::osmesa, face_pixels, face_pixels});
    if (!context) return context.error();
    auto impl = std::make_unique<Impl>(std::move(context.value()));
    const gl::Api& api = impl->context.api();
    auto path = gl::choose_path(api.caps, gl::Path::automatic);
    if (!path) return path.error();
    impl->apply.path = *path;
    if (*path == gl::Path::combiner) {
        auto created = gl::CombinerTexture::create(api);
        if (!created) return created.error();
        impl->combiner.emplace(std::move(created.value()));
        impl->apply.combiner = &*impl->combiner;
    }
    api.GenTextures(1, &impl->texture);
    api.BindTexture(GL_TEXTURE_2D, impl->texture);
    api.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    api.TexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, 1, 1, 0, GL_RGB, GL_UNSIGNED_BYTE, impl->texel);
    api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    api.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    api.TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    api.Enable(GL_TEXTURE_2D);
    api.Enable(GL_DEPTH_TEST);
    api.DepthFunc(GL_LEQUAL);
    api.ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    return GlGrader(std::move(impl));
}

Result<tools::LsbDifferences> GlGrader::grade(const mesh::Mesh& mesh, const Frame<float>& frame,
                                              const mesh::ColourOptions& colour,
                                              const GlGradeOptions& options) {
    if (!(options.near_m > 0.0))
        return Error{"near_m", "near_m: expected > 0, got " + std::to_string(options.near_m)};
    if (!(options.far_m > options.near_m))
        return Error{"far_m", "far_m: expected > near_m, got " + std::to_string(options.far_m)};
    if (auto e = mesh::validate_mesh(mesh)) return *e;
    Impl& g = *impl_;
    const gl::Api& api = g.context.api();
    const int size = g.context.width();

    // The texel: one texel of the brightest texel's 8-bit code, as the engine's texture holds it.
    const std::uint8_t texel[3] = {to_unorm8(colour.texel.x), to_unorm8(colour.texel.y),
                                   to_unorm8(colour.texel.z)};
    if (!std::equal(texel, texel + 3, g.texel)) {
        std::copy(texel, texel + 3, g.texel);
        api.TexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, 1, 1, 0, GL_RGB, GL_UNSIGNED_BYTE, g.texel);
    }
    const float texel_value[3] = {texel[0] / 255.0f, texel[1] / 255.0f, texel[2] / 255.0f};

    // The vertex arrays (every vertex; deleted faces are not drawn) and their colours.
    std::vector<float> positions;
    positions.reserve(3 * mesh.n_vertices());
    for (const auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        positions.insert(positions.end(), {float(p[0]), float(p[1]), float(p[2])});
    }
    std::vector<unsigned> indices;
    indices.reserve(3 * mesh.n_faces());
    for (const auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        for (const auto v : mesh.fv_range(f)) indices.push_back(unsigned(v.idx()));
    }
    const std::size_t n = mesh.n_vertices();
    std::vector<std::uint8_t> primary(4 * n), secondary(4 * n);
    BatchOutputs out;
    out.extinction_rgba8 = primary.data();
    out.in_scattering_rgba8 = secondary.data();
    BatchSettings settings;
    settings.display = colour.display;
    if (auto stats = shade_into(frame, Positions::aos(positions.data(), n), out, settings); !stats)
        return stats.error();
    gl::VertexColours colours;
    colours.primary = primary.data();
    colours.secondary = secondary.data();
    colours.vertex_count = n;
    const auto draw = [&] {
        api.EnableClientState(GL_VERTEX_ARRAY);
        api.VertexPointer(3, GL_FLOAT, 0, positions.data());
        api.DrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT, indices.data());
        api.DisableClientState(GL_VERTEX_ARRAY);
    };

    const glm::dvec3 eye = frame.view.eye;
    const glm::dmat4 projection = glm::perspective(kHalfPi, 1.0, options.near_m, options.far_m);
    const std::array<std::pair<glm::dvec3, glm::dvec3>, 6> faces = {{
        {{1, 0, 0}, {0, 0, 1}},
        {{-1, 0, 0}, {0, 0, 1}},
        {{0, 1, 0}, {0, 0, 1}},
        {{0, -1, 0}, {0, 0, 1}},
        {{0, 0, 1}, {0, 1, 0}},
        {{0, 0, -1}, {0, 1, 0}},
    }};
    tools::LsbHistogram histogram;
    std::vector<float> depth(std::size_t(size) * std::size_t(size)), points, extinction,
        in_scattering;
    std::vector<std::size_t> pixels;
    api.Viewport(0, 0, size, size);
    for (const auto& [forward, up] : faces) {
        const glm::dmat4 view = glm::lookAt(eye, eye + forward, up);
        api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        api.MatrixMode(GL_PROJECTION);
        api.LoadMatrixf(glm::value_ptr(glm::mat4(projection)));
        api.MatrixMode(GL_MODELVIEW);
        api.LoadMatrixf(glm::value_ptr(glm::mat4(view)));
        auto drawn = gl::draw_with_colours(api, g.apply, colours, draw);
        if (!drawn) return drawn.error();
        api.Finish();
        const std::vector<std::uint8_t> rgba = g.context.read_rgba8();
        api.PixelStorei(GL_PACK_ALIGNMENT, 1);
        api.ReadPixels(0, 0, size, size, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
        validation::positions_from_depth(depth, size, size, projection, view, points, pixels);
        if (pixels.empty()) continue;
        if (options.dome) {
            // The sky in the pixel's direction: the sphere's point along the ray from its centre
            // (the eye) through the drawn point.
            const glm::dvec3 centre = options.dome->centre;
            for (std::size_t i = 0; i < pixels.size(); ++i) {
                const glm::dvec3 p{points[3 * i], points[3 * i + 1], points[3 * i + 2]};
                const glm::dvec3 s = centre + options.dome->radius_m * glm::normalize(p - centre);
                points[3 * i] = float(s.x);
                points[3 * i + 1] = float(s.y);
                points[3 * i + 2] = float(s.z);
            }
        }
        extinction.resize(points.size());
        in_scattering.resize(points.size());
        BatchOutputs exact;
        exact.extinction_rgb = extinction.data();
        exact.in_scattering_rgb = in_scattering.data();
        BatchSettings exact_settings;
        exact_settings.display = colour.display;
        auto stats =
            shade_into(frame, Positions::aos(points.data(), pixels.size()), exact, exact_settings);
        if (!stats) return stats.error();
        for (std::size_t i = 0; i < pixels.size(); ++i) {
            std::uint8_t reference[3];
            for (std::size_t c = 0; c < 3; ++c)
                reference[c] = to_unorm8(texel_value[c] * extinction[3 * i + c] +
                                         display_value(colour.display, in_scattering[3 * i + c]));
            const int lsb = histogram.add(&rgba[4 * pixels[i]], reference);
            if (options.report && lsb >= options.report_lsb) {
                GlGradeOptions::Pixel pixel;
                pixel.point = {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
                std::copy(&rgba[4 * pixels[i]], &rgba[4 * pixels[i]] + 3, pixel.drawn);
                std::copy(reference, reference + 3, pixel.reference);
                options.report->push_back(pixel);
            }
        }
    }
    const GLenum error = api.GetError();
    if (error != GL_NO_ERROR) return Error{"GL", "GL error " + gl::gl_error_name(error)};
    if (histogram.pixels() == 0) return Error{"mesh", "mesh: no pixel of it is in view"};
    return histogram.differences();
}

}  // namespace aerial::tess
