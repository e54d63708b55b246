// aerial-eval --export-shader-tests: the piglit shader_test files it writes, checked two ways.
//
//   1. Always (GoogleTest): every file parses; its [vertex program] is what
//      `aerial-eval --print-arb-program` prints for the program it names; its parameter lines
//      are aerial::arb_program_parameters of the frame it states; every probe is the mean of
//      aerial::validation's executor outputs at the probed rect's diagonal vertices, recomputed
//      here from the file alone. Bad uses of the flag exit 2 with one line.
//   2. `test_shader_tests --run-piglit DIR` (CTest ShaderTests.PassUnderPiglitShaderRunner):
//      exports into DIR and runs each file with piglit's shader_runner (`-auto -fbo`, headless:
//      PIGLIT_PLATFORM=surfaceless_egl unless set), requiring "result": "pass" from each. Without
//      shader_runner (or without a GL context for it) it prints one line "not supported: ..."
//      and exits 77, which CTest reports as skipped (SKIP_RETURN_CODE).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/aerial.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/validation/arb_executor.hpp"
#include "tool_runner.hpp"

namespace {

namespace fs = std::filesystem;
using aerial::test::RunResult;
using Vec4 = std::array<float, 4>;

constexpr const char* kBinary = AERIAL_EVAL_PATH;
constexpr int kExitSkip = 77;  ///< CTest's SKIP_RETURN_CODE for the piglit run
constexpr std::size_t kFiles = 20;
constexpr std::size_t kProbesPerFile = 128;
/// The probes are printed with 6 decimals.
constexpr double kPrintedTolerance = 1e-6;

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream stream(text);
    std::string line;
    while (std::getline(stream, line)) lines.push_back(line);
    return lines;
}

bool starts_with(const std::string& s, const std::string& prefix) {
    return s.compare(0, prefix.size(), prefix) == 0;
}

/// A file cut into its sections and header comments.
struct ShaderTest {
    std::string program_flags;                 ///< "# program: aerial-eval ..." after aerial-eval
    std::map<std::string, std::string> frame;  ///< "# frame: key=value ..."
    std::vector<std::string> require;
    std::string vertex_program, fragment_program;
    std::vector<std::string> test;
};

::testing::AssertionResult parse_shader_test(const std::string& text, ShaderTest& st) {
    const std::string vp = "\n[vertex program]\n", fp = "\n[fragment program]\n",
                      req = "\n[require]\n", tst = "\n[test]\n";
    const std::size_t r = text.find(req), v = text.find(vp), f = text.find(fp), t = text.find(tst);
    if (r == std::string::npos || v == std::string::npos || f == std::string::npos ||
        t == std::string::npos || !(r < v && v < f && f < t)) {
        return ::testing::AssertionFailure()
               << "the sections [require], [vertex program], [fragment program], [test] are "
                  "not all there in that order";
    }
    for (const std::string& line : lines_of(text.substr(0, r))) {
        if (starts_with(line, "# program: aerial-eval ")) {
            st.program_flags = line.substr(std::string("# program: aerial-eval ").size());
        } else if (starts_with(line, "# frame: ")) {
            std::istringstream words(line.substr(9));
            std::string word;
            while (words >> word) {
                const std::size_t eq = word.find('=');
                if (eq != std::string::npos) st.frame[word.substr(0, eq)] = word.substr(eq + 1);
            }
        } else if (!line.empty() && line[0] != '#') {
            return ::testing::AssertionFailure() << "a line before [require] is not a comment";
        }
    }
    for (const std::string& line : lines_of(text.substr(r + req.size(), v - r - req.size()))) {
        if (!line.empty()) st.require.push_back(line);
    }
    st.vertex_program = text.substr(v + vp.size(), f - v - vp.size());
    st.fragment_program = text.substr(f + fp.size(), t - f - fp.size());
    for (const std::string& line : lines_of(text.substr(t + tst.size()))) {
        if (!line.empty() && line[0] != '#') st.test.push_back(line);
    }
    if (st.program_flags.empty() || st.frame.empty()) {
        return ::testing::AssertionFailure() << "the '# program:' or '# frame:' line is missing";
    }
    return ::testing::AssertionSuccess();
}

