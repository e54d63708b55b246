// Differences of two 8-bit RGB images in 8-bit steps (LSB) and in CIEDE2000: the figures
// aerial-compare prints and aerial-bench writes, computed in one place.
//
// How to use this:
//   1. `auto d = aerial::tools::compare_images(a, b);` (same size; aerial::tools::Rgb8Image).
//   2. Pass a non-null `diff` to also get an image of where they differ (see diff_colour).
#pragma once

#include <array>
#include <cstdint>

#include "common/png.hpp"

namespace aerial::tools {

/// What two images differ by. A pixel's difference is the largest of |A - B| over R, G and B.
struct ImageDifferences {
    int max_lsb = 0;           ///< largest pixel difference
    int p99_lsb = 0;           ///< 99th percentile (nearest rank) of the pixel differences
    double rmse_lsb = 0.0;     ///< root mean square over every channel of every pixel
    double over1 = 0.0;        ///< fraction of pixels off by more than 1 step
    double over2 = 0.0;        ///< ... by more than 2 steps
    double de2000_mean = 0.0;  ///< mean CIEDE2000 (lcms2), both read as sRGB, CIELAB D50
};

/// Colour of one pixel of the diff image: equal pixels show A dimmed to a quarter in grey;
/// others are blue (1 step), green (2), yellow (3-4), orange (5-8) or red (more than 8).
std::array<std::uint8_t, 3> diff_colour(int lsb, const std::uint8_t* a);

/// The differences of two images of the same size (the caller checks the sizes); with `diff`,
/// also the diff image.
ImageDifferences compare_images(const Rgb8Image& a, const Rgb8Image& b, Rgb8Image* diff = nullptr);

}  // namespace aerial::tools
