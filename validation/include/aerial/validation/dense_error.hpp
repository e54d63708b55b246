// aerial/validation/dense_error.hpp — a dense measure of the colour a mesh shows against the
// exact per-pixel colour, which the tools and tests grade meshes with (aerial::validation;
// engines do not link it).
#pragma once

#include "aerial/error.hpp"
#include "aerial/mesh.hpp"
#include "aerial/scattering.hpp"
#include "aerial/validation/lsb_figures.hpp"

namespace aerial::validation {

/// An independent, dense measure of what a mesh shows against the exact per-pixel colour: every
/// face sampled on a barycentric grid whose spacing, seen from the eye, is at most
/// `spacing_rad` (at least the edge midpoints; at most `max_per_edge` per edge). Samples weigh
/// alike. Deleted faces are skipped. One error is a sample's largest channel difference between
/// the interpolated vertex colours and the exact colour there; `count` is the samples, rmse_lsb
/// is over them and p99_lsb is binned at 1/64 step.
using DenseError = LsbFigures<double>;
Result<DenseError> dense_error(const aerial::mesh::Mesh& mesh, const Frame<float>& frame,
                               const aerial::mesh::ColourOptions& options, double spacing_rad,
                               int max_per_edge = 96);

}  // namespace aerial::validation
