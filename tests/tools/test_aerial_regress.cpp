// aerial-regress end to end (docs/regression-testing.md): a deliberately broken driver setting
// gives the right status with a one-line reason, a crashing or hanging case is one case's
// result and the run goes on, a baseline makes only changes fail, and the reports carry what
// the run was pointed at.
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tool_runner.hpp"

namespace {

constexpr const char* kRegress = AERIAL_REGRESS_PATH;
constexpr const char* kSuiteDir = AERIAL_REGRESS_SUITE_DIR;
constexpr int kExitOk = 0, kExitRegression = 1, kExitRefused = 2, kExitNotSupported = 77;

struct Row {
    std::string status, reason;
};

/// results.csv by case (the reason is the column before platform; reasons here hold no commas
/// inside quotes that matter for the status).
std::map<std::string, Row> read_results(const std::string& path) {
    std::map<std::string, Row> rows;
    std::istringstream lines(aerial::test::read_text(path));
    std::string line;
    std::getline(lines, line);  // header
    while (std::getline(lines, line)) {
        std::vector<std::string> fields;
        std::string field;
        bool quoted = false;
        for (char c : line) {
            if (c == '"') {
                quoted = !quoted;
            } else if (c == ',' && !quoted) {
                fields.push_back(field);
                field.clear();
            } else {
                field += c;
            }
        }
        fields.push_back(field);
        if (fields.size() >= 15) rows[fields[0]] = {fields[3], fields[10]};
    }
    return rows;
}

class AerialRegress : public aerial::test::ToolTest {
  protected:
    /// Runs the runner on the source tree's suite (or `suite`) into out/.
    aerial::test::RunResult regress(std::vector<std::string> args,
                                    const std::vector<std::string>& environment = {},
                                    const std::string& suite = "") {
        args.insert(args.end(), {"--out", path("out"), "--suite",
                                 suite.empty() ? std::string(kSuiteDir) + "/suite.txt" : suite});
        return run(kRegress, args, "", environment);
    }
    std::map<std::string, Row> results() { return read_results(path("out/results.csv")); }

