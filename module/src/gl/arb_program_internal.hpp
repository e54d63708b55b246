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

/// d.w = 2^-20 exactly (hoffman-preetham: vertex.w - eye.w, eye.w = 1 - 2^-20; height: 0 - eye.w,
/// eye.w = -2^-20): the DP4 of d with
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

/// One vector of a program's per-frame layout: the name the program text declares it by
/// (`PARAM name = program.local[...]`) and its meaning. Each model's file holds its table; the
/// table is the source of truth for the declarations, the counts and arb_parameter_layout.
struct ParameterRow {
    const char* name;
    const char* meaning;
};

/// The 3 vectors after a program's frame parameters when ArbProgramOptions::model_matrix is on.
inline constexpr int kModelMatrixRows = 3;

/// The frame's layout (relative indices), then the model-matrix rows when o.model_matrix is on.
std::vector<ParameterRow> parameter_layout(const ArbProgramOptions& o, ArbHeightFidelity fidelity);

/// `PARAM name = parameter;  # meaning` for every row of parameter_layout.
void write_parameter_declarations(ProgramWriter& w, const ArbProgramOptions& o,
                                  ArbHeightFidelity fidelity);

/// The segment from the eye to the vertex into `reg`: `reg = world * scale - eye` (a MAD of
/// vertex.position) or, with the model matrix, the world position M * vertex.position by three
/// DP4 first. The caller's scale and eye give reg.w (`scale` empty: a SUB, w from pos.w).
void write_world_segment(ProgramWriter& w, const ArbProgramOptions& o, const std::string& reg,
                         const std::string& scale, const std::string& comment);

/// The four DP4 of the clip-space position, unless the program is position-invariant.
void write_clip_space_position(ProgramWriter& w, const ArbProgramOptions& o);

/// The texture coordinates passed through unchanged, then END.
void write_texcoords_and_end(ProgramWriter& w, const ArbProgramOptions& o);

/// The parameters rounded to float; an error names the first one out of float range.
Result<std::vector<std::array<float, 4>>> to_float_parameters(
    const std::vector<std::array<double, 4>>& p);

/// The frame layouts of each model (relative indices).
std::vector<ParameterRow> hoffman_preetham_layout();
std::vector<ParameterRow> height_layout(ArbHeightFidelity fidelity);

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
