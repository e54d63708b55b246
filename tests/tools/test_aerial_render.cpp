// aerial-render end to end (docs/conventions.md, Interfaces): a small scene renders to a PNG of
// the requested size
// with the one-line report, the same every time; and every bad flag, file and scene field exits
// 2 with one stderr line naming it, before any context is created.
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/png.hpp"
#include "tool_runner.hpp"

namespace {

using aerial::test::RunResult;
using Json = nlohmann::json;

constexpr const char* kBinary = AERIAL_RENDER_PATH;
constexpr const char* kTool = "aerial-render";

/// A small valid scene: a flat checker ground and one box, earth, the 2002 model.
Json valid_scene() {
    return Json::parse(R"({
      "camera": {"eye": [0, -500, 60], "look_at": [0, 500, 0], "up": [0, 0, 1],
                 "fov_y_deg": 50, "near": 1, "far": 20000},
      "sun": {"elevation_deg": 40, "azimuth_deg": 20},
      "atmosphere": "hazy",
      "model": "hoffman-preetham",
      "display": {"exposure": 10, "tone": "clamp"},
      "meters_per_unit": 1,
      "background": [0.5, 0.6, 0.8],
      "texture": {"kind": "checker", "size": 16, "cells": 4, "colors": [[0.2, 0.4, 0.1],
                  [0.6, 0.6, 0.5]], "seed": 1},
      "terrain": {"center": [0, 2000], "size": 8000, "resolution": 8, "height_amplitude": 50,
                  "feature_size": 2000, "seed": 3, "texture_repeat": 200},
      "boxes": [{"center": [50, 300, 20], "size": [40, 40, 40], "subdivisions": 2}]
    })");
}

class AerialRender : public aerial::test::ToolTest {
  protected:
    RunResult run(const std::vector<std::string>& args) {
        return ToolTest::run(kBinary, args, "", {"LP_NUM_THREADS=1"});
    }

    std::string scene_file(const Json& scene, const std::string& name = "scene.json") {
        return file(name, scene.dump(2));
    }

    /// aerial-render on `scene` with `backend` into `out` (in the test's directory), plus
    /// `more` flags.
    RunResult render(const Json& scene, const std::string& backend,
                     std::vector<std::string> more = {}, const std::string& out = "out.png") {
        std::vector<std::string> args{"--scene", scene_file(scene), "--backend", backend,
                                      "--size",  "32x24",           "--out",     path(out)};
        args.insert(args.end(), more.begin(), more.end());
        return run(args);
    }

    /// The scene with one field (a JSON pointer) set to `value`, or removed when it is null.
    ::testing::AssertionResult rejects_field(const std::string& pointer, const Json& value,
                                             std::initializer_list<const char*> expected) {
        Json scene = valid_scene();
        const Json::json_pointer p(pointer);
        if (value.is_null()) {
            scene[p.parent_pointer()].erase(p.back());
        } else {
            scene[p] = value;
        }
        return aerial::test::rejected_naming(render(scene, "none"), kTool, expected);
    }
};

TEST_F(AerialRender, HelpExitsZeroAndMentionsEveryFlag) {
    const RunResult r = run({"--help"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    for (const char* flag : {"--scene", "--backend", "--gl", "--size", "--path", "--out"}) {
        EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
    }
}

TEST_F(AerialRender, WritesAnImageOfTheRequestedSizeAndOneReportLine) {
    for (const char* backend : {"none", "fog", "perpixel"}) {
        SCOPED_TRACE(backend);
        const RunResult r = render(valid_scene(), backend);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(r.err, "");
        EXPECT_EQ(
            r.out.rfind(std::string("backend=") + backend + " path=- gl=osmesa size=32x24 ms=", 0),
            0u)
            << r.out;
        EXPECT_NE(r.out.find(" renderer=\""), std::string::npos) << r.out;
        const auto image = aerial::tools::read_png(path("out.png"));
        ASSERT_TRUE(image.ok()) << image.error().message;
        EXPECT_EQ(image->width, 32);
        EXPECT_EQ(image->height, 24);
    }
}

TEST_F(AerialRender, ArbBackendNamesTheProgramItLoaded) {
    // The 2002 model's program, and for `height` the highest fidelity the driver takes (Mesa's
    // native limits take the full program).
    RunResult r = render(valid_scene(), "arb");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(" program=hoffman-preetham:22 renderer="), std::string::npos) << r.out;
    Json height = valid_scene();
    height["model"] = "height";
    r = render(height, "arb");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(" program=height:multiple-scattering:"), std::string::npos) << r.out;
    r = render(valid_scene(), "perpixel");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(" program=- renderer="), std::string::npos) << r.out;
}