std::vector<std::string> words_of(const std::string& text) {
    std::vector<std::string> words;
    std::istringstream stream(text);
    std::string word;
    while (stream >> word) words.push_back(word);
    return words;
}

glm::dvec3 vec3_of(const std::string& text) {
    glm::dvec3 v{0.0};
    std::sscanf(text.c_str(), "%lf,%lf,%lf", &v.x, &v.y, &v.z);
    return v;
}

/// The options and frame the file states, rebuilt from its comments (not from the exporter).
struct Stated {
    aerial::ArbProgramOptions options;
    aerial::View view;
    std::string preset;
    float exposure = 0.0f;
};

::testing::AssertionResult stated(const ShaderTest& st, Stated& s) {
    const std::vector<std::string> flags = words_of(st.program_flags);
    for (std::size_t i = 0; i + 1 < flags.size(); ++i) {
        if (flags[i] == "--model") {
            auto model = aerial::parse_model(flags[i + 1]);
            if (!model) return ::testing::AssertionFailure() << model.error().message;
            s.options.model = *model;
        } else if (flags[i] == "--arb-height-fidelity") {
            auto level = aerial::parse_arb_height_fidelity(flags[i + 1]);
            if (!level) return ::testing::AssertionFailure() << level.error().message;
            s.options.height_fidelity = *level;
            // What --print-arb-program checks the level against.
            s.options.limits = aerial::arb_reference_limits(*level);
        }
    }
    for (const char* key : {"preset", "eye", "sun", "up", "meters_per_unit", "exposure"}) {
        if (st.frame.count(key) == 0) {
            return ::testing::AssertionFailure() << "the frame line has no " << key;
        }
    }
    s.preset = st.frame.at("preset");
    s.view.eye = vec3_of(st.frame.at("eye"));
    s.view.sun_dir = vec3_of(st.frame.at("sun"));
    s.view.up = vec3_of(st.frame.at("up"));
    s.view.meters_per_unit = std::strtod(st.frame.at("meters_per_unit").c_str(), nullptr);
    s.exposure = std::strtof(st.frame.at("exposure").c_str(), nullptr);
    return ::testing::AssertionSuccess();
}

std::optional<Vec4> parenthesised(const std::string& text) {
    Vec4 v{};
    if (std::sscanf(text.c_str(), " (%f , %f , %f , %f)", &v[0], &v[1], &v[2], &v[3]) != 4) {
        return std::nullopt;
    }
    return v;
}

class ExportShaderTests : public aerial::test::ToolTest {};

