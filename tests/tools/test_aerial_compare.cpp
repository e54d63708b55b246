// aerial-compare end to end (docs/conventions.md, Interfaces): the figures of its one line on
// images with known
// differences, the diff image, and for every kind of bad input exit status 2 with one stderr line
// naming the culprit.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/png.hpp"
#include "tool_runner.hpp"

namespace {

using aerial::test::RunResult;
using aerial::tools::Rgb8Image;

constexpr const char* kBinary = AERIAL_COMPARE_PATH;
constexpr const char* kTool = "aerial-compare";

Rgb8Image grey_image(int width, int height, std::uint8_t value) {
    return Rgb8Image{
        width, height,
        std::vector<std::uint8_t>(std::size_t(width) * std::size_t(height) * 3, value)};
}

class AerialCompare : public aerial::test::ToolTest {
  protected:
    RunResult run(const std::vector<std::string>& args) { return ToolTest::run(kBinary, args); }

    std::string png(const std::string& name, const Rgb8Image& image) {
        const std::string p = path(name);
        EXPECT_EQ(aerial::tools::write_png(p, image), std::nullopt);
        return p;
    }
};

TEST_F(AerialCompare, HelpExitsZeroAndMentionsTheFlagAndTheFigures) {
    const RunResult r = run({"--help"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    for (const char* piece :
         {"--diff", "max_lsb", "p99_lsb", "rmse_lsb", "over1", "over2", "de2000_mean"}) {
        EXPECT_NE(r.out.find(piece), std::string::npos) << piece;
    }
}

TEST_F(AerialCompare, IdenticalImagesGiveZeroEverywhere) {
    const std::string a = png("a.png", grey_image(8, 6, 120));
    const RunResult r = run({a, a});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(r.out,
              "max_lsb=0 p99_lsb=0 rmse_lsb=0.0000 over1=0.000000 over2=0.000000 "
              "de2000_mean=0.0000\n");
}

TEST_F(AerialCompare, KnownDifferencesGiveTheDocumentedFigures) {
    // 100 pixels: one off by 3 steps in red, one by 1 step in blue. Per-pixel LSB sorted: 98
    // zeros, a 1 and a 3, so the 99th percentile (nearest rank) is 1; RMSE over 300 channels is
    // sqrt((9 + 1) / 300).
    const Rgb8Image a = grey_image(10, 10, 100);
    Rgb8Image b = a;
    b.rgb[3 * 17 + 0] = 103;
    b.rgb[3 * 42 + 2] = 99;
    const std::string diff = path("diff.png");
    const RunResult r = run({png("a.png", a), png("b.png", b), "--diff", diff});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    int max_lsb = -1, p99_lsb = -1;
    double rmse = -1, over1 = -1, over2 = -1, de = -1;
    ASSERT_EQ(std::sscanf(r.out.c_str(),
                          "max_lsb=%d p99_lsb=%d rmse_lsb=%lf over1=%lf over2=%lf de2000_mean=%lf",
                          &max_lsb, &p99_lsb, &rmse, &over1, &over2, &de),
              6)
        << r.out;
    EXPECT_EQ(max_lsb, 3);
    EXPECT_EQ(p99_lsb, 1);
    EXPECT_NEAR(rmse, std::sqrt(10.0 / 300.0), 1e-4);
    EXPECT_DOUBLE_EQ(over1, 0.01);
    EXPECT_DOUBLE_EQ(over2, 0.01);
    EXPECT_GT(de, 0.0);
    EXPECT_LT(de, 0.1) << "two pixels of a hundred, each by a few steps";

    // The diff image: the same size; equal pixels grey, 1 step blue, 3 steps yellow.
    const auto image = aerial::tools::read_png(diff);
    ASSERT_TRUE(image.ok()) << image.error().message;
    EXPECT_EQ(image->width, 10);
    EXPECT_EQ(image->height, 10);
    const std::uint8_t* same = image->pixel(0, 0);
    EXPECT_TRUE(same[0] == same[1] && same[1] == same[2]) << "an equal pixel is grey";
    const std::uint8_t* three = image->pixel(7, 1);
    EXPECT_EQ(three[0], 255);
    EXPECT_EQ(three[1], 230);
    EXPECT_EQ(three[2], 0);
    const std::uint8_t* one = image->pixel(2, 4);
    EXPECT_EQ(one[0], 0);
    EXPECT_EQ(one[2], 255);
}

TEST_F(AerialCompare, ABoundExceededExitsOneNamingIt) {
    // The same two images as above: max_lsb 3, p99_lsb 1, over1 = over2 = 0.01.
    const Rgb8Image a = grey_image(10, 10, 100);
    Rgb8Image b = a;
    b.rgb[3 * 17 + 0] = 103;
    b.rgb[3 * 42 + 2] = 99;
    const std::string pa = png("a.png", a), pb = png("b.png", b);
    RunResult r = run(
        {pa, pb, "--max-lsb", "3", "--p99-lsb", "1", "--max-over1", "0.01", "--max-over2", "0.01"});
    EXPECT_EQ(r.exit_code, 0) << "every bound met exactly: " << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    r = run({pa, pb, "--max-lsb", "2", "--max-over1", "0.001"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.out.rfind("max_lsb=3 p99_lsb=1", 0), 0u) << "the figures are still printed";
    EXPECT_EQ(r.err,
              "aerial-compare: over the bounds (max_lsb<=2 max_over1<=0.001): max_lsb 3 > 2, "
              "over1 0.01 > 0.001\n");
    r = run({pa, pb, "--p99-lsb", "0"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("p99_lsb 1 > 0"), std::string::npos) << r.err;
}

TEST_F(AerialCompare, RejectsABoundOutOfRange) {
    const Rgb8Image a = grey_image(2, 2, 0);
    const RunResult r = run({png("a.png", a), png("b.png", a), "--max-over1", "2"});
    EXPECT_TRUE(rejected_naming(r, "aerial-compare", {"--max-over1"}));
}

// ---- bad input: exit 2, one stderr line naming the culprit, nothing on stdout ---------------

TEST_F(AerialCompare, RejectsAMissingSecondImage) {
    const std::string a = png("a.png", grey_image(4, 4, 0));
    EXPECT_TRUE(aerial::test::rejected_naming(run({a}), kTool, {"B"}));
}

TEST_F(AerialCompare, RejectsNoArguments) {
    EXPECT_TRUE(aerial::test::rejected_naming(run({}), kTool, {"A"}));
}

TEST_F(AerialCompare, RejectsAMissingFileNamingIt) {
    const std::string a = png("a.png", grey_image(4, 4, 0));
    const std::string missing = path("nowhere/b.png");
    EXPECT_TRUE(aerial::test::rejected_naming(run({a, missing}), kTool, {"B", missing.c_str()}));
    EXPECT_TRUE(aerial::test::rejected_naming(run({missing, a}), kTool, {"A", missing.c_str()}));
}

TEST_F(AerialCompare, RejectsAFileThatIsNotAPng) {
    const std::string a = png("a.png", grey_image(4, 4, 0));
    const std::string text = file("b.png", "not a picture\n");
    EXPECT_TRUE(aerial::test::rejected_naming(run({a, text}), kTool, {"B", text.c_str()}));
}

TEST_F(AerialCompare, RejectsATruncatedPng) {
    const std::string a = png("a.png", grey_image(32, 32, 7));
    const std::string whole = aerial::test::read_text(a);
    const std::string cut = file("cut.png", whole.substr(0, whole.size() / 2));
    EXPECT_TRUE(aerial::test::rejected_naming(run({a, cut}), kTool, {"B", cut.c_str()}));
}

TEST_F(AerialCompare, RejectsImagesOfDifferentSizesNamingBoth) {
    const std::string a = png("a.png", grey_image(4, 4, 0));
    const std::string b = png("b.png", grey_image(4, 5, 0));
    EXPECT_TRUE(aerial::test::rejected_naming(run({a, b}), kTool, {"4x5", "4x4"}));
}

TEST_F(AerialCompare, RejectsAnUnknownFlagNamingIt) {
    const std::string a = png("a.png", grey_image(4, 4, 0));
    EXPECT_TRUE(
        aerial::test::rejected_naming(run({a, a, "--tolerance=2"}), kTool, {"--tolerance"}));
}

TEST_F(AerialCompare, RejectsAThirdImage) {
    const std::string a = png("a.png", grey_image(4, 4, 0));
    EXPECT_TRUE(aerial::test::rejected_naming(run({a, a, a}), kTool, {a.c_str()}));
}

TEST_F(AerialCompare, RejectsADiffPathThatCannotBeWritten) {
    const std::string a = png("a.png", grey_image(4, 4, 0));
    const std::string blocker = file("blocker", "a file, not a directory\n");
    EXPECT_TRUE(aerial::test::rejected_naming(run({a, a, "--diff", blocker + "/diff.png"}), kTool,
                                              {"--diff"}));
}

}  // namespace
