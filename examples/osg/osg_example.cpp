// aerial-osg-example: one frame of a terrain and a tower rendered headless by OpenSceneGraph with
// the aerial adapter (aerial/osg.hpp), or by the module's own renderer (aerial::scene) from the
// same meshes, texture and camera, so that the two images can be compared with aerial-compare.
//
// OpenSceneGraph 3.6 without X: an EGL surfaceless context (aerial::headless) is made current,
// an osgViewer::Viewer is set up as embedded in it (GraphicsWindowEmbedded) with the context's
// framebuffer object as its default framebuffer, and the frame is read back from that FBO. OSG
// links libGL (GLVND), whose dispatch follows the current EGL context; OSMesa is never used here
// (a program that links libGL and libOSMesa gets NULL from glGetString).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>
#include <osg/Depth>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/Image>
#include <osg/Texture2D>
#include <osgViewer/Viewer>

#include "aerial/atmosphere.hpp"
#include "aerial/gl.hpp"
#include "aerial/headless.hpp"
#include "aerial/osg.hpp"
#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"
#include "support/cli.hpp"
#include "support/png.hpp"

#ifndef GL_FRAMEBUFFER_BINDING
#define GL_FRAMEBUFFER_BINDING 0x8CA6
#endif

namespace {

constexpr const char* kTool = "aerial-osg-example";
constexpr const char* kDescription =
    "Renders one frame of a hazy terrain with a tower, headless on EGL (llvmpipe), either with\n"
    "OpenSceneGraph and the aerial adapter (--renderer osg) or with the module's own scene\n"
    "renderer from the same meshes, texture and camera (--renderer module), and writes a PNG.\n"
    "Compare the two with aerial-compare.";

struct SceneData {
    std::shared_ptr<const aerial::scene::MeshData> terrain, tower;
    std::shared_ptr<const aerial::scene::Texture> texture;
    aerial::scene::Camera camera;
    aerial::Atmosphere atmosphere;
    glm::dvec3 sun_dir{0.0};
    glm::vec3 clear{0.0f};
};

/// A 64 × 64 texture: grass and rock patches with a fine grain (deterministic).
aerial::scene::Texture make_texture() {
    aerial::scene::Texture t;
    t.width = t.height = 64;
    t.rgb.resize(64 * 64 * 3);
    for (int y = 0; y < 64; ++y) {
        for (int x = 0; x < 64; ++x) {
            const unsigned h = (unsigned(x) * 73856093u) ^ (unsigned(y) * 19349663u);
            const int grain = int((h >> 7) % 40u);
            const bool rock = ((x / 16) + (y / 16)) % 2 == 0;
            std::uint8_t* p = &t.rgb[(std::size_t(y) * 64 + std::size_t(x)) * 3];
            p[0] = std::uint8_t(rock ? 120 + grain : 60 + grain);
            p[1] = std::uint8_t(rock ? 110 + grain : 130 + grain);
            p[2] = std::uint8_t(rock ? 100 + grain : 40 + grain / 2);
        }
    }
    return t;
}

/// A box from (x0, y0, z0) to (x1, y1, z1): 6 faces of 2 triangles, texture repeated per face.
aerial::scene::MeshData make_box(glm::dvec3 lo, glm::dvec3 hi) {
    aerial::scene::MeshData m;
    const glm::dvec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                             {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                             {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    const int faces[6][4] = {{0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6},
                             {3, 0, 4, 7}, {4, 5, 6, 7}, {3, 2, 1, 0}};
    const float st[4][2] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
    for (const auto& f : faces) {
        const auto base = std::uint32_t(m.positions.size() / 3);
        for (int k = 0; k < 4; ++k) {
            for (int a = 0; a < 3; ++a) m.positions.push_back(float(c[f[k]][a]));
            m.texcoords.push_back(st[k][0]);
            m.texcoords.push_back(st[k][1]);
        }
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
    }
    return m;
}

aerial::Result<SceneData> make_scene() {
    SceneData s;
    aerial::scene::HeightfieldSpec spec;
    spec.origin_x = -20000.0;
    spec.origin_y = -12000.0;
    spec.size = 40000.0;
    spec.resolution = 97;
    spec.texture_repeat = 500.0;
    aerial::scene::ProceduralTerrain hills;
    hills.amplitude = 900.0;
    hills.feature_size = 9000.0;
    auto terrain = aerial::scene::heightfield_mesh(
        spec, [&](double x, double y) { return aerial::scene::procedural_height(hills, x, y); });
    if (!terrain) return terrain.error();
    s.terrain = std::make_shared<aerial::scene::MeshData>(std::move(terrain.value()));
    s.tower = std::make_shared<aerial::scene::MeshData>(
        make_box({-150.0, -6000.0, 0.0}, {150.0, -5700.0, 1400.0}));
    s.texture = std::make_shared<aerial::scene::Texture>(make_texture());
    auto atmosphere = aerial::atmosphere_preset("hazy");
    if (!atmosphere) return atmosphere.error();
    s.atmosphere = atmosphere.value();
    const double elevation = 0.25, azimuth = 1.2;  // rad; the sun ahead and to the left
    s.sun_dir = {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                 std::sin(elevation)};
    s.camera.eye = {0.0, -11000.0, 1300.0};
    s.camera.target = {0.0, 20000.0, 0.0};
    s.camera.fov_y_rad = 0.9;
    s.camera.near_units = 10.0;
    s.camera.far_units = 60000.0;
    s.clear = glm::vec3(0.6f, 0.7f, 0.85f);  // no sky dome: a plain sky colour
    return s;
}

::osg::Matrixd to_osg(const glm::dmat4& m) {
    ::osg::Matrixd r;
    r.set(&m[0][0]);  // both column-major in memory as OpenGL reads them
    return r;
}

::osg::ref_ptr<::osg::Texture2D> osg_texture(const aerial::scene::Texture& t) {
    // The module's mipmap chain, so both renderers sample the same texels.
    const auto levels = aerial::scene::mipmap_levels(t);
    std::size_t total = 0;
    for (const auto& l : levels) total += l.size();
    auto* data = new unsigned char[total];
    ::osg::Image::MipmapDataType offsets;
    std::size_t at = 0;
    for (std::size_t i = 0; i < levels.size(); ++i) {
        if (i > 0) offsets.push_back(static_cast<unsigned int>(at));
        std::copy(levels[i].begin(), levels[i].end(), data + at);
        at += levels[i].size();
    }
    ::osg::ref_ptr<::osg::Image> image = new ::osg::Image;
    image->setImage(t.width, t.height, 1, GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE, data,
                    ::osg::Image::USE_NEW_DELETE, 1);
    image->setMipmapLevels(offsets);
    ::osg::ref_ptr<::osg::Texture2D> texture = new ::osg::Texture2D(image.get());
    texture->setFilter(::osg::Texture::MIN_FILTER, ::osg::Texture::LINEAR_MIPMAP_LINEAR);
    texture->setFilter(::osg::Texture::MAG_FILTER, ::osg::Texture::LINEAR);
    texture->setWrap(::osg::Texture::WRAP_S, ::osg::Texture::REPEAT);
    texture->setWrap(::osg::Texture::WRAP_T, ::osg::Texture::REPEAT);
    texture->setResizeNonPowerOfTwoHint(false);
    texture->setInternalFormat(GL_RGB8);
    return texture;
}

::osg::ref_ptr<::osg::Geometry> osg_geometry(const std::string& name,
                                             const aerial::scene::MeshData& m) {
    ::osg::ref_ptr<::osg::Geometry> g = new ::osg::Geometry;
    g->setName(name);
    auto* vertices = new ::osg::Vec3Array;
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        vertices->push_back({m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]});
    }
    g->setVertexArray(vertices);
    if (!m.texcoords.empty()) {
        auto* st = new ::osg::Vec2Array;
        for (std::size_t i = 0; i < m.vertex_count(); ++i) {
            st->push_back({m.texcoords[2 * i], m.texcoords[2 * i + 1]});
        }
        g->setTexCoordArray(0, st, ::osg::Array::BIND_PER_VERTEX);
    }
    g->addPrimitiveSet(
        new ::osg::DrawElementsUInt(GL_TRIANGLES, m.indices.begin(), m.indices.end()));
    g->setUseDisplayList(false);
    g->setUseVertexBufferObjects(true);
    return g;
}

/// The frame by OpenSceneGraph with the adapter, read from the context's framebuffer.
aerial::Result<std::vector<std::uint8_t>> render_osg(aerial::headless::Context& ctx,
                                                     const SceneData& s,
                                                     aerial::osg_adapter::Settings settings) {
    osgViewer::Viewer viewer;
    viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);
    auto window = viewer.setUpViewerAsEmbeddedInWindow(0, 0, ctx.width(), ctx.height());
    GLint fbo = 0;
    ctx.api().GetIntegerv(GL_FRAMEBUFFER_BINDING, &fbo);
    window->setDefaultFboId(GLuint(fbo));  // the EGL context renders into this FBO

    ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
    auto texture = osg_texture(*s.texture);
    for (auto [name, mesh] : {std::pair{"terrain", s.terrain}, std::pair{"tower", s.tower}}) {
        auto g = osg_geometry(name, *mesh);
        g->getOrCreateStateSet()->setTextureAttributeAndModes(0, texture.get());
        root->addChild(g.get());
    }
    // The module's renderer draws meshes with GL_LEQUAL; match it.
    root->getOrCreateStateSet()->setAttributeAndModes(new ::osg::Depth(::osg::Depth::LEQUAL));

