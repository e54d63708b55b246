// How much of its seeded sweeps a long test runs: AERIAL_TEST_SCALE, a fraction in (0, 1]
// (default 1, the whole sweep). The sanitizer stage of `tools/aerial.sh test` sets 0.05, where
// every operation costs about ten times more; the sweeps keep their seeds, so a scaled run checks
// the first cases of the full one. A test that scales prints how many cases it ran.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

namespace aerial::testing {

/// AERIAL_TEST_SCALE, or 1 when unset; a value that is not a number in (0, 1] fails the test
/// that asks (so that a typo never shrinks a sweep silently).
inline double test_scale() {
    const char* text = std::getenv("AERIAL_TEST_SCALE");
    if (text == nullptr || *text == '\0') return 1.0;
    char* end = nullptr;
    const double scale = std::strtod(text, &end);
    if (*end != '\0' || !(scale > 0.0 && scale <= 1.0)) {
        ADD_FAILURE() << "AERIAL_TEST_SCALE: expected a number in (0, 1], got '" << text << "'";
        return 1.0;
    }
    return scale;
}

/// `full` cases scaled by test_scale(), at least 1; prints the count when it is scaled.
inline int scaled_count(int full, const char* what) {
    const double scale = test_scale();
    const int count = std::max(1, int(std::lround(full * scale)));
    if (count != full) {
        std::printf("AERIAL_TEST_SCALE=%g: %d of %d %s\n", scale, count, full, what);
    }
    return count;
}

/// Which cases of a grid a scaled run keeps: every round(1 / test_scale())-th in the order the
/// test visits them, so that the kept ones spread over the whole grid (every preset, eye, sun
/// and exposure); all of them at scale 1. Prints what it kept when it is destroyed.
class GridSample {
  public:
    explicit GridSample(const char* what)
        : what_(what), stride_(std::max(1L, std::lround(1.0 / test_scale()))) {}
    GridSample(const GridSample&) = delete;
    GridSample& operator=(const GridSample&) = delete;
    ~GridSample() {
        if (stride_ > 1) {
            std::printf("AERIAL_TEST_SCALE: %ld of %ld %s (every %ld-th)\n", kept_, seen_, what_,
                        stride_);
        }
    }
    bool keep() {
        const bool kept = seen_++ % stride_ == 0;
        kept_ += kept ? 1 : 0;
        return kept;
    }

  private:
    const char* what_;
    long stride_;
    long seen_ = 0;
    long kept_ = 0;
};

}  // namespace aerial::testing