    /// A suite file in the test's directory that uses the source tree's scenes.
    std::string suite(const std::string& text) {
        std::filesystem::create_directories(dir() / "suite");
        std::filesystem::create_directory_symlink(std::string(kSuiteDir) + "/scenes",
                                                  dir() / "suite" / "scenes");
        return file("suite/suite.txt", "setting size 32x24\nsetting env LP_NUM_THREADS=1\n" + text);
    }
};

TEST_F(AerialRegress, ABogusDriverOnOsmesaIsOneNotSupportedCase) {
    const auto r = regress({"--gl", "osmesa", "--driver", "bogus"});
    EXPECT_EQ(r.exit_code, kExitNotSupported) << r.out << r.err;
    const auto rows = results();
    ASSERT_EQ(rows.size(), 1u) << "only the context case runs";
    EXPECT_EQ(rows.at("context").status, "not-supported");
    EXPECT_NE(rows.at("context").reason.find("GALLIUM_DRIVER"), std::string::npos)
        << rows.at("context").reason;
}

TEST_F(AerialRegress, ABogusDriverOnEglIsOneNotSupportedCase) {
    const auto r = regress({"--gl", "egl", "--driver", "bogus"});
    EXPECT_EQ(r.exit_code, kExitNotSupported) << r.out << r.err;
    EXPECT_EQ(results().at("context").status, "not-supported");
}

TEST_F(AerialRegress, ZinkOnOsmesaIsNotSupportedAndTheRunCompletes) {
    const auto r = regress({"--gl", "osmesa", "--driver", "zink"});
    EXPECT_EQ(r.exit_code, kExitNotSupported) << r.out << r.err;
    EXPECT_EQ(results().at("context").status, "not-supported");
    EXPECT_NE(r.out.find("aerial-regress: not supported: context: "
                         "aerial::headless::Context::create(): GALLIUM_DRIVER: OSMesa renders"),
              std::string::npos)
        << r.out;
}

TEST_F(AerialRegress, ACoreProfileIsNamedAndNotSupported) {
    const auto r =
        regress({"--gl", "egl", "--driver", "llvmpipe"}, {"MESA_GL_VERSION_OVERRIDE=3.3FC"});
    EXPECT_EQ(r.exit_code, kExitNotSupported) << r.out << r.err;
    const Row context = results().at("context");
    EXPECT_EQ(context.status, "not-supported");
    EXPECT_NE(context.reason.find("core profile context: no fixed-function pipeline"),
              std::string::npos)
        << context.reason;
}

TEST_F(AerialRegress, AMissingEglPlatformIsOneNotSupportedCase) {
    const auto r = regress({"--gl", "egl", "--driver", "llvmpipe"},
                           {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/vendor.json"});
    EXPECT_EQ(r.exit_code, kExitNotSupported) << r.out << r.err;
    const Row context = results().at("context");
    EXPECT_EQ(context.status, "not-supported");
    EXPECT_NE(context.reason.find("EGL_MESA_platform_surfaceless"), std::string::npos)
        << context.reason;
}

TEST_F(AerialRegress, AHiddenExtensionMakesItsCasesNotSupportedAndTheRestRun) {
    const auto r = regress(
        {"--gl", "osmesa", "--driver", "llvmpipe", "--tier", "portable", "--cases", "noon_valley"},
        {"MESA_EXTENSION_OVERRIDE=-GL_ARB_vertex_program"});
    EXPECT_EQ(r.exit_code, kExitOk) << r.out << r.err;
    const auto rows = results();
    ASSERT_TRUE(rows.count("cross/noon_valley/arb")) << r.out;
    EXPECT_EQ(rows.at("cross/noon_valley/arb").status, "not-supported");
    EXPECT_NE(rows.at("cross/noon_valley/arb").reason.find("GL_ARB_vertex_program"),
              std::string::npos);
    EXPECT_EQ(rows.at("state/noon_valley/arb").status, "not-supported");
    EXPECT_EQ(rows.at("cross/noon_valley/cpu").status, "pass");
}

TEST_F(AerialRegress, ARendererOtherThanTheDriverAskedForIsRefused) {
    const auto r = regress({"--gl", "egl", "--driver", "llvmpipe"},
                           {"LIBGL_ALWAYS_SOFTWARE=1", "MESA_LOADER_DRIVER_OVERRIDE=zink"});
    EXPECT_EQ(r.exit_code, kExitRefused) << r.out << r.err;
    const Row context = results().at("context");
    EXPECT_EQ(context.status, "fail");
    EXPECT_NE(context.reason.find("refused: GL_RENDERER is 'zink"), std::string::npos)
        << context.reason;
    EXPECT_NE(context.reason.find("MESA_LOADER_DRIVER_OVERRIDE=zink is set"), std::string::npos)
        << context.reason;
}

TEST_F(AerialRegress, ADriverVariableTheCallerSetOtherwiseIsNotOverridden) {
    const auto r = regress({"--gl", "osmesa", "--driver", "llvmpipe"}, {"GALLIUM_DRIVER=softpipe"});
    EXPECT_TRUE(aerial::test::rejected_naming(r, "aerial-regress",
                                              {"--driver", "GALLIUM_DRIVER=softpipe"}));
}

TEST_F(AerialRegress, CrashesAndHangsAreOneCaseEachAndTheRunGoesOn) {
    const std::string s = suite(
        "selftest crash\nselftest hang\nselftest fail\n"
        "cross noon_valley max_lsb=255\n");
    const auto r =
        regress({"--gl", "osmesa", "--timeout", "3", "--cases", "cross/noon_valley/cpu"}, {}, s);
    EXPECT_EQ(r.exit_code, kExitRegression) << r.out << r.err;
    const auto rows = results();
    EXPECT_EQ(rows.at("selftest/crash").status, "crash");
    EXPECT_NE(rows.at("selftest/crash").reason.find("signal 6"), std::string::npos);
    EXPECT_EQ(rows.at("selftest/hang").status, "crash");
    EXPECT_NE(rows.at("selftest/hang").reason.find("timed out after 3 s"), std::string::npos);
    EXPECT_EQ(rows.at("selftest/fail").status, "fail");
    EXPECT_EQ(rows.at("cross/noon_valley/cpu").status, "pass") << "the run went on";
    EXPECT_NE(r.out.find("3 regression(s)"), std::string::npos) << r.out;
    const std::string junit = aerial::test::read_text(path("out/junit.xml"));
    EXPECT_NE(junit.find("failures=\"1\" errors=\"2\""), std::string::npos) << junit;
    EXPECT_NE(junit.find("<property name=\"GL_RENDERER\" value=\"llvmpipe"), std::string::npos);
}

TEST_F(AerialRegress, WithABaselineOnlyChangesFailTheRun) {
    const std::string s = suite("selftest crash\nselftest fail\ncross noon_valley max_lsb=255\n");
    const std::string baseline =
        file("baseline.txt",
             "# known\nselftest/crash crash\nselftest/fail fail\ncross/noon_valley/cpu fail\n");
    auto r = regress({"--gl", "osmesa", "--baseline", baseline, "--cases", "noon_valley/cpu",
                      "--write-baseline", path("written.txt")},
                     {}, s);
    EXPECT_EQ(r.exit_code, kExitOk) << r.out << r.err;
    EXPECT_NE(r.out.find("fixed: cross/noon_valley/cpu: fail -> pass"), std::string::npos) << r.out;
    EXPECT_EQ(aerial::test::read_text(path("written.txt")),
              "# aerial-regress baseline: the cases expected not to pass (CASE STATUS)\n"
              "selftest/crash crash\nselftest/fail fail\n");
    const std::string bad = file("bad.txt", "selftest/crash exploded\n");
    r = regress({"--gl", "osmesa", "--baseline", bad}, {}, s);
    EXPECT_TRUE(aerial::test::rejected_naming(r, "aerial-regress", {"--baseline", "bad.txt:1"}));
}

TEST_F(AerialRegress, AGoldenMissingForThisDeviceFailsNamingBless) {
    const std::string s = suite("golden noon_valley none\n");
    const auto r = regress({"--gl", "osmesa", "--driver", "llvmpipe", "--cases", "golden/"}, {}, s);
    EXPECT_EQ(r.exit_code, kExitRegression) << r.out << r.err;
    const Row golden = results().at("golden/noon_valley-none");
    EXPECT_EQ(golden.status, "fail");
    EXPECT_NE(golden.reason.find("osmesa-llvmpipe/noon_valley-none.png"), std::string::npos)
        << golden.reason;
    EXPECT_NE(golden.reason.find("--bless"), std::string::npos) << golden.reason;
}

TEST_F(AerialRegress, AMalformedSuiteNamesTheLine) {
    const std::string s = file("broken.txt", "setting size 32x24\ntolerance cross max_lsb=two\n");
    const auto r = run(kRegress, {"--suite", s, "--out", path("out")});
    EXPECT_TRUE(
        aerial::test::rejected_naming(r, "aerial-regress", {"broken.txt:2", "max_lsb=two"}));
}

}  // namespace
