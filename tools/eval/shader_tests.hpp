// aerial-eval's ARB program options and its export of the generated programs as piglit
// shader_test files (aerial-eval --export-shader-tests DIR; docs/arb-program.md, "piglit
// shader_test files").
//
// How to use this:
//   1. `arb_program_options(model, fidelity)` gives the options --print-arb-program generates
//      with (the same for the export, so the exported text is what --print-arb-program prints).
//   2. `export_shader_tests(dir)` writes one .shader_test file per program and frame and returns
//      their names. The expectations come from aerial::validation's CPU executor of the same text.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "aerial/arb_program.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"

namespace aerial::eval {

/// The options of `aerial-eval --print-arb-program [--model M] [--arb-height-fidelity F]`:
/// program.local[0...], one texture unit, not position-invariant; the height levels beyond
/// spec_minimum are checked against 256 instructions (Direct3D 9-class hardware) instead of 128.
ArbProgramOptions arb_program_options(Model model, std::optional<ArbHeightFidelity> fidelity);

/// The window, in pixels; `ortho 0 250 0 250` makes world x, y the pixel coordinates.
inline constexpr int kShaderTestSize = 250;
/// Each channel of a probe passes within this of the expectation: 1.5 steps of 8 bits, so that
/// the 8-bit value the driver writes is within one step of the rounded expectation.
inline constexpr double kShaderTestTolerance = 1.5 / 255.0;

/// Writes the files into `dir` (created if missing): for hoffman-preetham and each height
/// fidelity level, for the frames earth and hazy at noon and at a low sun. Returns the file
/// names in the order written. The error names "--export-shader-tests" and the path.
Result<std::vector<std::string>> export_shader_tests(const std::string& dir);

}  // namespace aerial::eval