TEST_F(AerialRender, TheSameSceneGivesTheSameImage) {
    ASSERT_EQ(render(valid_scene(), "perpixel", {}, "a.png").exit_code, 0);
    ASSERT_EQ(render(valid_scene(), "perpixel", {}, "b.png").exit_code, 0);
    const auto a = aerial::tools::read_png(path("a.png"));
    const auto b = aerial::tools::read_png(path("b.png"));
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->rgb, b->rgb);
}

TEST_F(AerialRender, SunElevationAndDirectionAreTheSameSun) {
    // elevation 90 deg is straight up whatever the azimuth.
    Json by_angle = valid_scene();
    by_angle["sun"] = {{"elevation_deg", 90}, {"azimuth_deg", 123}};
    Json by_direction = valid_scene();
    by_direction["sun"] = {{"direction", {0, 0, 2}}};
    ASSERT_EQ(render(by_angle, "perpixel", {}, "a.png").exit_code, 0);
    ASSERT_EQ(render(by_direction, "perpixel", {}, "b.png").exit_code, 0);
    const auto a = aerial::tools::read_png(path("a.png"));
    const auto b = aerial::tools::read_png(path("b.png"));
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(a->rgb, b->rgb);
}

// ---- bad flags --------------------------------------------------------------------------------

TEST_F(AerialRender, RejectsEachMissingRequiredFlag) {
    const std::string scene = scene_file(valid_scene());
    const std::string out = path("out.png");
    EXPECT_TRUE(aerial::test::rejected_naming(run({"--backend", "none", "--out", out}), kTool,
                                              {"--scene"}));
    EXPECT_TRUE(
        aerial::test::rejected_naming(run({"--scene", scene, "--out", out}), kTool, {"--backend"}));
    EXPECT_TRUE(aerial::test::rejected_naming(run({"--scene", scene, "--backend", "none"}), kTool,
                                              {"--out"}));
}

TEST_F(AerialRender, RejectsBadFlagValuesNamingTheFlag) {
    const std::vector<std::pair<std::vector<std::string>, const char*>> cases{
        {{"--backend", "raytrace"}, "--backend"},
        {{"--gl", "glx"}, "--gl"},
        {{"--size", "0x24"}, "--size"},
        {{"--size", "32"}, "--size"},
        {{"--size", "32x-4"}, "--size"},
        {{"--size", "9000x24"}, "--size"},
        {{"--size", "axb"}, "--size"},
        {{"--path", "fast"}, "--path"},
        {{"--frobnicate", "1"}, "--frobnicate"},
    };
    for (const auto& [flags, name] : cases) {
        SCOPED_TRACE(flags.front() + " " + flags.back());
        std::vector<std::string> args{
            "--scene", scene_file(valid_scene()), "--backend", "none", "--out", path("out.png")};
        // Later values of a flag replace earlier ones (CLI11), except the backend, given once.
        if (flags.front() == "--backend")
            args[3] = flags.back();
        else
            args.insert(args.end(), flags.begin(), flags.end());
        EXPECT_TRUE(aerial::test::rejected_naming(run(args), kTool, {name}));
    }
}

TEST_F(AerialRender, RejectsPathWithABackendOtherThanCpu) {
    EXPECT_TRUE(aerial::test::rejected_naming(render(valid_scene(), "fog", {"--path", "two-pass"}),
                                              kTool, {"--path", "fog"}));
}

