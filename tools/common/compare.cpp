#include "common/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace aerial::tools {

int pixel_lsb(const std::uint8_t* a, const std::uint8_t* b) {
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a[c]) - int(b[c])));
    return d;
}

int LsbHistogram::add(const std::uint8_t* a, const std::uint8_t* b) {
    const int lsb = pixel_lsb(a, b);
    ++histogram_[std::size_t(lsb)];
    for (int c = 0; c < 3; ++c) {
        const double d = double(a[c]) - double(b[c]);
        sum_squares_ += d * d;
    }
    ++pixels_;
    return lsb;
}

void LsbHistogram::merge(const LsbHistogram& other) {
    for (std::size_t v = 0; v < histogram_.size(); ++v) histogram_[v] += other.histogram_[v];
    sum_squares_ += other.sum_squares_;
    pixels_ += other.pixels_;
}

LsbDifferences LsbHistogram::differences() const {
    LsbDifferences d;
    d.pixels = pixels_;
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

}  // namespace aerial::tools
