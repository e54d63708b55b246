// The OpenSceneGraph adapter: the arrays and parameters it writes are the module's, the state it
// sets is what aerial/osg.hpp lists, errors name the field, and a frame drawn by OSG with the
// adapter leaves the GL state as the same frame without it (EGL surfaceless, llvmpipe).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/MatrixTransform>
#include <osg/TexEnv>
#include <osg/VertexProgram>
#include <osgUtil/UpdateVisitor>
#include <osgViewer/Viewer>

#include "aerial/gl.hpp"
#include "aerial/gl_state.hpp"
#include "aerial/headless.hpp"
#include "aerial/osg.hpp"

#ifndef GL_COLOR_SUM
#define GL_COLOR_SUM 0x8458
#endif
#ifndef GL_FRAMEBUFFER_BINDING
#define GL_FRAMEBUFFER_BINDING 0x8CA6
#endif

namespace {

using aerial::osg_adapter::Backend;
using aerial::osg_adapter::ScatteringCallback;
using aerial::osg_adapter::Settings;

/// A grid of quads in the plane z = height, from (x0, y0) to (x0 + size, y0 + size).
::osg::ref_ptr<::osg::Geometry> make_grid(float x0, float y0, float size, float height, int n,
                                          const char* name) {
    ::osg::ref_ptr<::osg::Geometry> g = new ::osg::Geometry;
    g->setName(name);
    auto* v = new ::osg::Vec3Array;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            v->push_back({x0 + size * float(i) / float(n), y0 + size * float(j) / float(n),
                          height + 30.0f * float((i * 7 + j * 3) % 5)});
        }
    }
    g->setVertexArray(v);
    auto* e = new ::osg::DrawElementsUInt(GL_TRIANGLES);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const unsigned a = unsigned(j * (n + 1) + i), b = a + 1, c = a + unsigned(n + 1),
                           d = c + 1;
            for (unsigned k : {a, b, d, a, d, c}) e->push_back(k);
        }
    }
    g->addPrimitiveSet(e);
    return g;
}

Settings test_settings(Backend backend) {
    Settings s;
    s.backend = backend;
    s.sun_dir = glm::normalize(glm::dvec3(0.3, 0.8, 0.4));
    s.display.exposure = 2.0f;
    return s;
}

/// The module's own results for world positions, as the adapter must write them.
struct Expected {
    std::vector<std::uint8_t> primary, secondary;
};
Expected shade(const Settings& s, const glm::dvec3& eye, const std::vector<float>& world) {
    aerial::View view;
    view.eye = eye;
    view.sun_dir = s.sun_dir;
    view.up = s.up;
    view.meters_per_unit = s.meters_per_unit;
    auto frame = aerial::prepare_frame<float>(s.atmosphere, view, s.model);
    EXPECT_TRUE(frame.ok());
    const std::size_t n = world.size() / 3;
    Expected ex{std::vector<std::uint8_t>(4 * n), std::vector<std::uint8_t>(4 * n)};
    aerial::BatchOutputs out;
    out.extinction_rgba8 = ex.primary.data();
    out.in_scattering_rgba8 = ex.secondary.data();
    aerial::BatchSettings b;
    b.display = s.display;
    b.threads = 1;
    EXPECT_TRUE(
        aerial::shade_into(frame.value(), aerial::Positions::aos(world.data(), n), out, b).ok());
    return ex;
}