TEST_F(AerialRender, RejectsTheArbBackendForAToneItCannotDo) {
    Json exponential = valid_scene();
    exponential["display"]["tone"] = "exponential";
    EXPECT_TRUE(
        aerial::test::rejected_naming(render(exponential, "arb"), kTool, {"--backend arb"}));
}

TEST_F(AerialRender, RejectsAnOutputThatCannotBeWritten) {
    const std::string blocker = file("blocker", "a file, not a directory\n");
    EXPECT_TRUE(
        aerial::test::rejected_naming(run({"--scene", scene_file(valid_scene()), "--backend",
                                           "none", "--out", blocker + "/out.png"}),
                                      kTool, {"--out"}));
}

// ---- bad scene files --------------------------------------------------------------------------

TEST_F(AerialRender, RejectsAMissingSceneFileNamingIt) {
    const std::string missing = path("nowhere/scene.json");
    EXPECT_TRUE(aerial::test::rejected_naming(
        run({"--scene", missing, "--backend", "none", "--out", path("out.png")}), kTool,
        {"--scene", missing.c_str()}));
}

TEST_F(AerialRender, RejectsMalformedJsonAndNonObjects) {
    for (const char* text : {"{\"camera\": ", "[1, 2, 3]", "42", ""}) {
        SCOPED_TRACE(text);
        const std::string scene = file("bad.json", text);
        EXPECT_TRUE(aerial::test::rejected_naming(
            run({"--scene", scene, "--backend", "none", "--out", path("out.png")}), kTool,
            {"--scene", scene.c_str()}));
    }
}

TEST_F(AerialRender, RejectsUnknownFieldsAtEveryLevelNamingThem) {
    EXPECT_TRUE(rejects_field("/skybox", true, {"skybox", "unknown field"}));
    EXPECT_TRUE(rejects_field("/camera/fovy", 40, {"camera.fovy", "unknown field"}));
    EXPECT_TRUE(rejects_field("/sun/zenith_deg", 40, {"sun.zenith_deg"}));
    EXPECT_TRUE(rejects_field("/display/gamma", 2.2, {"display.gamma"}));
    EXPECT_TRUE(rejects_field("/texture/filter", "nearest", {"texture.filter"}));
    EXPECT_TRUE(rejects_field("/terrain/lacunarity", 2, {"terrain.lacunarity"}));
    EXPECT_TRUE(rejects_field("/boxes/0/color", Json::array({1, 0, 0}), {"boxes[0].color"}));
    EXPECT_TRUE(rejects_field("/atmosphere", Json{{"ozone", 1e-6}}, {"atmosphere", "ozone"}));
}

TEST_F(AerialRender, RejectsBadCameraFieldsNamingThem) {
    EXPECT_TRUE(rejects_field("/camera", nullptr, {"camera", "required"}));
    EXPECT_TRUE(rejects_field("/camera", 5, {"camera", "object"}));
    EXPECT_TRUE(rejects_field("/camera/eye", Json::array({0, 1}), {"camera.eye"}));
    EXPECT_TRUE(rejects_field("/camera/eye/2", "high", {"camera.eye[2]"}));
    EXPECT_TRUE(rejects_field("/camera/look_at", nullptr, {"camera.look_at", "camera.direction"}));
    EXPECT_TRUE(rejects_field("/camera/direction", Json::array({0, 1, 0}),
                              {"camera.look_at", "camera.direction"}));
    EXPECT_TRUE(rejects_field("/camera/look_at", Json::array({0, -500, 60}), {"camera.look_at"}));
    EXPECT_TRUE(rejects_field("/camera/up", Json::array({0, 0, 0}), {"camera.up"}));
    EXPECT_TRUE(rejects_field("/camera/fov_y_deg", 0, {"camera.fov_y_deg"}));
    EXPECT_TRUE(rejects_field("/camera/fov_y_deg", 180, {"camera.fov_y_deg"}));
    EXPECT_TRUE(rejects_field("/camera/fov_y_deg", "wide", {"camera.fov_y_deg"}));
    EXPECT_TRUE(rejects_field("/camera/near", -1, {"camera.near"}));
    EXPECT_TRUE(rejects_field("/camera/far", 0.5, {"camera.far"}));
}

