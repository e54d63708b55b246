// aerial/validation/dense_error.hpp — a dense measure of the colour a mesh shows against the
// exact per-pixel colour, which the tools and tests grade meshes with (aerial::validation;
// engines do not link it).
#pragma once

#include <cstddef>

#include "aerial/error.hpp"
#include "aerial/mesh.hpp"
#include "aerial/scattering.hpp"

namespace aerial::validation {

/// An independent, dense measure of what a mesh shows against the exact per-pixel colour: every
/// face sampled on a barycentric grid whose spacing, seen from the eye, is at most
/// `spacing_rad` (at least the edge midpoints; at most `max_per_edge` per edge). Samples weigh
/// alike. Deleted faces are skipped.
struct DenseError {
    double max_lsb = 0.0;
    double p99_lsb = 0.0;
    double rmse_lsb = 0.0;
    double over1 = 0.0;  ///< fraction of samples off by more than 1 step
    double over2 = 0.0;  ///< ... by more than 2 steps
    std::size_t samples = 0;
};
Result<DenseError> dense_error(const aerial::mesh::Mesh& mesh, const Frame<float>& frame,
                               const aerial::mesh::ColourOptions& options, double spacing_rad,
                               int max_per_edge = 96);

}  // namespace aerial::validation