void check_cpu_backend(const Settings& s) {
    auto cb = ScatteringCallback::create(s, nullptr);
    ASSERT_TRUE(cb.ok()) << cb.error().message;
    ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
    ::osg::ref_ptr<::osg::MatrixTransform> xf = new ::osg::MatrixTransform;
    const ::osg::Matrixd m = ::osg::Matrixd::rotate(0.4, ::osg::Vec3d(0, 0, 1)) *
                             ::osg::Matrixd::translate(2000.0, 9000.0, 150.0);
    xf->setMatrix(m);
    auto grid = make_grid(-3000.0f, -3000.0f, 6000.0f, 0.0f, 8, "grid");
    xf->addChild(grid.get());
    root->addChild(xf.get());

    const glm::dvec3 eye(0.0, -2000.0, 400.0);
    auto error = cb.value()->update_now(*root, eye);
    ASSERT_FALSE(error) << error->message;
    EXPECT_EQ(cb.value()->last_report().geometries, 1u);
    EXPECT_EQ(cb.value()->last_report().vertices, 81u);
    EXPECT_EQ(cb.value()->last_report().invalid_vertices, 0u);

    const auto* v = static_cast<const ::osg::Vec3Array*>(grid->getVertexArray());
    std::vector<float> world;
    for (const auto& p : *v) {
        const ::osg::Vec3d w = ::osg::Vec3d(p) * m;
        world.insert(world.end(), {float(w.x()), float(w.y()), float(w.z())});
    }
    const Expected ex = shade(s, eye, world);
    const auto* primary = dynamic_cast<const ::osg::Vec4ubArray*>(grid->getColorArray());
    const auto* secondary = dynamic_cast<const ::osg::Vec3ubArray*>(grid->getSecondaryColorArray());
    ASSERT_NE(primary, nullptr) << "no Vec4ub colour array";
    ASSERT_NE(secondary, nullptr) << "no Vec3ub secondary-colour array";
    ASSERT_EQ(primary->size(), v->size());
    ASSERT_EQ(secondary->size(), v->size());
    EXPECT_EQ(primary->getBinding(), ::osg::Array::BIND_PER_VERTEX);
    bool some_haze = false;
    for (std::size_t i = 0; i < v->size(); ++i) {
        for (int c = 0; c < 4; ++c) {
            ASSERT_EQ((*primary)[i][c], ex.primary[4 * i + c]) << "F_ex of vertex " << i;
        }
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ((*secondary)[i][c], ex.secondary[4 * i + c]) << "L_in of vertex " << i;
        }
        some_haze = some_haze || (*secondary)[i][2] > 0;
    }
    EXPECT_TRUE(some_haze) << "the scene is too small to test anything";
    EXPECT_EQ(grid->getDataVariance(), ::osg::Object::DYNAMIC);

    // State the header lists, on the callback's node.
    const ::osg::StateSet* state = root->getStateSet();
    ASSERT_NE(state, nullptr);
    EXPECT_EQ(state->getMode(GL_COLOR_SUM), ::osg::StateAttribute::ON);
    EXPECT_EQ(state->getMode(GL_LIGHTING), ::osg::StateAttribute::OFF);
    const auto* env = dynamic_cast<const ::osg::TexEnv*>(
        state->getTextureAttribute(0, ::osg::StateAttribute::TEXENV));
    ASSERT_NE(env, nullptr);
    EXPECT_EQ(env->getMode(), ::osg::TexEnv::MODULATE);
    EXPECT_EQ(state->getAttribute(::osg::StateAttribute::VERTEXPROGRAM), nullptr);

    // A moved eye changes the colours and marks the arrays dirty (OSG re-uploads them).
    const unsigned modified = primary->getModifiedCount();
    ASSERT_FALSE(cb.value()->update_now(*root, eye + glm::dvec3(0.0, 4000.0, 0.0)));
    EXPECT_GT(primary->getModifiedCount(), modified);
    EXPECT_EQ(shade(s, eye + glm::dvec3(0.0, 4000.0, 0.0), world).primary[0], (*primary)[0][0]);
}

TEST(OsgAdapter, CpuBackendWritesTheModulesColoursForWorldPositionsBelowATransform) {
    // OSG's Z-up in metres, and a Y-up scene in kilometres: the adapter passes both on.
    Settings y_up_km = test_settings(Backend::cpu);
    y_up_km.up = {0.0, 1.0, 0.0};
    y_up_km.sun_dir = glm::normalize(glm::dvec3(0.3, 0.4, -0.8));
    y_up_km.meters_per_unit = 1000.0;
    y_up_km.model = aerial::Model::height;
    for (const Settings& s : {test_settings(Backend::cpu), y_up_km}) {
        SCOPED_TRACE(s.meters_per_unit == 1.0 ? "Z up, metres" : "Y up, kilometres");
        check_cpu_backend(s);
    }
}