TEST_F(ExportShaderTests, EveryFileIsTheGeneratedProgramWithTheExecutorsProbes) {
    const RunResult run = this->run(kBinary, {"--export-shader-tests", path("out")});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_EQ(run.err, "");
    const std::vector<std::string> listed = lines_of(run.out);
    ASSERT_EQ(listed.size(), kFiles) << run.out;
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(path("out"))) {
        ASSERT_EQ(entry.path().extension(), ".shader_test") << entry.path();
        ++files;
    }
    EXPECT_EQ(files, kFiles);
    std::map<std::string, int> programs;

    for (const std::string& file : listed) {
        SCOPED_TRACE(file);
        ShaderTest st;
        ASSERT_TRUE(parse_shader_test(aerial::test::read_text(file), st));
        EXPECT_NE(std::find(st.require.begin(), st.require.end(), "GL_ARB_vertex_program"),
                  st.require.end());
        EXPECT_NE(std::find(st.require.begin(), st.require.end(), "GL_ARB_fragment_program"),
                  st.require.end());
        EXPECT_TRUE(starts_with(st.fragment_program, "!!ARBfp1.0\n"));

        // The program: what --print-arb-program prints for the flags the file names.
        std::vector<std::string> print_args = words_of(st.program_flags);
        ASSERT_FALSE(print_args.empty());
        EXPECT_EQ(print_args.front(), "--print-arb-program");
        const RunResult printed = this->run(kBinary, print_args);
        ASSERT_EQ(printed.exit_code, 0) << printed.err;
        EXPECT_EQ(st.vertex_program, printed.out);
        ++programs[st.program_flags];

        // The parameters: arb_program_parameters of the stated frame, bit for bit.
        Stated s;
        ASSERT_TRUE(stated(st, s));
        auto program = aerial::generate_arb_program(s.options);
        ASSERT_TRUE(program.ok()) << program.error().message;
        EXPECT_EQ(program->text, st.vertex_program);
        auto atmosphere = aerial::atmosphere_preset(s.preset);
        ASSERT_TRUE(atmosphere.ok()) << atmosphere.error().message;
        auto frame = aerial::prepare_frame<float>(*atmosphere, s.view, s.options.model);
        ASSERT_TRUE(frame.ok()) << frame.error().message;
        aerial::Display display;
        display.exposure = s.exposure;
        auto expected_params = aerial::arb_program_parameters(*frame, display, program->options);
        ASSERT_TRUE(expected_params.ok()) << expected_params.error().message;

        // The [test] section, replayed on the executor.
        auto parsed = aerial::validation::parse_arb_program(st.vertex_program);
        ASSERT_TRUE(parsed.ok()) << parsed.error().message;
        aerial::validation::ArbMachine machine;
        std::optional<Vec4> select;
        std::vector<std::array<int, 4>> rects;
        std::size_t probes = 0, params_seen = 0;
        bool tolerance_seen = false, ortho_seen = false;
        std::array<double, 2> brightest{0.0, 0.0};  // per pass: largest probed channel
        for (const std::string& line : st.test) {
            SCOPED_TRACE(line);
            int index = -1, n = 0;
            if (starts_with(line, "parameter local_vp ")) {
                ASSERT_EQ(std::sscanf(line.c_str(), "parameter local_vp %d%n", &index, &n), 1);
                const auto v = parenthesised(line.substr(static_cast<std::size_t>(n)));
                ASSERT_TRUE(v.has_value());
                ASSERT_GE(index, 0);
                ASSERT_LT(static_cast<std::size_t>(index), expected_params->size());
                EXPECT_EQ(*v, (*expected_params)[static_cast<std::size_t>(index)]);
                if (machine.local.size() <= static_cast<std::size_t>(index)) {
                    machine.local.resize(static_cast<std::size_t>(index) + 1);
                }
                machine.local[static_cast<std::size_t>(index)] = *v;
                ++params_seen;
            } else if (starts_with(line, "parameter local_fp 0 ")) {
                select = parenthesised(line.substr(std::string("parameter local_fp 0 ").size()));
                ASSERT_TRUE(select.has_value());
                ASSERT_TRUE((*select == Vec4{1, 0, 0, 0} || *select == Vec4{0, 1, 0, 0}));
            } else if (line == "clear") {
                rects.clear();
            } else if (starts_with(line, "draw rect ")) {
                std::array<int, 4> r{};
                ASSERT_EQ(
                    std::sscanf(line.c_str(), "draw rect %d %d %d %d", &r[0], &r[1], &r[2], &r[3]),
                    4);
                ASSERT_EQ(r[2], 1);
                ASSERT_EQ(r[3], 1);
                rects.push_back(r);
            } else if (starts_with(line, "probe rgba ")) {
                int x = 0, y = 0;
                Vec4 printed_rgba{};
                ASSERT_EQ(std::sscanf(line.c_str(), "probe rgba %d %d %f %f %f %f", &x, &y,
                                      &printed_rgba[0], &printed_rgba[1], &printed_rgba[2],
                                      &printed_rgba[3]),
                          6);
                ASSERT_TRUE(select.has_value());
                ASSERT_NE(std::find(rects.begin(), rects.end(), std::array<int, 4>{x, y, 1, 1}),
                          rects.end())
                    << "no rect drawn on the probed pixel since the last clear";
                std::array<double, 4> mean{};
                for (const auto& [vx, vy] : {std::pair<int, int>{x + 1, y}, {x, y + 1}}) {
                    aerial::validation::ArbVertex vertex;
                    vertex.position = {float(vx), float(vy), 0.0f, 1.0f};
                    const auto out = aerial::validation::run_arb_program(*parsed, machine, vertex);
                    for (std::size_t c = 0; c < 4; ++c) {
                        const double colour = (*select)[0] * double(out.color_primary.value[c]) +
                                              (*select)[1] * double(out.color_secondary.value[c]);
                        mean[c] += 0.5 * std::clamp(colour, 0.0, 1.0);
                    }
                }
                for (std::size_t c = 0; c < 4; ++c) {
                    EXPECT_NEAR(double(printed_rgba[c]), mean[c], kPrintedTolerance)
                        << "channel " << c;
                    if (c < 3) {
                        auto& b = brightest[(*select)[0] == 1.0f ? 0 : 1];
                        b = std::max(b, mean[c]);
                    }
                }
                ++probes;
            } else if (starts_with(line, "tolerance ")) {
                const std::vector<std::string> t = words_of(line);
                ASSERT_EQ(t.size(), 5u);
                for (std::size_t c = 1; c < 5; ++c) {
                    EXPECT_NEAR(std::strtod(t[c].c_str(), nullptr), 1.5 / 255.0, 1e-9);
                }
                tolerance_seen = true;
            } else if (line == "ortho 0 250 0 250") {
                ortho_seen = true;
            } else {
                EXPECT_EQ(line, "clear color 0.0 0.0 0.0 0.0") << "an unexpected command";
            }
        }
        EXPECT_TRUE(tolerance_seen);
        EXPECT_TRUE(ortho_seen);
        EXPECT_EQ(params_seen, expected_params->size());
        EXPECT_EQ(probes, kProbesPerFile);
        // Both passes show something: F_ex near 1 close to the eye, L_in up to the exposure's
        // target of 0.9.
        EXPECT_GT(brightest[0], 0.9);
        EXPECT_GT(brightest[1], 0.3);
    }
    // Four frames for each of the five programs.
    EXPECT_EQ(programs.size(), 5u);
    for (const auto& [flags, count] : programs) EXPECT_EQ(count, 4) << flags;
}

