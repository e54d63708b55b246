// The renderer's frame plan without a GL context: what each node gets (skipped, cached, which
// model) and the inputs it rejects.
#include <memory>
#include <utility>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"
#include "frame_plan.hpp"

namespace {

/// The renderer's memo of validated meshes, shared by the tests (each has its own meshes).
aerial::scene::detail::ValidatedMeshes validated_;

using aerial::Model;
using aerial::scene::Backend;
using aerial::scene::Method;
using aerial::scene::detail::FrameInputs;
using aerial::scene::detail::NodeState;

/// A square of `side` engine units at height `z`, centred `distance` ahead (+y) of the origin (the
/// default camera stands 100 units above it).
std::shared_ptr<aerial::scene::MeshData> square(double distance, double side, float z = 0.0f) {
    auto mesh = std::make_shared<aerial::scene::MeshData>();
    const float y0 = float(distance - side / 2), y1 = float(distance + side / 2);
    const float x0 = float(-side / 2), x1 = float(side / 2);
    mesh->positions = {x0, y0, z, x1, y0, z, x1, y1, z, x0, y1, z};
    mesh->normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    mesh->indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

aerial::scene::FrameSettings settings_for(Model model, bool policy, double target_lsb) {
    aerial::scene::FrameSettings s;
    s.sun_dir = glm::normalize(glm::dvec3(0.3, 0.5, 0.4));
    s.display.exposure = 8.0f;
    s.model = model;
    s.policy = policy;
    s.error_target_lsb = target_lsb;
    s.ambient = glm::vec3(0.02f);
    return s;
}

/// Prepares the frame and plans one node as the renderer does (geometry first).
struct Planner {
    explicit Planner(aerial::scene::FrameSettings s, aerial::scene::Camera c = {})
        : camera(c), settings(std::move(s)) {}

    aerial::scene::Camera camera;
    aerial::scene::FrameSettings settings;
    Backend backend = Backend::cpu;
    NodeState state;

    aerial::scene::detail::NodePlan plan(const aerial::scene::Node& node) {
        auto inputs = aerial::scene::detail::prepare_frame_inputs(node, camera, settings, backend,
                                                                  validated_);
        EXPECT_TRUE(inputs.ok()) << (inputs.ok() ? "" : inputs.error().message);
        FrameInputs frame = std::move(inputs).value();
        frame.ambient = settings.ambient;
        aerial::scene::detail::update_geometry(state, node, glm::dmat4(1.0));
        const auto plan = aerial::scene::detail::plan_node(frame, state, node);
        if (backend == Backend::cpu && plan.method != Method::skipped) state.has_colours = true;
        return plan;
    }
};

TEST(FramePlan, WithoutThePolicyEveryNodeGetsTheFramesModel) {
    for (Model model : {Model::hoffman_preetham, Model::height, Model::reference}) {
        Planner p(settings_for(model, false, 2.0));
        const auto node = aerial::scene::make_mesh("near", square(5.0, 1.0));
        for (int frame = 0; frame < 2; ++frame) {
            const auto plan = p.plan(*node);
            EXPECT_EQ(plan.model, model);
            EXPECT_EQ(plan.method, aerial::scene::detail::method_of(model)) << "frame " << frame;
        }
    }
}

TEST(FramePlan, NegligibleScatteringIsSkippedAndDistantScatteringIsNot) {
    Planner p(settings_for(Model::height, true, 2.0));
    const auto near = aerial::scene::make_mesh("near", square(2.0, 0.5, 100.0f));
    EXPECT_EQ(p.plan(*near).method, Method::skipped);
    Planner q(settings_for(Model::height, true, 2.0));
    const auto far = aerial::scene::make_mesh("far", square(20000.0, 2000.0));
    EXPECT_NE(q.plan(*far).method, Method::skipped);
}

TEST(FramePlan, ColoursAreReusedUntilTheEyeMovesTooFar) {
    Planner p(settings_for(Model::height, true, 0.0));
    const auto node = aerial::scene::make_terrain_tile("tile", square(8000.0, 4000.0));
    EXPECT_EQ(p.plan(*node).method, Method::height);
    EXPECT_EQ(p.plan(*node).method, Method::cached);
    p.camera.eye += glm::dvec3(0.001, 0.0, 0.0);
    p.camera.target += glm::dvec3(0.001, 0.0, 0.0);
    EXPECT_EQ(p.plan(*node).method, Method::cached);
    p.camera.eye += glm::dvec3(0.0, 0.0, 3000.0);
    p.camera.target += glm::dvec3(0.0, 0.0, 3000.0);
    EXPECT_EQ(p.plan(*node).method, Method::height);
}

TEST(FramePlan, TheCheaperModelIsTakenOnlyWithinTheTarget) {
    const auto node = aerial::scene::make_mesh("far", square(20000.0, 2000.0));
    Planner strict(settings_for(Model::height, true, 0.0));
    strict.camera.eye = glm::dvec3(0.0, 0.0, 2000.0);
    strict.camera.target = glm::dvec3(0.0, 1000.0, 2000.0);
    EXPECT_EQ(strict.plan(*node).model, Model::height);
    Planner loose(settings_for(Model::height, true, 255.0), strict.camera);
    EXPECT_EQ(loose.plan(*node).model, Model::hoffman_preetham);
    EXPECT_EQ(loose.state.model, Model::hoffman_preetham);
}

TEST(FramePlan, InputsTheBackendCannotDrawAreErrorsNamingTheField) {
    const auto node = aerial::scene::make_mesh("m", square(100.0, 10.0));
    const aerial::scene::Camera camera;
    auto reference = settings_for(Model::reference, true, 2.0);
    auto e = aerial::scene::detail::prepare_frame_inputs(*node, camera, reference, Backend::arb,
                                                         validated_);
    ASSERT_FALSE(e.ok());
    EXPECT_EQ(e.error().field, "model");
    auto dark = settings_for(Model::height, true, 2.0);
    dark.display.exposure = 0.0f;
    e = aerial::scene::detail::prepare_frame_inputs(*node, camera, dark, Backend::cpu, validated_);
    ASSERT_FALSE(e.ok());
    EXPECT_EQ(e.error().field, "display.exposure");
    auto negative = settings_for(Model::height, true, -1.0);
    e = aerial::scene::detail::prepare_frame_inputs(*node, camera, negative, Backend::cpu,
                                                    validated_);
    ASSERT_FALSE(e.ok());
    EXPECT_EQ(e.error().field, "error_target_lsb");
}

}  // namespace

namespace {

// A mesh is checked when first seen and again when any of its arrays moved or changed size: a
// valid mesh grown by a NaN vertex is caught, the unchanged one is not checked again.
TEST(ValidatedMeshes, AMeshIsCheckedOnceAndAgainWhenItsArraysChange) {
    aerial::scene::detail::ValidatedMeshes memo;
    auto mesh = square(500.0, 100.0);
    auto node = aerial::scene::make_mesh("square", mesh);
    EXPECT_FALSE(aerial::scene::detail::validate(*node, memo));
    EXPECT_TRUE(memo.contains(*mesh));
    mesh->positions.insert(mesh->positions.end(), {0.0f, 0.0f, std::nanf("")});
    mesh->normals.insert(mesh->normals.end(), {0.0f, 0.0f, 1.0f});
    EXPECT_FALSE(memo.contains(*mesh));
    const auto e = aerial::scene::detail::validate(*node, memo);
    ASSERT_TRUE(e);
    EXPECT_NE(e->message.find("positions"), std::string::npos) << e->message;
    EXPECT_FALSE(memo.contains(*mesh)) << "an invalid mesh is checked every frame";
}

}  // namespace