TEST(OsgAdapter, ArbBackendSetsTheGeneratedProgramAndItsParameters) {
    for (aerial::Model model : {aerial::Model::hoffman_preetham, aerial::Model::height}) {
        Settings s = test_settings(Backend::arb);
        s.model = model;
        auto cb = ScatteringCallback::create(s, nullptr);
        ASSERT_TRUE(cb.ok()) << cb.error().message;
        ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
        root->addChild(make_grid(-3000.0f, 1000.0f, 6000.0f, 0.0f, 4, "grid"));
        const glm::dvec3 eye(10.0, -500.0, 300.0);
        auto error = cb.value()->update_now(*root, eye);
        ASSERT_FALSE(error) << error->message;

        aerial::ArbProgramOptions options;
        options.model = model;
        options.model_matrix = true;  // the adapter's programs take model-space vertices
        auto program = aerial::generate_arb_program(options);
        ASSERT_TRUE(program.ok());
        EXPECT_EQ(cb.value()->program_text(), program->text);
        const auto* vp = dynamic_cast<const ::osg::VertexProgram*>(
            root->getStateSet()->getAttribute(::osg::StateAttribute::VERTEXPROGRAM));
        ASSERT_NE(vp, nullptr) << "no VertexProgram on the node's StateSet";
        EXPECT_EQ(vp->getVertexProgram(), program->text);
        EXPECT_EQ(root->getStateSet()->getMode(GL_COLOR_SUM), ::osg::StateAttribute::ON);

        aerial::View view;
        view.eye = eye;
        view.sun_dir = s.sun_dir;
        auto frame = aerial::prepare_frame<float>(s.atmosphere, view, model);
        ASSERT_TRUE(frame.ok());
        auto expected = aerial::arb_program_parameters(*frame, s.display, program->options);
        ASSERT_TRUE(expected.ok());
        const auto& locals = vp->getLocalParameters();
        ASSERT_EQ(locals.size(), expected->size());
        for (std::size_t i = 0; i < expected->size(); ++i) {
            const auto it = locals.find(GLuint(i));
            ASSERT_NE(it, locals.end()) << "program.local[" << i << "] not set";
            for (int c = 0; c < 4; ++c) {
                EXPECT_EQ(it->second[c], (*expected)[i][std::size_t(c)])
                    << "program.local[" << i << "][" << c << "]";
            }
        }

        // Back to the cpu backend: the program goes, colour arrays come.
        ASSERT_FALSE(cb.value()->set_settings(test_settings(Backend::cpu)));
        ASSERT_FALSE(cb.value()->update_now(*root, eye));
        EXPECT_EQ(root->getStateSet()->getAttribute(::osg::StateAttribute::VERTEXPROGRAM), nullptr);
    }
}

TEST(OsgAdapter, ErrorsNameTheField) {
    auto expect_field = [](const Settings& s, const std::string& field) {
        auto cb = ScatteringCallback::create(s, nullptr);
        ASSERT_FALSE(cb.ok()) << "expected an error naming " << field;
        EXPECT_EQ(cb.error().field, field);
        EXPECT_EQ(cb.error().message.rfind(
                      "aerial::osg_adapter::ScatteringCallback::create(): " + field + ": ", 0),
                  0u)
            << cb.error().message;
    };
    Settings s = test_settings(Backend::arb);
    s.model = aerial::Model::reference;
    expect_field(s, "model");
    s = test_settings(Backend::arb);
    s.display.tone = aerial::ToneCurve::exponential;
    expect_field(s, "display.tone");
    s = test_settings(Backend::cpu);
    s.display.exposure = 0.0f;
    expect_field(s, "display.exposure");
    s = test_settings(Backend::cpu);
    s.sun_dir = {0.0, 0.0, 2.0};
    expect_field(s, "sun_dir");
    s = test_settings(Backend::cpu);
    s.texture_units = 9;
    expect_field(s, "texture_units");
    s = test_settings(Backend::cpu);
    s.atmosphere.mie_g = 1.5;
    expect_field(s, "atmosphere.mie_g");
    EXPECT_EQ(aerial::osg_adapter::parse_backend("d3d").error().field, "backend");
    EXPECT_EQ(aerial::osg_adapter::validate(s)->message,
              "aerial::osg_adapter::validate(): atmosphere.mie_g: expected |g| < 1 (g > 0 scatters "
              "forwards), got 1.5");

    // Update-time errors: vertices that are not Vec3Array.
    auto cb = ScatteringCallback::create(test_settings(Backend::cpu), nullptr);
    ASSERT_TRUE(cb.ok());
    ::osg::ref_ptr<::osg::Geometry> g = new ::osg::Geometry;
    g->setVertexArray(new ::osg::Vec4Array(3));
    ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
    root->addChild(g.get());
    auto error = cb.value()->update_now(*root, glm::dvec3(0.0));
    ASSERT_TRUE(error);
    EXPECT_EQ(error->field, "vertices");

    auto arb = ScatteringCallback::create(test_settings(Backend::arb), nullptr);
    ASSERT_TRUE(arb.ok());
    // As an update callback without a camera: an error naming the camera, logged, no throw.
    ::osg::ref_ptr<::osg::Group> node = new ::osg::Group;
    node->addChild(make_grid(0.0f, 0.0f, 100.0f, 0.0f, 1, "grid"));
    node->setUpdateCallback(arb.value().get());
    osgUtil::UpdateVisitor update;
    node->accept(update);
    ASSERT_TRUE(arb.value()->last_error());
    EXPECT_EQ(arb.value()->last_error()->field, "camera");
}

