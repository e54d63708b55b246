#include "aerial/validation/mesh_grader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "aerial/adaptive_scene.hpp"
#include "aerial/batch.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/headless.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/validation/scene_render.hpp"
#include "common/error_text.hpp"

namespace aerial::validation {
namespace {
constexpr double kHalfPi = 1.57079632679489661923;  // the faces' field of view
constexpr const char* kCreate = "validation::MeshGrader::create";
constexpr const char* kGrade = "validation::MeshGrader::grade";
}  // namespace

struct MeshGrader::Impl {
    headless::Context context;
    std::optional<scene::SceneRenderer> renderer;
    std::shared_ptr<scene::Texture> texture;  ///< 1 x 1, the texel

    explicit Impl(headless::Context c) : context(std::move(c)) {}
};

MeshGrader::MeshGrader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MeshGrader::MeshGrader(MeshGrader&&) noexcept = default;
MeshGrader& MeshGrader::operator=(MeshGrader&&) noexcept = default;
MeshGrader::~MeshGrader() = default;

Result<MeshGrader> MeshGrader::create(int face_pixels) {
    if (face_pixels < 16 || face_pixels > 2048)
        return aerial::detail::invalid(kCreate, "face_pixels", "16 .. 2048",
                                       aerial::detail::number(face_pixels));
    auto context =
        headless::Context::create({headless::Platform::osmesa, face_pixels, face_pixels});
    if (!context) return aerial::detail::from(kCreate, context.error());
    auto impl = std::make_unique<Impl>(std::move(context.value()));
    auto renderer = scene::SceneRenderer::create(impl->context.api());
    if (!renderer) return aerial::detail::from(kCreate, renderer.error());
    impl->renderer.emplace(std::move(renderer.value()));
    impl->context.api().ClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    return MeshGrader(std::move(impl));
}

int MeshGrader::face_pixels() const { return impl_->context.width(); }

Result<MeshGrade> MeshGrader::grade(const GradeSetting& setting, const scene::MeshData& data) {
    auto made = mesh_from_data(data);
    if (!made) return aerial::detail::from(kGrade, made.error());
    return grade(setting, *made);
}

Result<MeshGrade> MeshGrader::grade(const GradeSetting& setting, const mesh::Mesh& mesh) {
    const Frame<float>& frame = setting.frame;
    const mesh::ColourOptions& colour = setting.colour;
    const MeshGradeOptions& options = setting.options;
    if (!(options.near_m > 0.0))
        return aerial::detail::invalid(kGrade, "near_m", "a value > 0",
                                       aerial::detail::number(options.near_m));
    if (!(options.far_m > options.near_m))
        return aerial::detail::invalid(kGrade, "far_m", "a value > near_m",
                                       aerial::detail::number(options.far_m));
    if (auto e = mesh::validate_mesh(mesh)) return aerial::detail::from(kGrade, *e);
    Impl& g = *impl_;
    const gl::Api& api = g.context.api();
    const int size = g.context.width();

    // The texel: one texel of the brightest texel's 8-bit code, as the engine's texture holds it.
    const std::uint8_t texel[3] = {to_unorm8(colour.texel.x), to_unorm8(colour.texel.y),
                                   to_unorm8(colour.texel.z)};
    if (!g.texture || !std::equal(texel, texel + 3, g.texture->rgb.begin())) {
        g.texture = std::make_shared<scene::Texture>();
        g.texture->width = g.texture->height = 1;
        g.texture->rgb.assign(texel, texel + 3);
    }
    const float texel_value[3] = {texel[0] / 255.0f, texel[1] / 255.0f, texel[2] / 255.0f};

    // The mesh as one node drawn by the library's renderer with the frame's model, policy off.
    auto root = scene::make_group("grade");
    root->add(scene::make_mesh(
        "mesh", std::make_shared<scene::MeshData>(scene::mesh_data_from(mesh, 1.0)), g.texture));
    scene::FrameSettings settings;
    settings.atmosphere = frame.atmosphere;
    settings.sun_dir = frame.view.sun_dir;
    settings.up = frame.view.up;
    settings.meters_per_unit = frame.view.meters_per_unit;
    settings.display = colour.display;
    settings.model = frame.model;
    settings.policy = false;
    scene::Camera camera;
    camera.eye = frame.view.eye;
    camera.fov_y_rad = kHalfPi;
    camera.aspect = 1.0;
    camera.near_units = options.near_m;
    camera.far_units = options.far_m;
    const std::array<std::pair<glm::dvec3, glm::dvec3>, 6> faces = {{
        {{1, 0, 0}, {0, 0, 1}},
        {{-1, 0, 0}, {0, 0, 1}},
        {{0, 1, 0}, {0, 0, 1}},
        {{0, -1, 0}, {0, 0, 1}},
        {{0, 0, 1}, {0, 1, 0}},
        {{0, 0, -1}, {0, 1, 0}},
    }};
    LsbHistogram histogram;
    std::vector<float> depth(std::size_t(size) * std::size_t(size)), points, extinction,
        in_scattering;
    std::vector<std::size_t> pixels;
    api.Viewport(0, 0, size, size);
    if (options.images) {
        options.images->width = 6 * size;
        options.images->height = size;
        options.images->drawn.assign(std::size_t(6 * size) * std::size_t(size) * 3, 0);
        options.images->reference = options.images->drawn;
        options.images->covered.assign(std::size_t(6 * size) * std::size_t(size), 0);
    }
    // Pixel i of a face (top row first) in the six-face images.
    const auto image_index = [&](std::size_t face, std::size_t i) {
        return 3 * ((i / std::size_t(size)) * std::size_t(6 * size) + face * std::size_t(size) +
                    i % std::size_t(size));
    };
    for (std::size_t face = 0; face < faces.size(); ++face) {
        const auto& [forward, up] = faces[face];
        camera.target = camera.eye + forward;
        camera.up = up;
        api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        auto drawn = g.renderer->render(*root, camera, settings);
        if (!drawn) return aerial::detail::from(kGrade, drawn.error());
        api.Finish();
        const std::vector<std::uint8_t> rgba = g.context.read_rgba8();
        if (options.images) {
            for (std::size_t i = 0; i < std::size_t(size) * std::size_t(size); ++i)
                std::copy_n(&rgba[4 * i], 3, &options.images->drawn[image_index(face, i)]);
        }
        api.PixelStorei(GL_PACK_ALIGNMENT, 1);
        api.ReadPixels(0, 0, size, size, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
        validation::positions_from_depth(depth, size, size, scene::projection_matrix(camera),
                                         scene::view_matrix(camera), points, pixels);
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
        if (!stats) return aerial::detail::from(kGrade, stats.error());
        for (std::size_t i = 0; i < pixels.size(); ++i) {
            std::uint8_t reference[3];
            for (std::size_t c = 0; c < 3; ++c)
                reference[c] = to_unorm8(texel_value[c] * extinction[3 * i + c] +
                                         display_value(colour.display, in_scattering[3 * i + c]));
            const int lsb = histogram.add(&rgba[4 * pixels[i]], reference);
            if (options.images) {
                const std::size_t at = image_index(face, pixels[i]);
                std::copy_n(reference, 3, &options.images->reference[at]);
                options.images->covered[at / 3] = 1;
            }
            if (options.report && lsb >= options.report_lsb) {
                MeshGradeOptions::Pixel pixel;
                pixel.point = {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
                std::copy(&rgba[4 * pixels[i]], &rgba[4 * pixels[i]] + 3, pixel.drawn);
                std::copy(reference, reference + 3, pixel.reference);
                options.report->push_back(pixel);
            }
        }
    }
    const GLenum error = api.GetError();
    if (error != GL_NO_ERROR)
        return aerial::detail::error(kGrade, "GL", "GL error " + gl::gl_error_name(error));
    if (histogram.pixels() == 0)
        return aerial::detail::error(kGrade, "mesh", "no pixel of it is in view");
    return histogram.differences();
}

Result<mesh::Mesh> mesh_from_data(const scene::MeshData& data) {
    mesh::Mesh m;
    std::vector<mesh::Mesh::VertexHandle> vertices;
    vertices.reserve(data.vertex_count());
    for (std::size_t i = 0; i < data.vertex_count(); ++i) {
        vertices.push_back(m.add_vertex(mesh::Mesh::Point(
            data.positions[3 * i], data.positions[3 * i + 1], data.positions[3 * i + 2])));
    }
    for (std::size_t t = 0; t + 2 < data.indices.size(); t += 3) {
        for (std::size_t k = t; k < t + 3; ++k) {
            if (data.indices[k] >= vertices.size())
                return aerial::detail::invalid(
                    "validation::mesh_from_data", "indices[" + std::to_string(k) + "]",
                    "a vertex index below " + std::to_string(vertices.size()),
                    std::to_string(data.indices[k]));
        }
        const auto face = m.add_face(vertices[data.indices[t]], vertices[data.indices[t + 1]],
                                     vertices[data.indices[t + 2]]);
        if (!face.is_valid()) {
            return aerial::detail::error("validation::mesh_from_data",
                                         "triangles[" + std::to_string(t / 3) + "]",
                                         "cannot be added (non-manifold, or repeats a vertex)");
        }
    }
    m.update_face_normals();
    return m;
}

}  // namespace aerial::validation