TEST_F(ExportShaderTests, TakesNoOtherFlag) {
    const RunResult run =
        this->run(kBinary, {"--export-shader-tests", path("out"), "--preset", "earth"});
    EXPECT_TRUE(
        aerial::test::rejected_naming(run, "aerial-eval", {"--export-shader-tests", "--preset"}));
    EXPECT_FALSE(fs::exists(path("out")));
}

TEST_F(ExportShaderTests, RejectsADirectoryItCannotCreate) {
    const std::string blocker = file("blocker", "a file, not a directory\n");
    const RunResult run = this->run(kBinary, {"--export-shader-tests", blocker + "/out"});
    EXPECT_TRUE(aerial::test::rejected_naming(run, "aerial-eval",
                                              {"--export-shader-tests", "cannot create"}));
}

// ---- --run-piglit ----------------------------------------------------------------------------

bool executable(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && access(p.c_str(), X_OK) == 0;
}

/// AERIAL_SHADER_RUNNER, else piglit's install locations (Debian: /usr/lib/<triplet>/piglit),
/// else shader_runner on PATH.
std::optional<fs::path> find_shader_runner(std::string& searched) {
    if (const char* env = std::getenv("AERIAL_SHADER_RUNNER")) {
        searched = std::string("AERIAL_SHADER_RUNNER=") + env;
        if (executable(env)) return fs::path(env);
        return std::nullopt;
    }
    std::vector<fs::path> candidates{"/usr/lib/piglit/bin/shader_runner",
                                     "/usr/local/lib/piglit/bin/shader_runner"};
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator("/usr/lib", ec)) {
        candidates.push_back(entry.path() / "piglit/bin/shader_runner");
    }
    if (const char* path = std::getenv("PATH")) {
        std::istringstream dirs(path);
        std::string dir;
        while (std::getline(dirs, dir, ':')) {
            if (!dir.empty()) candidates.push_back(fs::path(dir) / "shader_runner");
        }
    }
    for (const fs::path& c : candidates) {
        if (executable(c)) return c;
    }
    searched = "/usr/lib/*/piglit/bin, /usr/lib/piglit/bin, /usr/local/lib/piglit/bin, PATH";
    return std::nullopt;
}