/// One OSG frame into the EGL context; returns the GL state after it and the pixels.
struct FrameResult {
    aerial::gl::StateSnapshot state;
    std::vector<std::uint8_t> pixels;
};

/// Embeds `viewer` in the current 96 x 64 EGL context (its framebuffer) with the tests' camera:
/// 60 degrees, near 10, far 50 km, looking north from 3 km south at 500 m.
::osg::Camera* embed_viewer(osgViewer::Viewer& viewer, const aerial::gl::Api& api) {
    viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);
    auto window = viewer.setUpViewerAsEmbeddedInWindow(0, 0, 96, 64);
    GLint fbo = 0;
    api.GetIntegerv(GL_FRAMEBUFFER_BINDING, &fbo);
    window->setDefaultFboId(GLuint(fbo));
    ::osg::Camera* camera = viewer.getCamera();
    camera->setComputeNearFarMode(::osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    camera->setProjectionMatrixAsPerspective(60.0, 1.5, 10.0, 50000.0);
    camera->setViewMatrixAsLookAt({0, -3000, 500}, {0, 5000, 0}, {0, 0, 1});
    camera->setClearColor({0.2f, 0.3f, 0.5f, 1.0f});
    return camera;
}

TEST(OsgAdapter, AFrameWithTheAdapterLeavesTheGlStateAsOneWithout) {
    auto ctx = aerial::headless::Context::create({aerial::headless::Platform::egl, 96, 64});
    ASSERT_TRUE(ctx.ok()) << ctx.error().message;
    const auto& api = ctx->api();
    for (Backend backend : {Backend::cpu, Backend::arb}) {
        SCOPED_TRACE(aerial::osg_adapter::backend_name(backend));
        osgViewer::Viewer viewer;
        ::osg::Camera* camera = embed_viewer(viewer, api);

        // The hazy grid on the left with the adapter, a plain one on the right drawn after it.
        ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
        ::osg::ref_ptr<::osg::Group> aerial_group = new ::osg::Group;
        aerial_group->addChild(make_grid(-9000.0f, 0.0f, 8000.0f, 0.0f, 6, "hazy"));
        aerial_group->getOrCreateStateSet()->setRenderBinDetails(1, "RenderBin");
        auto plain = make_grid(1000.0f, 0.0f, 8000.0f, 0.0f, 6, "plain");
        plain->setUseDisplayList(false);  // arrays, as the adapter's Geometry
        plain->setUseVertexBufferObjects(true);
        auto* white = new ::osg::Vec4Array(1);
        (*white)[0].set(1.0f, 1.0f, 1.0f, 1.0f);
        plain->setColorArray(white, ::osg::Array::BIND_OVERALL);
        plain->getOrCreateStateSet()->setMode(GL_LIGHTING, ::osg::StateAttribute::OFF);
        plain->getOrCreateStateSet()->setRenderBinDetails(2, "RenderBin");
        root->addChild(aerial_group.get());
        root->addChild(plain.get());
        Settings s = test_settings(backend);
        auto cb = ScatteringCallback::create(s, camera);
        ASSERT_TRUE(cb.ok()) << cb.error().message;
        aerial_group->setUpdateCallback(cb.value().get());
        viewer.setSceneData(root.get());
        viewer.realize();

        auto frame = [&]() {
            viewer.frame();
            api.Finish();
            return FrameResult{aerial::gl::capture_state(api), ctx->read_rgba8()};
        };
        const FrameResult with = frame();
        ASSERT_FALSE(cb.value()->last_error()) << cb.value()->last_error()->message;
        EXPECT_GT(cb.value()->last_report().vertices, 0u);
        frame();  // the second frame with the adapter, after OSG's lazy state settled
        const FrameResult with2 = frame();
        // The baseline: the same Geometry with the same colour arrays (the adapter made them),
        // drawn without the adapter's callback and StateSet.
        aerial_group->setUpdateCallback(nullptr);
        aerial_group->setStateSet(nullptr);
        aerial_group->getOrCreateStateSet()->setRenderBinDetails(1, "RenderBin");
        frame();
        const FrameResult without = frame();

        for (const auto& d : aerial::gl::state_differences(without.state, with2.state)) {
            ADD_FAILURE() << "after a frame with the adapter, against one without: " << d;
        }
        for (const auto& d : aerial::gl::state_differences(with.state, with2.state)) {
            ADD_FAILURE() << "between two frames with the adapter: " << d;
        }
        // The plain grid (right half) looks the same with and without the adapter's node;
        // the adapter's grid (left half) is drawn.
        int left_changed = 0, right_changed = 0;
        for (int y = 0; y < 64; ++y) {
            for (int x = 0; x < 96; ++x) {
                const std::size_t p = (std::size_t(y) * 96 + std::size_t(x)) * 4;
                bool differ = false;
                for (int c = 0; c < 3; ++c)
                    differ = differ || with.pixels[p + c] != without.pixels[p + c];
                (x < 48 ? left_changed : right_changed) += differ ? 1 : 0;
                for (int c = 0; c < 3; ++c) {
                    ASSERT_EQ(with.pixels[p + c], with2.pixels[p + c])
                        << "pixel " << x << "," << y << " of two frames with the adapter";
                }
            }
        }
        EXPECT_EQ(right_changed, 0) << "the adapter's state leaked into the plain grid";
        EXPECT_GT(left_changed, 100) << "the adapter's StateSet changed nothing on its grid";
    }
}

