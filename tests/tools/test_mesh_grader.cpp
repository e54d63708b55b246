// The GL grading of aerial-tess (aerial/validation/mesh_grader.hpp): the image through the
// fixed-function path against the per-pixel reference.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/adaptive_scene.hpp"
#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"
#include "aerial/validation/mesh_grader.hpp"
#include "aerial/validation/tess_scenes.hpp"

namespace {

struct Dome : aerial::validation::GradeSetting {
    aerial::mesh::DomeOptions dome;
    Dome() {
        dome.centre = {0, 0, 2};
        aerial::View view;
        view.eye = dome.centre;
        view.sun_dir = glm::normalize(glm::dvec3(1, 0, 0.2));
        frame = aerial::prepare_frame<float>(aerial::atmosphere_preset("earth").value(), view,
                                             aerial::Model::height)
                    .value();
        colour.texel = glm::vec3(0.0f);
        colour.display.exposure = 12.0f;
        colour.display.tone = aerial::ToneCurve::exponential;
        options.dome = dome;
        options.near_m = 100.0;
        options.far_m = 4.0 * dome.radius_m;
    }
};

TEST(MeshGrader, CoarseDomeShowsLargeErrorsAndAFineOneIsWithinAStep) {
    auto created = aerial::validation::MeshGrader::create(48);
    ASSERT_TRUE(created.ok()) << created.error().message;
    aerial::validation::MeshGrader& grader = created.value();
    const Dome d;
    const auto coarse = grader.grade(d, aerial::mesh::geodesic_dome(2, d.dome).value());
    ASSERT_TRUE(coarse.ok()) << coarse.error().message;
    const auto fine = grader.grade(d, aerial::mesh::geodesic_dome(96, d.dome).value());
    ASSERT_TRUE(fine.ok()) << fine.error().message;
    // The upper hemisphere covers half of the cube's pixels.
    const double half = 3.0 * 48 * 48;
    EXPECT_NEAR(double(coarse->count), half, 0.05 * half);
    EXPECT_EQ(coarse->count, fine->count);
    EXPECT_GE(coarse->max_lsb, 8) << "a 13-vertex dome should show the interpolation error";
    EXPECT_GT(coarse->rmse_lsb, 2.0 * fine->rmse_lsb);
    EXPECT_LE(fine->max_lsb, 1) << "rmse " << fine->rmse_lsb;
    EXPECT_LE(fine->p99_lsb, fine->max_lsb);
}

TEST(MeshGrader, ReportListsExactlyThePixelsOffByTheGivenStepsWithTheirSurfacePoints) {
    auto created = aerial::validation::MeshGrader::create(32);
    ASSERT_TRUE(created.ok()) << created.error().message;
    Dome d;
    std::vector<aerial::validation::MeshGradeOptions::Pixel> report;
    d.options.report = &report;
    d.options.report_lsb = 3;
    const auto graded = created.value().grade(d, aerial::mesh::geodesic_dome(2, d.dome).value());
    ASSERT_TRUE(graded.ok()) << graded.error().message;
    // over2 counts the pixels off by more than 2 steps: those the report lists.
    ASSERT_GT(graded->over2, 0.0) << "a 13-vertex dome should have pixels off by 3 steps";
    EXPECT_EQ(double(report.size()), std::round(graded->over2 * double(graded->count)));
    for (const auto& pixel : report) {
        int lsb = 0;
        for (int c = 0; c < 3; ++c)
            lsb = std::max(lsb, std::abs(int(pixel.drawn[c]) - int(pixel.reference[c])));
        EXPECT_GE(lsb, 3);
        EXPECT_NEAR(glm::length(pixel.point - d.dome.centre), d.dome.radius_m,
                    1e-5 * d.dome.radius_m)
            << "the reference's point lies on the dome's sphere";
    }
}

TEST(MeshGrader, BadOptionsAreNamed) {
    EXPECT_EQ(aerial::validation::MeshGrader::create(8).error().field, "face_pixels");
    auto created = aerial::validation::MeshGrader::create(16);
    ASSERT_TRUE(created.ok());
    aerial::validation::MeshGrader& grader = created.value();
    Dome d;
    const auto mesh = aerial::mesh::geodesic_dome(2, d.dome).value();
    d.options.near_m = 0.0;
    EXPECT_EQ(grader.grade(d, mesh).error().message,
              "aerial::validation::MeshGrader::grade(): near_m: expected a value > 0, got 0");
    d.options.near_m = 10.0;
    d.options.far_m = 5.0;
    EXPECT_EQ(grader.grade(d, mesh).error().field, "far_m");
    EXPECT_EQ(grader.grade(Dome(), aerial::mesh::Mesh()).error().field, "mesh");
    aerial::scene::MeshData bad;
    bad.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bad.indices = {0, 1, 3};
    EXPECT_EQ(grader.grade(Dome(), bad).error().message,
              "aerial::validation::MeshGrader::grade(): indices[2]: expected a vertex index below "
              "3, got 3");
}

// A mesh handed as triangles (what scene::load_mesh_file reads) grades as the mesh itself.
TEST(MeshGrader, TrianglesGradeAsTheMeshTheyDescribe) {
    auto created = aerial::validation::MeshGrader::create(32);
    ASSERT_TRUE(created.ok()) << created.error().message;
    const Dome d;
    const auto mesh = aerial::mesh::geodesic_dome(6, d.dome).value();
    const auto as_mesh = created.value().grade(d, mesh);
    const auto as_data = created.value().grade(d, aerial::scene::mesh_data_from(mesh));
    ASSERT_TRUE(as_mesh.ok() && as_data.ok());
    EXPECT_EQ(as_mesh->max_lsb, as_data->max_lsb);
    EXPECT_EQ(as_mesh->count, as_data->count);
    EXPECT_EQ(as_mesh->rmse_lsb, as_data->rmse_lsb);
    EXPECT_EQ(as_mesh->over1, as_data->over1);
}

TEST(TessScenes, FileRoundTripsAndBuildsTheScenes) {
    const auto builtin = aerial::validation::builtin_tess_scenes(false);
    ASSERT_EQ(builtin.size(), 14u);
    const auto read =
        aerial::validation::read_tess_scenes(aerial::validation::write_tess_scenes(builtin));
    ASSERT_TRUE(read.ok()) << read.error().message;
    ASSERT_EQ(read->size(), builtin.size());
    for (std::size_t i = 0; i < builtin.size(); ++i) {
        EXPECT_EQ((*read)[i].kind, builtin[i].kind);
        EXPECT_EQ((*read)[i].sun_elevation_deg, builtin[i].sun_elevation_deg);
        EXPECT_EQ((*read)[i].mie_g, builtin[i].mie_g);
    }
    const auto dome = aerial::validation::make_tess_scene(builtin[5]);  // sun 10, g 0.9
    ASSERT_TRUE(dome.ok()) << dome.error().message;
    EXPECT_EQ(dome->name, "dome-sun10-g0.90");
    EXPECT_TRUE(dome->dome);
    EXPECT_FLOAT_EQ(dome->setting.frame.mie_g, 0.9f);
    EXPECT_NEAR(dome->setting.frame.view.sun_dir.z, std::sin(10.0 * 3.14159265358979 / 180.0),
                1e-12);
    aerial::scene::MeshData on_sphere;
    on_sphere.positions = {80000, 0, 2, 0, 80000, 2, 0, 0, 80002};
    on_sphere.indices = {0, 1, 2};
    EXPECT_TRUE(aerial::validation::tess_scene_fits(*dome, on_sphere));
    const auto terrain = aerial::validation::make_tess_scene(builtin.back());
    ASSERT_TRUE(terrain.ok());
    EXPECT_EQ(terrain->name, "terrain-eye3000-sun60");
    EXPECT_FALSE(aerial::validation::tess_scene_fits(*terrain, on_sphere));
}

// A path moves the sun and the eye linearly and keeps the first frame's exposure.
TEST(TessScenes, PathFramesMoveTheSunAndTheEyeAndKeepTheExposure) {
    const auto paths = aerial::validation::builtin_tess_paths();
    ASSERT_EQ(paths.size(), 2u);
    const auto read =
        aerial::validation::read_tess_scenes(aerial::validation::write_tess_scenes(paths));
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ((*read)[1].path.frames, 48);
    EXPECT_EQ((*read)[1].path.eye_move_m[0], 1200.0);
    const auto& dome = paths[0];
    const auto first = aerial::validation::make_tess_scene(dome, 0);
    const auto last = aerial::validation::make_tess_scene(dome, 47);
    ASSERT_TRUE(first.ok() && last.ok());
    EXPECT_NEAR(std::asin(last->setting.frame.view.sun_dir.z) * 180.0 / 3.14159265358979, 2.0,
                1e-9);
    EXPECT_EQ(first->setting.colour.display.exposure, last->setting.colour.display.exposure);
    EXPECT_EQ(first->name, last->name);
    const auto& terrain = paths[1];
    const auto flown = aerial::validation::make_tess_scene(terrain, 47);
    ASSERT_TRUE(flown.ok());
    const glm::dvec3 eye = flown->setting.frame.view.eye;
    EXPECT_NEAR(eye.x, 1200.0, 1e-9);
    EXPECT_NEAR(eye.z - flown->field.height_m(eye.x, eye.y), 300.0, 1e-9);
    EXPECT_EQ(aerial::validation::make_tess_scene(terrain, 48).error().message,
              "aerial::validation::make_tess_scene(): frame: expected 0 .. 47, got 48");
}

TEST(TessScenes, BadScenesAreErrorsNamingTheField) {
    const auto bad = [](const std::string& text) {
        const auto read = aerial::validation::read_tess_scenes(text);
        return read ? std::string("no error") : read.error().message;
    };
    EXPECT_EQ(bad(R"({"scenes": [{"kind": "dome", "mie_g": 1.5}]})"),
              "aerial::validation::read_tess_scenes(): scenes[0].mie_g: expected a number in [0, "
              "0.999], got 1.5");
    EXPECT_EQ(bad(R"({"scenes": [{"kind": "cube"}]})"),
              "aerial::validation::read_tess_scenes(): scenes[0].kind: expected \"dome\" or "
              "\"terrain\", got \"cube\"");
    EXPECT_EQ(bad(R"({"scenes": [{"kind": "terrain", "sun": 3}]})"),
              "aerial::validation::read_tess_scenes(): scenes[0].sun: unknown field (known: kind, "
              "name, preset, sun_elevation_deg, mie_g, eye_m, path)");
    EXPECT_EQ(bad(R"({"scenes": [{"kind": "dome", "path": {"frames": 1}}]})"),
              "aerial::validation::read_tess_scenes(): scenes[0].path.frames: expected 0 (no "
              "path) or 2 .. 10000, got 1");
    EXPECT_EQ(bad(R"({"scenes": [{"kind": "dome", "path": {"frames": 4, "eye_move_m": [1, 0]}}]})"),
              "aerial::validation::read_tess_scenes(): scenes[0].path.eye_move_m: a dome moves "
              "with its eye: only terrain paths move it");
    EXPECT_EQ(bad(R"({"scenes": [{"kind": "terrain", "path": {"frames": 4, "speed": 3}}]})"),
              "aerial::validation::read_tess_scenes(): scenes[0].path.speed: unknown field "
              "(known: frames, sun_elevation_end_deg, sun_azimuth_end_deg, eye_move_m)");
    EXPECT_EQ(bad(R"({"scenes": [{"kind": "terrain", "preset": "venus"}]})"),
              "aerial::validation::read_tess_scenes(): scenes[0].preset: expected a preset name, "
              "got 'venus'");
    EXPECT_EQ(bad("[1"), "aerial::validation::read_tess_scenes(): scenes: not JSON");
    aerial::validation::TessSceneSpec spec;
    spec.kind = "terrain";
    spec.eye_m = std::nan("");
    EXPECT_EQ(aerial::validation::make_tess_scene(spec).error().message,
              "aerial::validation::make_tess_scene(): eye_m: expected a number in [0.5, 20000], "
              "got nan");
}

}  // namespace
