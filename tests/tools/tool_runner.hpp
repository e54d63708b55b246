// Running the command-line tools end to end from GoogleTest: the real binary with its standard
// streams redirected to files in a per-test temporary directory, and the bad-input contract of
// docs/conventions.md, Interfaces (exit status 2, nothing on stdout, one stderr line "tool: ..."
// naming the culprit).
//
// How to use this:
//   1. Derive the fixture from aerial::test::ToolTest; `file(name, text)` writes an input,
//      `path(name)` names one, `run(binary, args, stdin_text)` runs the tool.
//   2. `EXPECT_TRUE(rejected_naming(result, "aerial-eval", {"--eye"}));`
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace aerial::test {

inline constexpr int kExitBadInput = 2;

struct RunResult {
    int exit_code = -1;
    std::string out;
    std::string err;
};

inline std::string shell_quote(const std::string& s) {
    std::string quoted = "'";
    for (char c : s) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

inline std::string read_text(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream file(path, std::ios::binary);
    file << text;
}

/// Runs `binary` with `args` through the shell, `input` on stdin; stdin, stdout and stderr go
/// through files named `stem`.* in `dir`. `environment` entries ("NAME=value") are set for it.
inline RunResult run_tool(const std::string& binary, const std::vector<std::string>& args,
                          const std::filesystem::path& dir, const std::string& stem,
                          const std::string& input = "",
                          const std::vector<std::string>& environment = {}) {
    const std::filesystem::path in = dir / (stem + ".stdin"), out = dir / (stem + ".stdout"),
                                err = dir / (stem + ".stderr");
    write_text(in, input);
    std::string command;
    if (!environment.empty()) {
        command = "env";
        for (const std::string& e : environment) command += " " + shell_quote(e);
        command += " ";
    }
    command += shell_quote(binary);
    for (const std::string& arg : args) command += " " + shell_quote(arg);
    command += " <" + shell_quote(in.string()) + " >" + shell_quote(out.string()) + " 2>" +
               shell_quote(err.string());
    const int status = std::system(command.c_str());
    RunResult result;
    result.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    result.out = read_text(out);
    result.err = read_text(err);
    return result;
}

/// The contract for bad input: exit status 2, nothing on stdout, exactly one line on stderr,
/// "tool: ..." containing every expected piece.
inline ::testing::AssertionResult rejected_naming(const RunResult& run, const std::string& tool,
                                                  std::initializer_list<const char*> expected) {
    if (run.exit_code != kExitBadInput) {
        return ::testing::AssertionFailure() << "exit status " << run.exit_code << ", expected "
                                             << kExitBadInput << "; stderr: '" << run.err << "'";
    }
    if (!run.out.empty()) {
        return ::testing::AssertionFailure() << "stdout is not empty: '" << run.out << "'";
    }
    const auto newlines =
        static_cast<std::size_t>(std::count(run.err.begin(), run.err.end(), '\n'));
    if (newlines != 1 || run.err.back() != '\n') {
        return ::testing::AssertionFailure() << "stderr is not exactly one line (" << newlines
                                             << " newlines): '" << run.err << "'";
    }
    if (run.err.rfind(tool + ": ", 0) != 0) {
        return ::testing::AssertionFailure()
               << "stderr does not start with '" << tool << ": ': '" << run.err << "'";
    }
    for (const char* piece : expected) {
        if (run.err.find(piece) == std::string::npos) {
            return ::testing::AssertionFailure()
                   << "stderr does not mention '" << piece << "': '" << run.err << "'";
        }
    }
    return ::testing::AssertionSuccess();
}

/// A fixture with a fresh temporary directory per test, kept after a failure for inspection.
class ToolTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = std::string(info->test_suite_name()) + "-" + info->name();
        std::replace(name.begin(), name.end(), '/', '_');
        dir_ = std::filesystem::temp_directory_path() /
               ("aerial-tool-test-" + std::to_string(::getpid()) + "-" + name);
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }

    void TearDown() override {
        if (!HasFailure()) std::filesystem::remove_all(dir_);
    }

    /// A path in the test's directory.
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    /// Writes a file in the test's directory and returns its path.
    std::string file(const std::string& name, const std::string& text) const {
        write_text(dir_ / name, text);
        return (dir_ / name).string();
    }

    RunResult run(const std::string& binary, const std::vector<std::string>& args,
                  const std::string& input = "", const std::vector<std::string>& environment = {}) {
        return run_tool(binary, args, dir_, "run" + std::to_string(++runs_), input, environment);
    }

    const std::filesystem::path& dir() const { return dir_; }

  private:
    std::filesystem::path dir_;
    int runs_ = 0;
};

}  // namespace aerial::test
