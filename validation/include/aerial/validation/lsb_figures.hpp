// aerial/validation/lsb_figures.hpp — the figures a set of colour errors in 8-bit steps (LSB) is
// summed up by. One struct for both measures that give them: aerial::validation::dense_error (a
// mesh against the exact per-pixel colour, DenseError) and the tools' image comparison (two
// images, aerial::tools::LsbDifferences; a mesh's image, MeshGrader) and the histogram they are
// counted in. Header only: the tools' image metrics use it without linking aerial::validation.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

namespace aerial::validation {

/// `Step` is int where the errors are differences of 8-bit values, double where they are
/// measured in fractions of a step. Each measure says what one error is and what rmse_lsb is
/// taken over.
template <typename Step>
struct LsbFigures {
    Step max_lsb = 0;
    Step p99_lsb = 0;       ///< the 99th percentile (nearest rank)
    double rmse_lsb = 0.0;  ///< root mean square
    double over1 = 0.0;     ///< fraction of the errors above 1 step
    double over2 = 0.0;     ///< ... above 2 steps
    std::size_t count = 0;  ///< errors measured (pixels, samples)
};

/// The largest channel difference of two RGB pixels (3 bytes each), in 8-bit steps.
inline int pixel_lsb(const std::uint8_t* a, const std::uint8_t* b) {
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a[c]) - int(b[c])));
    return d;
}

/// Pixel pairs counted by their difference: LsbFigures<int> of every pixel added.
class LsbHistogram {
  public:
    /// Adds one pixel pair (RGB, 3 bytes each); returns its difference (pixel_lsb).
    int add(const std::uint8_t* a, const std::uint8_t* b) {
        const int lsb = pixel_lsb(a, b);
        ++histogram_[std::size_t(lsb)];
        for (int c = 0; c < 3; ++c) {
            const double d = double(a[c]) - double(b[c]);
            sum_squares_ += d * d;
        }
        ++pixels_;
        return lsb;
    }
    /// Adds the pixels of another histogram.
    void merge(const LsbHistogram& other) {
        for (std::size_t v = 0; v < histogram_.size(); ++v) histogram_[v] += other.histogram_[v];
        sum_squares_ += other.sum_squares_;
        pixels_ += other.pixels_;
    }
    /// max and p99 (nearest rank) of the pixels' differences, RMSE over every channel, the shares
    /// of pixels more than 1 and 2 steps off, the pixel count.
    LsbFigures<int> differences() const {
        LsbFigures<int> d;
        d.count = pixels_;
        std::size_t below = 0, over1 = 0, over2 = 0;
        bool p99_found = false;
        for (int v = 0; v < 256; ++v) {
            const std::size_t n = histogram_[std::size_t(v)];
            if (n > 0) d.max_lsb = v;
            below += n;
            if (!p99_found && double(below) >= 0.99 * double(pixels_)) {
                d.p99_lsb = v;
                p99_found = true;
            }
            if (v > 1) over1 += n;
            if (v > 2) over2 += n;
        }
        const double n = double(std::max<std::size_t>(pixels_, 1));
        d.rmse_lsb = std::sqrt(sum_squares_ / (3.0 * n));
        d.over1 = double(over1) / n;
        d.over2 = double(over2) / n;
        return d;
    }
    std::size_t pixels() const { return pixels_; }

  private:
    std::array<std::size_t, 256> histogram_{};
    double sum_squares_ = 0.0;
    std::size_t pixels_ = 0;
};

}  // namespace aerial::validation
