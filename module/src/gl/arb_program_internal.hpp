// Internal: what the ARB program generators share (arb_program.cpp: options, dispatch and the
// public functions; arb_program_hoffman_preetham.cpp and arb_program_height.cpp: each model's
// program text and parameters). Nothing here calls GL.
#pragma once

#include <array>
#include <sstream>
#include <string>
#include <vector>

#include "aerial/arb_program.hpp"

namespace aerial::detail::arb {

/// d.w = vertex.w - eye.w = 2^-20 exactly (eye.w = 1 - 2^-20 is a float): the DP4 of d with
/// itself adds 2^-40 square units to s^2, so that RSQ never sees 0 (a vertex at the eye).
inline constexpr double kEpsilon = 1.0 / 1048576.0;
inline constexpr double kLog2E = 1.44269504088896340736;

/// A float constant for program text: 9 significant digits (round-trips a float), '.' as the
/// decimal point whatever the C locale says.
std::string format_float(double value);

/// "{ a, b, c, d }" of format_float.
std::string format_float4(double a, double b, double c, double d);

/// Writes one line of program text: the statement, then its comment from column 44.
class ProgramWriter {
  public:
    void comment(const std::string& text) { out_ << "# " << text << '\n'; }
    void line(const std::string& statement, const std::string& comment = {}) {
        out_ << statement;
        if (!comment.empty()) {
            const std::size_t pad = statement.size() < 43 ? 43 - statement.size() : 1;
            out_ << std::string(pad, ' ') << "# " << comment;
        }
        out_ << '\n';
    }
    std::string str() const { return out_.str(); }

  private:
    std::ostringstream out_;
};

/// "program.local[base + i]" or "program.env[base + i]": parameter i of the options' layout.
std::string parameter_name(const ArbProgramOptions& o, int i);

/// The four DP4 of the clip-space position, unless the program is position-invariant.
void write_clip_space_position(ProgramWriter& w, const ArbProgramOptions& o);

/// The texture coordinates passed through unchanged, then END.
void write_texcoords_and_end(ProgramWriter& w, const ArbProgramOptions& o);

/// The parameters rounded to float; an error names the first one out of float range.
Result<std::vector<std::array<float, 4>>> to_float_parameters(
    const std::vector<std::array<double, 4>>& p);

/// The hoffman-preetham program (arb_program_hoffman_preetham.cpp).
std::string hoffman_preetham_program_text(const ArbProgramOptions& o);
Result<std::vector<std::array<float, 4>>> hoffman_preetham_parameters(const Frame<float>& frame,
                                                                      const Display& display);

/// The height program at a resolved fidelity (arb_program_height.cpp).
std::string height_program_text(const ArbProgramOptions& o, ArbHeightFidelity fidelity);
Result<std::vector<std::array<float, 4>>> height_parameters(const Frame<float>& frame,
                                                            const Display& display,
                                                            ArbHeightFidelity fidelity);

}  // namespace aerial::detail::arb
