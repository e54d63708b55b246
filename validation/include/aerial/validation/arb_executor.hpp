// aerial/validation/arb_executor.hpp — a CPU executor of ARB vertex program text, for tests and
// tools (aerial::validation; engines do not link it).
//
// `parse_arb_program(text)` then `run_arb_program(...)` execute a program (the text of
// aerial::generate_arb_program) on the CPU in float, optionally with the approximate
// instructions (EX2, RSQ, POW, ...) perturbed the way old hardware computes them.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "aerial/arb_program.hpp"
#include "aerial/error.hpp"

namespace aerial::detail {
struct ArbCpuProgramData;  // the parsed instructions and bindings (module/src/gl/arb_parser.hpp)
}  // namespace aerial::detail

namespace aerial::validation {

/// A program parsed for run_arb_program: the subset of ARB_vertex_program 1.0 that
/// generate_arb_program emits, plus the other scalar instructions. Supported: OPTION
/// ARB_position_invariant; ATTRIB (vertex.position, vertex.texcoord[n]); PARAM (program.local[i],
/// program.env[i], state.matrix.mvp[.row[i]], constants); TEMP; OUTPUT (result.position,
/// result.color[.primary|.secondary], result.fogcoord, result.texcoord[n]); the instructions
/// MOV ADD SUB MUL MAD DP3 DP4 DPH MIN MAX SGE SLT SWZ EX2 LG2 EXP LOG RCP RSQ POW with swizzles,
/// write masks and negation; `#` comments. Anything else (ARL, ALIAS, LIT, ...) is a parse error.
struct ArbCpuProgram {
    std::shared_ptr<const detail::ArbCpuProgramData> data;  ///< the parsed instructions
    ArbResources resources;
    bool position_invariant = false;
};

/// Parses program text. Errors: field "line N", message
/// "aerial::validation::parse_arb_program(): line N: column C: what is wrong".
Result<ArbCpuProgram> parse_arb_program(std::string_view text);

/// The GL state a program reads. Parameters the vectors do not hold read as NaN (GL would give
/// 0 or a stale value), so that a missing upload shows in the results.
struct ArbMachine {
    std::vector<std::array<float, 4>> local;  ///< program.local[i]
    std::vector<std::array<float, 4>> env;    ///< program.env[i]
    /// state.matrix.mvp, row-major: clip = rows * position. Identity by default.
    std::array<std::array<float, 4>, 4> mvp{
        {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
};

/// One vertex's attributes.
struct ArbVertex {
    std::array<float, 4> position{0, 0, 0, 1};
    std::array<std::array<float, 4>, kArbMaxTexcoordUnits> texcoord{};
};

/// One result register: its value and which components the program wrote (bit i = component i;
/// unwritten components are NaN).
struct ArbOutput {
    std::array<float, 4> value{};
    unsigned written = 0;
};

/// The results of one run, before GL clamps the colours.
struct ArbResults {
    ArbOutput position;  ///< clip coordinates (unwritten with ARB_position_invariant)
    ArbOutput color_primary;
    ArbOutput color_secondary;
    ArbOutput fogcoord;
    std::array<ArbOutput, kArbMaxTexcoordUnits> texcoord;
};

/// Instructions whose results are approximations in the spec (bit mask).
enum ArbApprox : unsigned {
    kArbApproxEx2 = 1u << 0,
    kArbApproxLg2 = 1u << 1,
    kArbApproxExp = 1u << 2,  ///< the z component (x and y are exact in the spec)
    kArbApproxLog = 1u << 3,  ///< the z component
    kArbApproxRcp = 1u << 4,
    kArbApproxRsq = 1u << 5,
    kArbApproxPow = 1u << 6,
    kArbApproxAll = 0x7fu,
};

/// Models hardware whose approximate instructions are less precise than float: the n-th
/// approximate instruction of the program (counting those in `perturbed`, in program order, from
/// 0) has its result multiplied by 1 + relative_error if bit (n mod 32) of sign_pattern is set,
/// else by 1 - relative_error. LG2 and LOG.z, whose error the spec states in log2 units, get
/// +-relative_error added instead. relative_error = 2^-11 models the ~10-11 bits the spec
/// promises for EXP/LOG. Deterministic: the same pattern gives the same results.
struct ArbInterpreterOptions {
    float relative_error = 0.0f;
    std::uint32_t sign_pattern = 0;
    unsigned perturbed = kArbApproxAll;
};

/// Runs the program on one vertex in float, instruction by instruction as the spec defines them.
/// Temporaries start as NaN (the spec leaves them undefined).
ArbResults run_arb_program(const ArbCpuProgram& program, const ArbMachine& machine,
                           const ArbVertex& vertex, const ArbInterpreterOptions& options = {});

/// The number of approximate instructions (of the kinds in `perturbed`) the program executes:
/// the sign patterns 0 .. 2^n - 1 cover every combination of signs.
int count_approximate_instructions(const ArbCpuProgram& program,
                                   unsigned perturbed = kArbApproxAll);

}  // namespace aerial::validation
