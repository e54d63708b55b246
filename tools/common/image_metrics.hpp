// Differences of two 8-bit RGB images in 8-bit steps (LSB) and in CIEDE2000: the figures
// aerial-compare prints and aerial-bench writes, computed in one place.
//
// How to use this:
//   1. `auto d = aerial::tools::compare_images(a, b);` (same size; aerial::tools::Rgb8Image).
//   2. Pass a non-null `diff` to also get an image of where they differ (see diff_colour).
//   3. For a subset of pixels: `LsbHistogram h;` then `h.add(a_rgb, b_rgb)` per pixel, and
//      `h.differences()`.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "aerial/validation/lsb_figures.hpp"
#include "support/png.hpp"

namespace aerial::tools {

/// A pixel's difference is the largest of |A - B| over R, G and B. max_lsb and p99_lsb are the
/// largest and the 99th percentile (nearest rank) of those; rmse_lsb is the root mean square over
/// every channel of every pixel; over1 and over2 are the fractions of pixels off by more than 1
/// and 2 steps; `count` is the pixels. (The figures of aerial::validation::dense_error too.)
using LsbDifferences = validation::LsbFigures<int>;

/// The largest channel difference of two RGB pixels, and the histogram of such differences
/// (aerial/validation/lsb_figures.hpp).
using validation::LsbHistogram;
using validation::pixel_lsb;

/// What two images differ by: the LSB figures (LsbDifferences, over every pixel) and the mean
/// CIEDE2000 (lcms2), both images read as sRGB, CIELAB D50.
struct ImageDifferences : LsbDifferences {
    double de2000_mean = 0.0;
};

/// Bounds on LsbDifferences (aerial-compare's flags, the regression suite's tolerances): each
/// bound given is checked, the others are not.
struct LsbTolerance {
    std::optional<int> max_lsb, p99_lsb;         ///< at most
    std::optional<int> min_p99_lsb;              ///< at least (an image that must differ visibly)
    std::optional<double> max_over1, max_over2;  ///< fractions of the pixels, at most

    /// Empty when `d` is within every bound; otherwise the bounds exceeded,
    /// "max_lsb 3 > 2, over1 0.002 > 0.001".
    std::string violations(const LsbDifferences& d) const;
    /// "max_lsb<=2 max_over1<=0.001".
    std::string text() const;
};

/// Colour of one pixel of the diff image: equal pixels show A dimmed to a quarter in grey;
/// others are blue (1 step), green (2), yellow (3-4), orange (5-8) or red (more than 8).
std::array<std::uint8_t, 3> diff_colour(int lsb, const std::uint8_t* a);

/// The differences of two images of the same size (the caller checks the sizes); with `diff`,
/// also the diff image.
ImageDifferences compare_images(const Rgb8Image& a, const Rgb8Image& b, Rgb8Image* diff = nullptr);

}  // namespace aerial::tools