TEST_F(AerialRender, RejectsBadSunFieldsNamingThem) {
    EXPECT_TRUE(rejects_field("/sun", nullptr, {"sun", "required"}));
    EXPECT_TRUE(rejects_field("/sun/azimuth_deg", nullptr, {"sun.azimuth_deg"}));
    EXPECT_TRUE(rejects_field("/sun/elevation_deg", 91, {"sun.elevation_deg"}));
    EXPECT_TRUE(rejects_field("/sun/direction", Json::array({0, 0, 1}), {"sun.direction"}));
    Json scene = valid_scene();
    scene["sun"] = {{"direction", {0, 0, 0}}};
    EXPECT_TRUE(aerial::test::rejected_naming(render(scene, "none"), kTool, {"sun.direction"}));
}

TEST_F(AerialRender, RejectsBadAtmosphereModelAndDisplayNamingThem) {
    EXPECT_TRUE(rejects_field("/atmosphere", "venus", {"atmosphere", "venus"}));
    EXPECT_TRUE(rejects_field("/atmosphere", Json{{"mie_g", 2}}, {"atmosphere.mie_g"}));
    EXPECT_TRUE(rejects_field("/atmosphere", 3, {"atmosphere"}));
    EXPECT_TRUE(rejects_field("/model", "fast", {"model", "fast"}));
    EXPECT_TRUE(rejects_field("/model", "reference", {"model", "reference"}));
    EXPECT_TRUE(rejects_field("/display/exposure", 0, {"display.exposure"}));
    EXPECT_TRUE(rejects_field("/display/tone", "filmic", {"display.tone"}));
    EXPECT_TRUE(rejects_field("/meters_per_unit", 0, {"meters_per_unit"}));
    EXPECT_TRUE(rejects_field("/background", Json::array({2, 0, 0}), {"background[0]"}));
}

TEST_F(AerialRender, RejectsBadGeometryAndTextureNamingThem) {
    EXPECT_TRUE(rejects_field("/texture/kind", "marble", {"texture.kind"}));
    EXPECT_TRUE(rejects_field("/texture/size", 24, {"texture.size", "power of two"}));
    EXPECT_TRUE(rejects_field("/texture/cells", 3, {"texture.cells"}));
    EXPECT_TRUE(rejects_field("/texture/colors", Json::array({{0, 0, 0}}), {"texture.colors"}));
    EXPECT_TRUE(rejects_field("/texture/seed", -1, {"texture.seed"}));
    EXPECT_TRUE(rejects_field("/terrain/resolution", 0, {"terrain.resolution"}));
    EXPECT_TRUE(rejects_field("/terrain/octaves", 13, {"terrain.octaves", "[1, 12]"}));
    EXPECT_TRUE(rejects_field("/texture/kind", 3, {"texture.kind", "expected a string"}));
    EXPECT_TRUE(rejects_field("/terrain/resolution", 2.5, {"terrain.resolution"}));
    EXPECT_TRUE(rejects_field("/terrain/size", -10, {"terrain.size"}));
    EXPECT_TRUE(rejects_field("/terrain/height_amplitude", -1, {"terrain.height_amplitude"}));
    EXPECT_TRUE(rejects_field("/terrain/texture_repeat", 0, {"terrain.texture_repeat"}));
    EXPECT_TRUE(rejects_field("/boxes", 1, {"boxes"}));
    EXPECT_TRUE(rejects_field("/boxes/0/size", Json::array({1, -1, 1}), {"boxes[0].size"}));
    EXPECT_TRUE(rejects_field("/boxes/0/center", nullptr, {"boxes[0].center"}));
    EXPECT_TRUE(rejects_field("/boxes/0/subdivisions", 0, {"boxes[0].subdivisions"}));
    Json empty = valid_scene();
    empty.erase("terrain");
    empty.erase("boxes");
    EXPECT_TRUE(aerial::test::rejected_naming(render(empty, "none"), kTool, {"terrain", "boxes"}));
}

}  // namespace
