// Differences of two 8-bit images in 8-bit steps (LSB), as aerial-compare prints them, shared by
// aerial-compare and the GL grading of aerial-tess.
//
// How to use this:
//   1. `LsbHistogram h;` then `h.add(a_rgb, b_rgb)` for each pixel compared (3 bytes each).
//   2. `h.differences()` gives max, p99, rmse, over1 and over2 of the pixels added so far.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace aerial::tools {

/// A pixel's difference is the largest of |A - B| over R, G and B. max_lsb and p99_lsb are the
/// largest and the 99th percentile (nearest rank) of those; rmse_lsb is the root mean square over
/// every channel of every pixel; over1 and over2 are the fractions of pixels off by more than 1
/// and 2 steps.
struct LsbDifferences {
    int max_lsb = 0;
    int p99_lsb = 0;
    double rmse_lsb = 0.0;
    double over1 = 0.0;
    double over2 = 0.0;
    std::size_t pixels = 0;
};

/// The largest channel difference of two RGB pixels (3 bytes each), in 8-bit steps.
int pixel_lsb(const std::uint8_t* a, const std::uint8_t* b);

class LsbHistogram {
  public:
    /// Adds one pixel pair (RGB, 3 bytes each); returns its difference (pixel_lsb).
    int add(const std::uint8_t* a, const std::uint8_t* b);
    /// Adds the pixels of another histogram.
    void merge(const LsbHistogram& other);
    LsbDifferences differences() const;
    std::size_t pixels() const { return pixels_; }

  private:
    std::array<std::size_t, 256> histogram_{};
    double sum_squares_ = 0.0;
    std::size_t pixels_ = 0;
};

}  // namespace aerial::tools
