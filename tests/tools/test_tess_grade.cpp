// The GL grading of aerial-tess (tools/tess/gl_grade.hpp): the image through the fixed-function
// path against the per-pixel reference.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"
#include "tess/gl_grade.hpp"

namespace {

struct Dome {
    aerial::mesh::DomeOptions dome;
    aerial::mesh::ColourOptions colour;
    aerial::Frame<float> frame;
    aerial::tess::GlGradeOptions options;
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

TEST(GlGrade, CoarseDomeShowsLargeErrorsAndAFineOneIsWithinAStep) {
    auto created = aerial::tess::GlGrader::create(48);
    ASSERT_TRUE(created.ok()) << created.error().message;
    aerial::tess::GlGrader& grader = created.value();
    const Dome d;
    const auto coarse =
        grader.grade(aerial::mesh::geodesic_dome(2, d.dome).value(), d.frame, d.colour, d.options);
    ASSERT_TRUE(coarse.ok()) << coarse.error().message;
    const auto fine =
        grader.grade(aerial::mesh::geodesic_dome(96, d.dome).value(), d.frame, d.colour, d.options);
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

TEST(GlGrade, ReportListsExactlyThePixelsOffByTheGivenStepsWithTheirSurfacePoints) {
    auto created = aerial::tess::GlGrader::create(32);
    ASSERT_TRUE(created.ok()) << created.error().message;
    Dome d;
    std::vector<aerial::tess::GlGradeOptions::Pixel> report;
    d.options.report = &report;
    d.options.report_lsb = 3;
    const auto graded = created.value().grade(aerial::mesh::geodesic_dome(2, d.dome).value(),
                                              d.frame, d.colour, d.options);
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

TEST(GlGrade, BadOptionsAreNamed) {
    EXPECT_EQ(aerial::tess::GlGrader::create(8).error().field, "face_pixels");
    auto created = aerial::tess::GlGrader::create(16);
    ASSERT_TRUE(created.ok());
    aerial::tess::GlGrader& grader = created.value();
    Dome d;
    const auto mesh = aerial::mesh::geodesic_dome(2, d.dome).value();
    d.options.near_m = 0.0;
    EXPECT_EQ(grader.grade(mesh, d.frame, d.colour, d.options).error().field, "near_m");
    d.options.near_m = 10.0;
    d.options.far_m = 5.0;
    EXPECT_EQ(grader.grade(mesh, d.frame, d.colour, d.options).error().field, "far_m");
    EXPECT_EQ(grader.grade(aerial::mesh::Mesh(), d.frame, d.colour, Dome().options).error().field,
              "mesh");
}

}  // namespace