/// "pass", "fail", "skip", ... from piglit's last line, or "" when there is none.
std::string piglit_result(const std::string& out) {
    static const std::regex result(R"(PIGLIT: \{["']result["']: ["'](\w+)["'])");
    std::string last;
    for (auto it = std::sregex_iterator(out.begin(), out.end(), result);
         it != std::sregex_iterator(); ++it) {
        last = (*it)[1];
    }
    return last;
}

int run_piglit(const fs::path& dir) {
    std::string searched;
    const auto runner = find_shader_runner(searched);
    if (!runner) {
        std::printf("not supported: piglit's shader_runner not found (%s)\n", searched.c_str());
        return kExitSkip;
    }
    setenv("PIGLIT_PLATFORM", "surfaceless_egl", 0);  // headless unless the caller chose
    const char* platform = std::getenv("PIGLIT_PLATFORM");
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);

    // GL_RENDERER from piglit's glinfo next to shader_runner, on the same platform; a context
    // it cannot create means the platform is not usable here.
    const fs::path glinfo = runner->parent_path() / "glinfo";
    if (executable(glinfo)) {
        const RunResult info = aerial::test::run_tool(glinfo.string(), {"-auto"}, dir, "glinfo");
        std::string renderer, version;
        for (const std::string& line : lines_of(info.out)) {
            if (starts_with(line, "GL_RENDERER = ")) renderer = line.substr(14);
            if (starts_with(line, "GL_VERSION = ")) version = line.substr(13);
        }
        if (renderer.empty()) {
            // The line that says why (piglit's "error: ..." on stderr), else the first one.
            const std::vector<std::string> lines = lines_of(info.err + info.out);
            std::string why = lines.empty() ? "no output" : lines.front();
            for (const std::string& line : lines) {
                if (line.find("error") != std::string::npos) {
                    why = line;
                    break;
                }
            }
            std::printf("not supported: no GL context on PIGLIT_PLATFORM=%s (%s: %s)\n", platform,
                        glinfo.c_str(), why.c_str());
            return kExitSkip;
        }
        std::printf("GL_RENDERER = %s\nGL_VERSION = %s\n", renderer.c_str(), version.c_str());
    }
    std::printf("shader_runner: %s (PIGLIT_PLATFORM=%s)\n", runner->c_str(), platform);

    const RunResult exported = aerial::test::run_tool(
        kBinary, {"--export-shader-tests", (dir / "files").string()}, dir, "export");
    if (exported.exit_code != 0) {
        std::printf("FAIL: aerial-eval --export-shader-tests: %s", exported.err.c_str());
        return 1;
    }
    int passed = 0, skipped = 0, failed = 0;
    for (const std::string& file : lines_of(exported.out)) {
        const std::string stem = fs::path(file).stem().string();
        const RunResult r =
            aerial::test::run_tool(runner->string(), {file, "-auto", "-fbo"}, dir, stem);
        const std::string result = piglit_result(r.out);
        std::printf("%-5s %s\n", result.empty() ? "none" : result.c_str(),
                    fs::path(file).filename().c_str());
        if (result == "pass") {
            ++passed;
        } else if (result == "skip") {
            ++skipped;
        } else {
            ++failed;
            const std::vector<std::string> lines = lines_of(r.out + r.err);
            const std::size_t from = lines.size() > 12 ? lines.size() - 12 : 0;
            for (std::size_t i = from; i < lines.size(); ++i) {
                std::printf("    %s\n", lines[i].c_str());
            }
        }
    }
    std::printf("%d passed, %d skipped, %d failed\n", passed, skipped, failed);
    if (failed > 0 || passed + skipped == 0) return 1;
    if (passed == 0) {
        std::printf("not supported: shader_runner skipped every file\n");
        return kExitSkip;
    }
    return skipped > 0 ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc == 3 && std::string(argv[1]) == "--run-piglit") return run_piglit(argv[2]);
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
