// aerial-compare: compares two 8-bit images and prints one line of differences in 8-bit steps
// (LSB) and in CIEDE2000 (docs/conventions.md, Interfaces), optionally writing an image of where
// they differ.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "common/image_metrics.hpp"
#include "support/cli.hpp"
#include "support/png.hpp"

namespace {

constexpr const char* kTool = "aerial-compare";

constexpr const char* kDescription =
    "Compares two PNG images of the same size and prints one line:\n"
    "  max_lsb=… p99_lsb=… rmse_lsb=… over1=… over2=… de2000_mean=…\n"
    "A pixel's difference is the largest of |A - B| over R, G and B, in 8-bit steps (LSB).\n"
    "max_lsb and p99_lsb are the largest and the 99th percentile (nearest rank) of those;\n"
    "rmse_lsb is the root mean square over every channel of every pixel; over1 and over2 are the\n"
    "fractions of pixels off by more than 1 and 2 steps; de2000_mean is the mean CIEDE2000\n"
    "difference (lcms2) with both images read as sRGB and converted to CIELAB (D50).\n"
    "--diff writes a PNG of the differences: equal pixels show A dimmed to a quarter in grey;\n"
    "others are blue (1 step), green (2), yellow (3-4), orange (5-8) or red (more than 8).\n"
    "--max-lsb, --p99-lsb, --max-over1 and --max-over2 bound max_lsb, p99_lsb, over1 and over2:\n"
    "a bound exceeded is named on stderr and the exit status is 1.\n"
    "Alpha is ignored (composited on black). Exit status: 0 when compared (and within every\n"
    "bound given), 1 when a bound is exceeded, 2 on bad input (unreadable file, different sizes,\n"
    "bad flag).";

/// Exit status when a bound given on the command line is exceeded.
constexpr int kExitOverBound = 1;

}  // namespace

int main(int argc, char** argv) {
    using namespace aerial;
    CLI::App app{kDescription, kTool};
    std::string a_path, b_path, diff_path;
    app.add_option("A", a_path, "First image (PNG)")->required();
    app.add_option("B", b_path, "Second image (PNG)")->required();
    app.add_option("--diff", diff_path, "Write an image of the differences here (PNG)");
    tools::LsbTolerance bounds;
    app.add_option("--max-lsb", bounds.max_lsb, "Exit 1 when max_lsb is above this")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--p99-lsb", bounds.p99_lsb, "Exit 1 when p99_lsb is above this")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--max-over1", bounds.max_over1,
                   "Exit 1 when the fraction of pixels off by more than 1 step is above this")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--max-over2", bounds.max_over2,
                   "Exit 1 when the fraction of pixels off by more than 2 steps is above this")
        ->check(CLI::Range(0.0, 1.0));
    if (auto status = tools::parse_command_line(app, argc, argv, kTool)) return *status;

    const auto a = tools::read_png(a_path);
    if (!a) return tools::fail(kTool, "A: " + a.error().message);
    const auto b = tools::read_png(b_path);
    if (!b) return tools::fail(kTool, "B: " + b.error().message);
    if (a->width != b->width || a->height != b->height) {
        return tools::fail(kTool, "B: " + b_path + " is " + std::to_string(b->width) + "x" +
                                      std::to_string(b->height) + ", A: " + a_path + " is " +
                                      std::to_string(a->width) + "x" + std::to_string(a->height) +
                                      "; the sizes must be equal");
    }
    tools::Rgb8Image diff;
    const tools::ImageDifferences d =
        tools::compare_images(*a, *b, diff_path.empty() ? nullptr : &diff);
    if (!diff_path.empty()) {
        if (auto error = tools::write_png(diff_path, diff))
            return tools::fail(kTool, "--diff " + *error);
    }
    std::printf("max_lsb=%d p99_lsb=%d rmse_lsb=%.4f over1=%.6f over2=%.6f de2000_mean=%.4f\n",
                d.max_lsb, d.p99_lsb, d.rmse_lsb, d.over1, d.over2, d.de2000_mean);
    if (std::fflush(stdout) != 0) return tools::fail(kTool, "cannot write output");
    const std::string over = bounds.violations(d);
    if (!over.empty()) {
        std::fprintf(stderr, "%s: over the bounds (%s): %s\n", kTool, bounds.text().c_str(),
                     over.c_str());
        return kExitOverBound;
    }
    return 0;
}
