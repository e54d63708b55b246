// aerial-compare: compares two 8-bit images and prints one line of differences in 8-bit steps
// (LSB) and in CIEDE2000 (DESIGN.md §3), optionally writing an image of where they differ.
#include <lcms2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/cli.hpp"
#include "common/compare.hpp"
#include "common/png.hpp"

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
    "Alpha is ignored (composited on black). Exit status: 0 when compared (whatever the\n"
    "differences), 2 on bad input (unreadable file, different sizes, bad flag).";

/// What two images differ by (see kDescription).
struct Differences {
    aerial::tools::LsbDifferences lsb;
    double de2000_mean = 0.0;
};

/// Colour of one pixel of the diff image.
std::array<std::uint8_t, 3> diff_colour(int lsb, const std::uint8_t* a) {
    if (lsb == 0) {
        const auto grey = std::uint8_t((int(a[0]) * 54 + int(a[1]) * 183 + int(a[2]) * 19) / 1024);
        return {grey, grey, grey};
    }
    if (lsb == 1) return {0, 90, 255};
    if (lsb == 2) return {0, 200, 0};
    if (lsb <= 4) return {255, 230, 0};
    if (lsb <= 8) return {255, 128, 0};
    return {255, 0, 0};
}

/// Mean CIEDE2000 of the pixels, both images taken as sRGB.
double mean_de2000(const aerial::tools::Rgb8Image& a, const aerial::tools::Rgb8Image& b) {
    using ProfilePtr = std::unique_ptr<void, cmsBool (*)(cmsHPROFILE)>;
    const ProfilePtr srgb(cmsCreate_sRGBProfile(), &cmsCloseProfile);
    const ProfilePtr lab(cmsCreateLab4Profile(nullptr), &cmsCloseProfile);
    const std::unique_ptr<void, void (*)(cmsHTRANSFORM)> transform(
        cmsCreateTransform(srgb.get(), TYPE_RGB_8, lab.get(), TYPE_Lab_DBL,
                           INTENT_RELATIVE_COLORIMETRIC, cmsFLAGS_NOCACHE),
        &cmsDeleteTransform);
    const std::size_t pixels = a.rgb.size() / 3;
    std::vector<cmsCIELab> lab_a(pixels), lab_b(pixels);
    cmsDoTransform(transform.get(), a.rgb.data(), lab_a.data(), cmsUInt32Number(pixels));
    cmsDoTransform(transform.get(), b.rgb.data(), lab_b.data(), cmsUInt32Number(pixels));
    double sum = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) {
        sum += cmsCIE2000DeltaE(&lab_a[i], &lab_b[i], 1.0, 1.0, 1.0);
    }
    return pixels ? sum / double(pixels) : 0.0;
}

Differences compare(const aerial::tools::Rgb8Image& a, const aerial::tools::Rgb8Image& b,
                    aerial::tools::Rgb8Image* diff) {
    const std::size_t pixels = a.rgb.size() / 3;
    aerial::tools::LsbHistogram histogram;
    if (diff) *diff = {a.width, a.height, std::vector<std::uint8_t>(a.rgb.size())};
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::uint8_t* pa = &a.rgb[3 * i];
        const int lsb = histogram.add(pa, &b.rgb[3 * i]);
        if (diff) {
            const auto colour = diff_colour(lsb, pa);
            std::copy(colour.begin(), colour.end(), &diff->rgb[3 * i]);
        }
    }
    Differences d;
    d.lsb = histogram.differences();
    d.de2000_mean = mean_de2000(a, b);
    return d;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace aerial;
    CLI::App app{kDescription, kTool};
    std::string a_path, b_path, diff_path;
    app.add_option("A", a_path, "First image (PNG)")->required();
    app.add_option("B", b_path, "Second image (PNG)")->required();
    app.add_option("--diff", diff_path, "Write an image of the differences here (PNG)");
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
    const Differences d = compare(*a, *b, diff_path.empty() ? nullptr : &diff);
    if (!diff_path.empty()) {
        if (auto error = tools::write_png(diff_path, diff))
            return tools::fail(kTool, "--diff " + *error);
    }
    std::printf("max_lsb=%d p99_lsb=%d rmse_lsb=%.4f over1=%.6f over2=%.6f de2000_mean=%.4f\n",
                d.lsb.max_lsb, d.lsb.p99_lsb, d.lsb.rmse_lsb, d.lsb.over1, d.lsb.over2,
                d.de2000_mean);
    if (std::fflush(stdout) != 0) return tools::fail(kTool, "cannot write output");
    return 0;
}
