// aerial-regress: the software-GL regression runner (docs/regression-testing.md). Points the
// suite of tests/golden/suite.txt at one platform and driver, checks that GL reports the driver
// asked for, runs every case in its own process, and writes results.csv, junit.xml and a
// summary; with --baseline only changes against known failures and skips fail the run.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "aerial/headless.hpp"
#include "regress/cases.hpp"
#include "regress/driver.hpp"
#include "regress/report.hpp"
#include "regress/spawn.hpp"
#include "regress/suite.hpp"
#include "support/cli.hpp"

namespace {

using namespace aerial;
using namespace aerial::regress;
namespace fs = std::filesystem;

constexpr const char* kTool = "aerial-regress";

/// Exit statuses (also in --help): cases as expected; a regression; bad usage or a driver other
/// than the one asked for; the context itself is not supported (nothing else ran).
constexpr int kExitOk = 0, kExitRegression = 1, kExitRefused = 2, kExitNotSupported = 77;

constexpr const char* kDescription =
    "Runs the regression suite (tests/golden/suite.txt) on one headless platform and driver.\n"
    "Every case runs in its own process: a crash or hang is that case's result. Statuses: pass,\n"
    "fail, skip, crash, not-supported (the context lacks an extension, a platform, a\n"
    "compatibility profile). Tiers: portable (per-vertex against per-pixel on the same driver,\n"
    "the paths against each other, GL state restored, CPU shading against the model: these\n"
    "hold on any conforming driver) and golden (this device's stored images, tests/golden/\n"
    "DEVICE/, and the CPU's vertex colours, tests/golden/cpu/).\n"
    "--driver sets GALLIUM_DRIVER (zink on EGL also LIBGL_ALWAYS_SOFTWARE=1), never over a value\n"
    "the caller set otherwise, and the run is refused when GL_RENDERER names another driver.\n"
    "Writes OUT/results.csv, OUT/junit.xml, OUT/summary.txt, OUT/images/ (fresh, reference and\n"
    "diff images of each compared case) and OUT/logs/.\n"
    "Exit status: 0 when every case is as expected (pass, or as --baseline lists it), 1 on a\n"
    "regression (fail or crash not in the baseline), 2 on bad usage or a driver mismatch, 77\n"
    "when the context itself is not supported.";

/// The suite of the source tree this was built from, else the installed one beside the binary
/// (PREFIX/bin/aerial-regress reads PREFIX/share/aerial/golden/suite.txt).
std::string default_suite() {
    std::error_code error;
    if (fs::exists(AERIAL_REGRESS_SUITE, error)) return AERIAL_REGRESS_SUITE;
    const fs::path self = fs::read_symlink("/proc/self/exe", error);
    if (error) return AERIAL_REGRESS_SUITE;
    return (self.parent_path().parent_path() / "share" / "aerial" / "golden" / "suite.txt")
        .string();
}

struct Flags {
    std::string gl = "osmesa", driver, suite = default_suite(), tier = "all", filter;
    std::string out = "regress", baseline, write_baseline;
    bool bless = false, bless_cpu = false;
    int jobs = 1, timeout = 300;
    // The child's flags (internal).
    std::string child, result, device;
};

bool selected(const Case& c, const Flags& f) {
    if (c.kind == CaseKind::context) return false;
    if (f.tier != "all" && f.tier != tier_name(c.tier)) return false;
    if (f.tier == "all" && c.tier == Tier::selftest) return true;
    return f.filter.empty() || c.name.find(f.filter) != std::string::npos;
}

std::string self_path() {
    char buffer[4096];
    const ssize_t n = readlink("/proc/self/exe", buffer, sizeof buffer - 1);
    if (n <= 0) return "aerial-regress";
    return std::string(buffer, std::size_t(n));
}

int run_child(const Suite& suite, const Flags& f, headless::Platform platform) {
    const Case* c = suite.find(f.child);
    if (c == nullptr) return tools::fail(kTool, "--child: no case '" + f.child + "'");
    CaseSettings settings;
    settings.platform = platform;
    settings.device = f.device;
    settings.images_dir = (fs::path(f.out) / "images").string();
    settings.bless = f.bless;
    settings.bless_cpu = f.bless_cpu;
    fs::create_directories(settings.images_dir);
    const CaseResult r = run_case(suite, *c, settings);
    std::printf("%s: %s %s\n", c->name.c_str(), status_name(r.status), r.reason.c_str());
    return write_result(f.result, r) ? 0 : 1;
}

Identity identity_from(const Flags& f, const CaseResult& context,
                       const std::vector<std::string>& environment, headless::Platform platform) {
    Identity id;
    id.platform = headless::platform_name(platform);
    id.driver = f.driver;
    const auto get = [&](const char* key) {
        const auto it = context.metrics.find(key);
        return it == context.metrics.end() ? std::string() : it->second;
    };
    id.vendor = get("GL_VENDOR");
    id.renderer = get("GL_RENDERER");
    id.version = get("GL_VERSION");
    id.simd_target = get("simd_target");
    id.device = id.renderer.empty() ? "-" : device_name(platform, id.renderer);
    id.environment = environment;
    return id;
}

/// Writes the reports and prints the summary; returns the exit status for the outcomes.
int report(const Flags& f, const Identity& id, const Suite& suite,
           const std::vector<Outcome>& outcomes, const Baseline& baseline, int status) {
    const Verdict verdict = judge(outcomes, baseline);
    const int exit_status = status != kExitOk             ? status
                            : verdict.regressions.empty() ? kExitOk
                                                          : kExitRegression;
    std::string text = summary(id, outcomes, verdict) + kTool + ": ";
    if (exit_status == kExitOk) {
        text += "ok\n";
    } else if (status == kExitOk) {
        text += std::to_string(verdict.regressions.size()) + " regression(s)\n";
    } else {
        const char* what = exit_status == kExitNotSupported ? "not supported" : "stopped";
        text += std::string(what) + ": " + outcomes[0].c->name + ": " + outcomes[0].result.reason +
                "\n";
    }
    std::fputs(text.c_str(), stdout);
    const fs::path out(f.out);
    for (const auto& error :
         {write_csv((out / "results.csv").string(), id, outcomes),
          write_junit((out / "junit.xml").string(), id, outcomes),
          f.write_baseline.empty() ? std::nullopt : write_baseline(f.write_baseline, outcomes),
          f.bless ? write_device_file(
                        (fs::path(suite.directory) / id.device / "device.txt").string(), id, suite)
                  : std::nullopt}) {
        if (error) return tools::fail(kTool, *error);
    }
    std::FILE* file = std::fopen((out / "summary.txt").string().c_str(), "w");
    if (file != nullptr) {
        std::fputs(text.c_str(), file);
        std::fclose(file);
    }
    return exit_status;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{kDescription, kTool};
    Flags f;
    app.add_option("--gl", f.gl, "Headless platform: osmesa (default) or egl");
    app.add_option("--driver", f.driver,
                   "Mesa driver: llvmpipe, softpipe, zink or another Gallium name (default: what "
                   "the environment gives)");
    app.add_option("--suite", f.suite, "Suite file (default: the source tree's suite.txt)");
    app.add_option("--tier", f.tier, "portable, golden or all (default)");
    app.add_option("--cases", f.filter, "Only the cases whose name contains this text");
    app.add_option("--out", f.out, "Output directory (default ./regress)");
    app.add_option("--baseline", f.baseline, "Known non-passing cases: 'CASE STATUS' lines");
    app.add_option("--write-baseline", f.write_baseline,
                   "Write this run's non-passing cases as a baseline file");
    app.add_flag("--bless", f.bless,
                 "Write this device's golden images (tests/golden/DEVICE/) instead of comparing");
    app.add_flag("--bless-cpu", f.bless_cpu,
                 "Write the stored CPU vertex colours (tests/golden/cpu/) instead of comparing");
    app.add_option("--jobs", f.jobs, "Cases run at the same time (default 1)")
        ->check(CLI::Range(1, 64));
    app.add_option("--timeout", f.timeout, "Seconds before a case is killed (default 300)")
        ->check(CLI::Range(1, 86400));
    app.add_option("--child", f.child)->group("");
    app.add_option("--result", f.result)->group("");
    app.add_option("--device", f.device)->group("");
    if (auto status = tools::parse_command_line(app, argc, argv, kTool)) return *status;

    const auto platform = headless::parse_platform(f.gl);
    if (!platform) return tools::fail(kTool, "--gl: expected osmesa or egl, got '" + f.gl + "'");
    if (f.tier != "all" && f.tier != "portable" && f.tier != "golden" && f.tier != "selftest") {
        return tools::fail(kTool, "--tier: expected portable, golden or all, got '" + f.tier + "'");
    }
    const auto suite = load_suite(f.suite);
    if (!suite) return tools::fail(kTool, suite.error().message);
    if (!f.child.empty()) return run_child(*suite, f, *platform);

    Baseline baseline;
    if (!f.baseline.empty()) {
        auto loaded = load_baseline(f.baseline);
        if (!loaded) return tools::fail(kTool, loaded.error().message);
        baseline = std::move(loaded).value();
    }
    const auto environment =
        apply_environment(driver_variables(*platform, f.driver), suite->environment);
    if (!environment) return tools::fail(kTool, environment.error().message);
    fs::create_directories(f.out);

    SpawnOptions spawn;
    spawn.executable = self_path();
    spawn.common_args = {"--suite", f.suite, "--gl", f.gl, "--out", f.out};
    if (f.bless) spawn.common_args.push_back("--bless");
    if (f.bless_cpu) spawn.common_args.push_back("--bless-cpu");
    spawn.out_dir = f.out;
    spawn.timeout_seconds = f.timeout;
    spawn.jobs = f.jobs;

    std::vector<Outcome> outcomes{{suite->find("context"), {}}};
    run_children({"context"}, spawn,
                 [&](std::size_t, const CaseResult& r) { outcomes[0].result = r; });
    Identity id = identity_from(f, outcomes[0].result, *environment, *platform);
    if (outcomes[0].result.status != Status::pass) {
        const bool unsupported = outcomes[0].result.status == Status::not_supported;
        return report(f, id, *suite, outcomes, baseline,
                      unsupported ? kExitNotSupported : kExitRegression);
    }
    if (const std::string why = driver_mismatch(f.driver, id.renderer); !why.empty()) {
        outcomes[0].result.status = Status::fail;
        outcomes[0].result.reason = "refused: " + why;
        report(f, id, *suite, outcomes, baseline, kExitRefused);
        std::fprintf(stderr, "%s: --driver %s: %s\n", kTool, f.driver.c_str(), why.c_str());
        return kExitRefused;
    }
    spawn.common_args.insert(spawn.common_args.end(), {"--device", id.device});

    std::vector<std::string> names;
    for (const Case& c : suite->cases) {
        if (selected(c, f)) names.push_back(c.name);
    }
    std::vector<CaseResult> results(names.size());
    std::size_t finished = 0;
    run_children(names, spawn, [&](std::size_t i, const CaseResult& r) {
        results[i] = r;
        std::printf("[%zu/%zu] %-13s %6.2f s  %s%s%s\n", ++finished, names.size(),
                    status_name(r.status), r.seconds, names[i].c_str(),
                    r.reason.empty() ? "" : ": ", r.reason.c_str());
        std::fflush(stdout);
    });
    for (std::size_t i = 0; i < names.size(); ++i) {
        outcomes.push_back({suite->find(names[i]), results[i]});
    }
    return report(f, id, *suite, outcomes, baseline, kExitOk);
}