    ::osg::Camera* camera = viewer.getCamera();
    camera->setComputeNearFarMode(::osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    camera->setCullingMode(::osg::CullSettings::NO_CULLING);
    camera->setProjectionMatrix(to_osg(aerial::scene::projection_matrix(s.camera)));
    camera->setViewMatrix(to_osg(aerial::scene::view_matrix(s.camera)));
    camera->setClearColor({s.clear.r, s.clear.g, s.clear.b, 1.0f});
    camera->setClearMask(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    auto callback = aerial::osg_adapter::ScatteringCallback::create(settings, camera);
    if (!callback) return callback.error();
    root->setUpdateCallback(callback.value().get());
    viewer.setSceneData(root.get());
    viewer.realize();
    viewer.frame();
    if (const auto& e = callback.value()->last_error()) return *e;
    ctx.api().Finish();
    return ctx.read_rgba8();
}

/// The same frame by aerial::scene::SceneRenderer (policy off: every node with the model).
aerial::Result<std::vector<std::uint8_t>> render_module(aerial::headless::Context& ctx,
                                                        const SceneData& s,
                                                        const aerial::osg_adapter::Settings& a) {
    aerial::scene::RendererOptions options;
    options.backend = a.backend == aerial::osg_adapter::Backend::arb ? aerial::scene::Backend::arb
                                                                     : aerial::scene::Backend::cpu;
    auto renderer = aerial::scene::SceneRenderer::create(ctx.api(), options);
    if (!renderer) return renderer.error();
    auto root = aerial::scene::make_group("world");
    root->add(aerial::scene::make_mesh("terrain", s.terrain, s.texture));
    root->add(aerial::scene::make_mesh("tower", s.tower, s.texture));
    aerial::scene::FrameSettings fs;
    fs.atmosphere = a.atmosphere;
    fs.sun_dir = a.sun_dir;
    fs.up = a.up;
    fs.meters_per_unit = a.meters_per_unit;
    fs.display = a.display;
    fs.model = a.model;
    fs.policy = false;
    const auto& api = ctx.api();
    api.Viewport(0, 0, ctx.width(), ctx.height());
    api.ClearColor(s.clear.r, s.clear.g, s.clear.b, 1.0f);
    api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    auto report = renderer.value().render(*root, s.camera, fs);
    if (!report) return report.error();
    api.Finish();
    return ctx.read_rgba8();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{kDescription, kTool};
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    std::string out, size_text = "320x180", renderer_text = "osg", backend_text = "cpu",
                     model_text = "hoffman-preetham";
    double exposure = 4.0;
    app.add_option("--out", out, "PNG to write")->required();
    app.add_option("--size", size_text, "Image size WxH, 16..4096")->capture_default_str();
    app.add_option("--renderer", renderer_text, "osg (the adapter) or module (aerial::scene)")
        ->capture_default_str();
    app.add_option("--backend", backend_text, "cpu or arb")->capture_default_str();
    app.add_option("--model", model_text, "hoffman-preetham or height")->capture_default_str();
    app.add_option("--exposure", exposure, "Display exposure, > 0")->capture_default_str();
    if (auto status = aerial::tools::parse_command_line(app, argc, argv, kTool)) return *status;

    auto size = aerial::tools::parse_size(size_text, "--size", 4096);
    if (!size || size->first < 16 || size->second < 16) {
        return aerial::tools::fail(
            kTool, size ? "--size: expected sides of 16..4096, got '" + size_text + "'"
                        : size.error().message);
    }
    if (renderer_text != "osg" && renderer_text != "module") {
        return aerial::tools::fail(
            kTool, "--renderer: '" + renderer_text + "' is unknown (expected osg or module)");
    }
    auto backend = aerial::osg_adapter::parse_backend(backend_text);
    if (!backend) return aerial::tools::fail(kTool, "--backend: " + backend.error().message);
    auto model = aerial::parse_model(model_text);
    if (!model || aerial::is_numerical(*model)) {
        return aerial::tools::fail(
            kTool, "--model: '" + model_text + "' is not one of hoffman-preetham, height");
    }
    if (!(exposure > 0.0) || !std::isfinite(exposure)) {
        return aerial::tools::fail(
            kTool, "--exposure: expected a finite value > 0, got " + std::to_string(exposure));
    }

    auto scene = make_scene();
    if (!scene) return aerial::tools::fail(kTool, scene.error().message);
    scene.value().camera.aspect = double(size->first) / double(size->second);

    auto ctx = aerial::headless::Context::create(
        {aerial::headless::Platform::egl, size->first, size->second});
    if (!ctx) return aerial::tools::fail(kTool, "EGL context: " + ctx.error().message);

    aerial::osg_adapter::Settings settings;
    settings.backend = *backend;
    settings.atmosphere = scene->atmosphere;
    settings.sun_dir = scene->sun_dir;
    settings.model = *model;
    settings.display.exposure = float(exposure);
    settings.arb_limits = aerial::gl::native_arb_limits(ctx->api());  // as the module's renderer

    auto pixels = renderer_text == "osg" ? render_osg(ctx.value(), *scene, settings)
                                         : render_module(ctx.value(), *scene, settings);
    if (!pixels) return aerial::tools::fail(kTool, pixels.error().message);
    const char* renderer = reinterpret_cast<const char*>(ctx->api().GetString(GL_RENDERER));
    auto image = aerial::tools::rgb_from_rgba8(size->first, size->second, pixels.value());
    if (auto e = aerial::tools::write_png(out, image)) return aerial::tools::fail(kTool, *e);
    std::printf("%s: renderer=%s backend=%s model=%s %dx%d GL_RENDERER=%s -> %s\n", kTool,
                renderer_text.c_str(), backend_text.c_str(), model_text.c_str(), size->first,
                size->second, renderer ? renderer : "?", out.c_str());
    return 0;
}
