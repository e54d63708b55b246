// aerial/validation/lsb_figures.hpp — the figures a set of colour errors in 8-bit steps (LSB) is
// summed up by. One struct for both measures that give them: aerial::validation::dense_error (a
// mesh against the exact per-pixel colour, DenseError) and the tools' image comparison (two
// images, aerial::tools::LsbDifferences). Header only: the tools' image metrics use it without
// linking aerial::validation.
#pragma once

#include <cstddef>

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

}  // namespace aerial::validation