/// One frame of a grid below a rotating and moving MatrixTransform, with the adapter on
/// `backend` (the height model; the arb program at the driver's native limits).
std::vector<std::uint8_t> transformed_frame(const aerial::headless::Context& ctx, Backend backend,
                                            const ::osg::Matrixd& m) {
    const auto& api = ctx.api();
    osgViewer::Viewer viewer;
    ::osg::Camera* camera = embed_viewer(viewer, api);
    ::osg::ref_ptr<::osg::Group> root = new ::osg::Group;
    ::osg::ref_ptr<::osg::MatrixTransform> xf = new ::osg::MatrixTransform;
    xf->setMatrix(m);
    auto grid = make_grid(-4000.0f, -4000.0f, 8000.0f, 0.0f, 12, "moved");
    xf->addChild(grid.get());
    root->addChild(xf.get());
    Settings s = test_settings(backend);
    s.model = aerial::Model::height;
    s.arb_limits = aerial::gl::native_arb_limits(api);
    auto cb = ScatteringCallback::create(s, camera);
    EXPECT_TRUE(cb.ok()) << cb.error().message;
    if (!cb.ok()) return {};
    root->setUpdateCallback(cb.value().get());
    viewer.setSceneData(root.get());
    viewer.realize();
    viewer.frame();  // the camera's view matrix reaches the update one frame late
    viewer.frame();
    api.Finish();
    EXPECT_FALSE(cb.value()->last_error()) << cb.value()->last_error()->message;
    if (backend == Backend::arb) {
        // Below a transform the Geometry has its own program with the transform's rows.
        const ::osg::StateSet* state = grid->getStateSet();
        EXPECT_TRUE(state && state->getAttribute(::osg::StateAttribute::VERTEXPROGRAM))
            << "no program of its own on the transformed Geometry";
    }
    return ctx.read_rgba8();
}

TEST(OsgAdapter, ArbBackendDrawsGeometriesBelowTransformsAsTheCpuBackendDoes) {
    auto ctx = aerial::headless::Context::create({aerial::headless::Platform::egl, 96, 64});
    ASSERT_TRUE(ctx.ok()) << ctx.error().message;
    const ::osg::Matrixd m = ::osg::Matrixd::rotate(0.5, ::osg::Vec3d(0, 0, 1)) *
                             ::osg::Matrixd::translate(1500.0, 9000.0, 120.0);
    const auto cpu = transformed_frame(*ctx, Backend::cpu, m);
    const auto arb = transformed_frame(*ctx, Backend::arb, m);
    ASSERT_EQ(cpu.size(), arb.size());
    int worst = 0, drawn = 0;
    for (std::size_t p = 0; p < cpu.size(); p += 4) {
        const bool background = cpu[p] == 51 && cpu[p + 1] == 77 && cpu[p + 2] == 128;
        drawn += background ? 0 : 1;
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(int(cpu[p + c]) - int(arb[p + c])));
    }
    std::printf("osg adapter below a transform, arb (full) vs cpu: max %d LSB, %d pixels drawn\n",
                worst, drawn);
    EXPECT_GT(drawn, 500) << "the transformed grid is not in view";
    EXPECT_LE(worst, 2);
}

}  // namespace
