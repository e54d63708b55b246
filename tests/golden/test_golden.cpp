// Golden images (docs/conventions.md, Tests and measurements): every image listed in goldens.txt
// is rendered afresh with
// aerial-render, on OSMesa and on EGL surfaceless (both llvmpipe, LP_NUM_THREADS pinned), and
// compared with the stored one by aerial-compare within a tolerance in 8-bit steps; the fresh
// image and a diff image stay in the build directory. The cross-backend checks render each scene
// with cpu, arb, perpixel and fog and bound the interpolation error of the per-vertex backends
// against the per-pixel image, and show that plain fog is visibly different.
// Never regenerates a golden: that is `tools/aerial.sh goldens`.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tool_runner.hpp"

namespace {

namespace fs = std::filesystem;

constexpr const char* kRender = AERIAL_RENDER_PATH;
constexpr const char* kCompare = AERIAL_COMPARE_PATH;
constexpr const char* kGoldenDir = AERIAL_GOLDEN_DIR;
constexpr const char* kOutDir = AERIAL_GOLDEN_OUT_DIR;

/// A golden matches when no pixel is off by more than kGoldenMaxLsb steps and at most
/// kGoldenMaxOver1 of the pixels by more than one: the same renderer gives the same image, and
/// this leaves room for a Highway target that rounds a vertex colour the other way.
constexpr int kGoldenMaxLsb = 2;
constexpr double kGoldenMaxOver1 = 0.001;
/// On EGL (an FBO with its own depth buffer) the goldens made on OSMesa may differ in a handful
/// of pixels as well: at most this fraction off by more than 2 steps, with no bound on how far.
/// Seen: on EGL the two-pass path adds L_in twice in one silhouette pixel of mountains_height
/// (55 steps), where a ridge's front and back triangles get the same depth value and both pass
/// depth EQUAL; on OSMesa they do not.
constexpr double kEglMaxOver2 = 0.0005;
/// Plain fog is visibly different from the per-pixel model: its worst 1 % of pixels are off by
/// at least this many steps.
constexpr int kFogMinP99Lsb = 8;

struct Golden {
    std::string scene, backend, path;
    std::string name() const { return scene + "-" + backend + (path.empty() ? "" : "-" + path); }
};

struct Cross {
    std::string scene;
    int max_lsb = 0, p99_lsb = 0;
};

void PrintTo(const Cross& c, std::ostream* os) { *os << c.scene; }

struct GoldenList {
    std::string size, gl;
    std::vector<std::string> environment;
    std::vector<Golden> goldens;
    std::vector<Cross> cross;
};

/// goldens.txt (its format is described at its top). Unknown lines fail the test run loudly.
const GoldenList& golden_list() {
    static const GoldenList list = [] {
        GoldenList l;
        std::ifstream file(fs::path(kGoldenDir) / "goldens.txt");
        std::string line;
        while (std::getline(file, line)) {
            std::istringstream words(line);
            std::string kind;
            if (!(words >> kind) || kind[0] == '#') continue;
            if (kind == "setting") {
                std::string name, value;
                words >> name >> value;
                if (name == "size") l.size = value;
                if (name == "gl") l.gl = value;
                if (name == "env") l.environment.push_back(value);
            } else if (kind == "golden") {
                Golden g;
                words >> g.scene >> g.backend >> g.path;
                l.goldens.push_back(g);
            } else if (kind == "cross") {
                Cross c;
                words >> c.scene >> c.max_lsb >> c.p99_lsb;
                l.cross.push_back(c);
            } else {
                std::cerr << "goldens.txt: unknown line '" << line << "'\n";
                std::abort();
            }
        }
        return l;
    }();
    return list;
}

/// aerial-compare's line, parsed.
struct Differences {
    int max_lsb = -1, p99_lsb = -1;
    double rmse_lsb = -1, over1 = -1, over2 = -1, de2000_mean = -1;
    std::string line;
};

bool parse_differences(const std::string& out, Differences& d) {
    d.line = out.substr(0, out.find('\n'));
    return std::sscanf(out.c_str(),
                       "max_lsb=%d p99_lsb=%d rmse_lsb=%lf over1=%lf over2=%lf de2000_mean=%lf",
                       &d.max_lsb, &d.p99_lsb, &d.rmse_lsb, &d.over1, &d.over2,
                       &d.de2000_mean) == 6;
}

fs::path out_dir() {
    const fs::path dir = fs::path(kOutDir);
    fs::create_directories(dir);
    return dir;
}

/// Renders one image into the build directory; fails the test when aerial-render does.
::testing::AssertionResult render(const std::string& scene, const std::string& backend,
                                  const std::string& path, const std::string& gl,
                                  const fs::path& out) {
    const GoldenList& list = golden_list();
    std::vector<std::string> args{
        "--scene",   (fs::path(kGoldenDir) / "scenes" / (scene + ".json")).string(),
        "--backend", backend,
        "--gl",      gl,
        "--size",    list.size,
        "--out",     out.string()};
    if (!path.empty()) args.insert(args.end(), {"--path", path});
    const aerial::test::RunResult r = aerial::test::run_tool(
        kRender, args, out.parent_path(), out.stem().string(), "", list.environment);
    if (r.exit_code != 0) {
        return ::testing::AssertionFailure()
               << "aerial-render exited " << r.exit_code << ": " << r.err;
    }
    std::cout << "  " << r.out;
    return ::testing::AssertionSuccess();
}

::testing::AssertionResult compare(const fs::path& a, const fs::path& b, const fs::path& diff,
                                   Differences& d) {
    const aerial::test::RunResult r =
        aerial::test::run_tool(kCompare, {a.string(), b.string(), "--diff", diff.string()},
                               diff.parent_path(), diff.stem().string());
    if (r.exit_code != 0 || !parse_differences(r.out, d)) {
        return ::testing::AssertionFailure()
               << "aerial-compare exited " << r.exit_code << ": " << r.out << r.err;
    }
    return ::testing::AssertionSuccess();
}

// ---- goldens --------------------------------------------------------------------------------

struct GoldenCase {
    Golden golden;
    std::string gl;
};

void PrintTo(const GoldenCase& c, std::ostream* os) { *os << c.golden.name() << " on " << c.gl; }

class GoldenImage : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(GoldenImage, MatchesTheStoredImage) {
    const GoldenCase& c = GetParam();
    const std::string name = c.golden.name();
    const fs::path golden = fs::path(kGoldenDir) / (name + ".png");
    ASSERT_TRUE(fs::exists(golden)) << golden << " is missing: run tools/aerial.sh goldens";
    const fs::path fresh = out_dir() / (name + "-" + c.gl + ".png");
    const fs::path diff = out_dir() / (name + "-" + c.gl + "-diff.png");
    ASSERT_TRUE(render(c.golden.scene, c.golden.backend, c.golden.path, c.gl, fresh));
    Differences d;
    ASSERT_TRUE(compare(golden, fresh, diff, d));
    std::cout << "  " << name << " (" << c.gl << "): " << d.line << "\n";
    if (c.gl == golden_list().gl) {
        EXPECT_LE(d.max_lsb, kGoldenMaxLsb)
            << name << " on " << c.gl << " differs from " << golden << ": " << d.line
            << "\n  fresh image: " << fresh << "\n  diff image: " << diff
            << "\n  (the goldens' renderer is in tests/golden/RENDERER.txt)";
    } else {
        EXPECT_LE(d.over2, kEglMaxOver2)
            << name << " on " << c.gl << " differs from " << golden << ": " << d.line
            << "\n  fresh image: " << fresh << "\n  diff image: " << diff;
    }
    EXPECT_LE(d.over1, kGoldenMaxOver1)
        << name << " on " << c.gl << ": " << d.line << "\n  diff image: " << diff;
}

std::vector<GoldenCase> golden_cases() {
    std::vector<GoldenCase> cases;
    for (const char* gl : {"osmesa", "egl"}) {
        for (const Golden& g : golden_list().goldens) cases.push_back({g, gl});
    }
    return cases;
}

std::string test_name(const std::string& text) {
    std::string name;
    for (char ch : text) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(Goldens, GoldenImage, ::testing::ValuesIn(golden_cases()),
                         [](const ::testing::TestParamInfo<GoldenCase>& p) {
                             return test_name(p.param.golden.name() + "_" + p.param.gl);
                         });

// ---- cross-backend sanity -------------------------------------------------------------------

class CrossBackend : public ::testing::TestWithParam<Cross> {};

bool has_golden(const std::string& scene, const std::string& backend) {
    for (const Golden& g : golden_list().goldens) {
        if (g.scene == scene && g.backend == backend) return true;
    }
    return false;
}

TEST_P(CrossBackend, PerVertexBackendsAreCloseToPerPixelAndFogIsNot) {
    const Cross& c = GetParam();
    const std::string gl = golden_list().gl;
    const fs::path dir = out_dir();
    const auto image = [&](const std::string& backend) {
        return dir / ("cross-" + c.scene + "-" + backend + ".png");
    };
    ASSERT_TRUE(render(c.scene, "perpixel", "", gl, image("perpixel")));
    std::vector<std::string> per_vertex{"cpu"};
    if (has_golden(c.scene, "arb")) per_vertex.push_back("arb");
    for (const std::string& backend : per_vertex) {
        ASSERT_TRUE(render(c.scene, backend, "", gl, image(backend)));
        Differences d;
        ASSERT_TRUE(compare(image(backend), image("perpixel"),
                            dir / ("cross-" + c.scene + "-" + backend + "-diff.png"), d));
        std::cout << "  " << c.scene << " " << backend << " vs perpixel: " << d.line << "\n";
        ::testing::Test::RecordProperty(backend + "_vs_perpixel", d.line);
        EXPECT_LE(d.max_lsb, c.max_lsb) << c.scene << " " << backend << " vs perpixel: " << d.line;
        EXPECT_LE(d.p99_lsb, c.p99_lsb) << c.scene << " " << backend << " vs perpixel: " << d.line;
    }
    ASSERT_TRUE(render(c.scene, "fog", "", gl, image("fog")));
    Differences fog;
    ASSERT_TRUE(compare(image("fog"), image("perpixel"),
                        dir / ("cross-" + c.scene + "-fog-diff.png"), fog));
    std::cout << "  " << c.scene << " fog vs perpixel: " << fog.line << "\n";
    ::testing::Test::RecordProperty("fog_vs_perpixel", fog.line);
    EXPECT_GE(fog.p99_lsb, kFogMinP99Lsb) << c.scene << " fog vs perpixel: " << fog.line;
}

INSTANTIATE_TEST_SUITE_P(Scenes, CrossBackend, ::testing::ValuesIn(golden_list().cross),
                         [](const ::testing::TestParamInfo<Cross>& p) {
                             return test_name(p.param.scene);
                         });

}  // namespace
