// aerial/arb_program.hpp — the hoffman-preetham and height models as ARB vertex programs
// (`!!ARBvp1.0` text) and their per-frame parameters. Nothing here calls GL.
//
// How to use this:
//   1. Once: `auto program = aerial::generate_arb_program(options);` and hand `program->text` as
//      it is to glProgramStringARB(GL_VERTEX_PROGRAM_ARB, GL_PROGRAM_FORMAT_ASCII_ARB, ...).
//   2. Per frame: `auto frame = aerial::prepare_frame<float>(atmosphere, view, options.model);`
//      then `auto p = aerial::arb_program_parameters(*frame, display, options);` and upload p[i]
//      (arb_parameter_count(options) vectors) to program.local[options.parameter_base + i]
//      (glProgramLocalParameter4fvARB) or program.env[...] (glProgramEnvParameter4fvARB).
//   3. Draw with the program bound and enabled, texture env MODULATE and GL_COLOR_SUM on: the
//      primary colour is F_ex (it modulates the texture), the secondary colour is L_in with the
//      exposure applied (it is added; GL clamps it to [0, 1]), the fog coordinate is the
//      distance eye -> vertex in engine units.
// A CPU executor of the text (for tests and tools, not for engines) is in aerial::validation
// (aerial/validation/arb_executor.hpp).
//
// Vertex positions are read from vertex.position as world positions in engine units (what
// aerial::scatter takes), and vertex.position.w must be 1 (glVertex3*, 3-component arrays). With
// ArbProgramOptions::model_matrix they are model-space positions and the program reads the
// model matrix's top rows per draw (arb_model_matrix_parameters).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "aerial/batch.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"

namespace aerial {

// ---- Generator -------------------------------------------------------------------------------

/// Where the program reads its per-frame parameters from.
enum class ParameterSpace {
    local,  ///< program.local[i]: belongs to the program object (what Irrlicht and Ogre write)
    env,    ///< program.env[i]: shared by every vertex program of the context
};

/// Resource limits of ARB_vertex_program. The defaults are the spec's minimums, which every
/// implementation meets; pass a driver's MAX_PROGRAM_NATIVE_* values to check against those.
struct ArbLimits {
    int max_instructions = 128;  ///< MAX_PROGRAM_INSTRUCTIONS_ARB (minus 4 if position-invariant)
    int max_temporaries = 12;    ///< MAX_PROGRAM_TEMPORARIES_ARB
    int max_parameters = 96;     ///< MAX_PROGRAM_PARAMETERS_ARB, and the local/env index range
    int max_attributes = 16;     ///< MAX_PROGRAM_ATTRIBS_ARB
};

/// Largest texture-coordinate set passed through (MAX_TEXTURE_COORDS of the hardware era).
inline constexpr int kArbMaxTexcoordUnits = 8;

/// How much of the CPU `height` model the height program computes. Each level is a different
/// program with its own parameter count; docs/arb-program.md gives the measured error
/// of each against the CPU model.
enum class ArbHeightFidelity {
    /// The highest of the levels below whose program fits ArbProgramOptions::limits (the spec
    /// minimums by default: spec_minimum; a driver's native limits via aerial::gl::
    /// native_arb_limits). generate_arb_program reports the level it chose in
    /// ArbProgram::options.
    automatic,
    /// 125 instructions (with one texture unit; 128 with model_matrix), 11 temporaries: within
    /// the spec minimums of 128 instructions and 12 temporaries. Leaves out parts of the model
    /// (listed at kArbHeightParameterCount).
    spec_minimum,
    /// spec_minimum plus the weights' correction by the exact optical depth, each channel's own
    /// attenuation to the sunlight points (and phi from its series near 0): 159 instructions.
    exact_optical_depth,
    /// All of the CPU model's single scattering: exact_optical_depth plus the sun's column
    /// factors at the vertex (an erfcx fit and the below-horizon branch) interpolated along the
    /// segment as the model does, the planet's shadow per sunlight point and the eye's or the
    /// vertex's blocked sun: 245 instructions (248 with model_matrix), 12 temporaries and
    /// kArbHeightFullParameterCount parameters: within 1 LSB of the CPU model without its
    /// higher orders (Frame::multiple_scattering reset). Needs a driver whose
    /// MAX_PROGRAM_NATIVE_INSTRUCTIONS is at least that (256 on Direct3D 9-class hardware;
    /// Mesa's are far larger).
    full,
    /// All of the CPU model: full plus the light scattered more than once (the frame's slice as
    /// parameter arrays read through the address register): 424 instructions (427 with
    /// model_matrix), 23 temporaries, kArbHeightMultipleParameterCount parameters: within 1 LSB
    /// of the CPU model at all but 0.001 % of the test grid's vertices (2 LSB there). Mesa's
    /// limits (2048 parameters) hold it; hardware limited to 256 instructions or parameters
    /// runs `full`.
    multiple_scattering,
};

/// The limits a level is checked against where no driver is at hand (aerial-eval, the piglit
/// files, the tests): the spec minimums for spec_minimum (and automatic), the native limits of
/// Direct3D 9-class hardware (256 instructions) for exact_optical_depth and full, and 512
/// instructions, 32 temporaries and 2048 parameters (Mesa's parameters) for
/// multiple_scattering.
ArbLimits arb_reference_limits(ArbHeightFidelity fidelity);

/// "automatic", "spec-minimum", "exact-optical-depth", "full" or "multiple-scattering".
const char* arb_height_fidelity_name(ArbHeightFidelity fidelity);
/// The inverse of arb_height_fidelity_name; an error names the field "height_fidelity" and lists
/// the known names.
Result<ArbHeightFidelity> parse_arb_height_fidelity(std::string_view name);

/// Options of generate_arb_program and arb_program_parameters (use the same for both).
struct ArbProgramOptions {
    /// hoffman_preetham (22 instructions) or height (125 to 424 by height_fidelity).
    /// `reference` has no program.
    Model model = Model::hoffman_preetham;
    ParameterSpace parameter_space = ParameterSpace::local;
    int parameter_base = 0;  ///< index of the first parameter, >= 0
    /// Texture units whose coordinates are copied unchanged to the rasteriser (units 0 .. n-1),
    /// 0 .. kArbMaxTexcoordUnits (the height program fits the spec minimum of 128 instructions
    /// with at most 2). Outputs a program does not write are undefined.
    int texcoord_units = 1;
    /// `OPTION ARB_position_invariant`: GL transforms the position exactly as the fixed pipeline
    /// does (needed when passes with and without the program are mixed); saves 4 instructions.
    bool position_invariant = false;
    /// For hardware whose EX2 is only ~11 bits accurate: L_in = lin (1 - F_ex) cancels where F_ex
    /// is close to 1, so such an EX2 would put an error of 2^-11 lin into L_in (lin: the haze at
    /// infinity, many times display white towards a bright Mie lobe). The guard clamps F_ex
    /// between its series bounds 1 - tau + tau^2/2 - tau^3/6 <= F_ex <= 1 - tau + tau^2/2, which
    /// keeps L_in within 1 LSB at any exposure. Costs 7 instructions (29 by default); not
    /// needed where EX2 is full precision (Mesa computes it in float; Direct3D asks 21 bits of
    /// the vertex-shader exp that the same hardware runs). hoffman-preetham only; the height
    /// program ignores it.
    bool guard_coarse_ex2 = false;
    /// height only: how much of the CPU height model the program computes (see
    /// ArbHeightFidelity). `automatic` takes the highest level whose program fits `limits`.
    ArbHeightFidelity height_fidelity = ArbHeightFidelity::automatic;
    /// vertex.position is in model space: the program takes the world position as M *
    /// vertex.position from the 3 top rows of a per-draw model matrix, the 3 parameter vectors
    /// at arb_model_matrix_parameter_index (right after the frame's); the clip-space position
    /// still comes from state.matrix.mvp and vertex.position (the engine's modelview holds M).
    /// Costs 4 instructions in hoffman-preetham (26), 3 in height.
    bool model_matrix = false;
    ArbLimits limits;  ///< checked by generate_arb_program
};

/// How many frame parameter vectors the hoffman-preetham program reads (from parameter_base;
/// arb_parameter_layout names and describes each: eye, sun, ext, ray, mie, hg). beta_ex is
/// clamped per channel to at least 1e-12 * (largest channel) and 1e-30 /m, so that a channel
/// without extinction stays finite (see arb_program_parameters).
inline constexpr int kArbParameterCount = 6;

/// How many frame parameter vectors the `height` program reads at the spec_minimum and
/// exact_optical_depth levels (arb_parameter_layout names and describes each: 13 shared with
/// `full`, then the sun columns' slopes slr, slm). It computes what the CPU `height` model
/// computes, F_ex within 1 LSB, L_in with these approximations at spec_minimum:
///   - the sun's column factors along the segment: the eye's, plus their change to first order
///     in d = vertex - eye (the model interpolates to the vertex's exact factors); right within
///     tens of km, wrong on rays of hundreds of km at a low sun;
///   - the nodes are placed by the G optical depth with the mean sag (the model: without it)
///     and the weights miss the model's correction by the exact optical depth to each node
///     (exact_optical_depth adds it): wrong on very long rays (a sky dome of 1000 km, whose
///     segments sag tens of km below the straight altitude profile) and where two components
///     with very different scale heights both carry optical depth (haze or fog layers);
///   - no per-node planet shadow: a sun below the eye's horizon is treated as blocked.
/// The `full` level leaves none of them out. docs/arb-program.md gives the measured error.
inline constexpr int kArbHeightParameterCount = 15;

/// How many frame parameter vectors the `full` height program reads: the 13 shared ones, then
/// sunc, chx, chh, fitc (arb_parameter_layout).
inline constexpr int kArbHeightFullParameterCount = 17;

/// How many frame parameter vectors the `multiple_scattering` height program reads: full's 17,
/// then msz, mss, msr, msm, msq, the 32 x 16 rows of `lev` and the 8 x 153 of `shp`
/// (arb_parameter_layout).
inline constexpr int kArbHeightMultipleParameterCount = 1758;

/// kArbParameterCount or kArbHeightParameterCount (0 for a model without a program).
constexpr int arb_parameter_count(Model model) {
    return model == Model::hoffman_preetham ? kArbParameterCount
           : model == Model::height         ? kArbHeightParameterCount
                                            : 0;
}

/// The parameter count of the program `options` describe: its frame parameters
/// (kArbParameterCount, kArbHeightParameterCount or, at the `full` fidelity,
/// kArbHeightFullParameterCount; `automatic` resolved as generate_arb_program resolves it),
/// plus the 3 model-matrix rows with options.model_matrix. arb_parameter_layout(options).size().
int arb_parameter_count(const ArbProgramOptions& options);

/// The fidelity generate_arb_program uses for `options` (height model): options.height_fidelity,
/// or for `automatic` the highest level whose program fits options.limits, spec_minimum when
/// none does (generation then fails naming the exceeded limit).
ArbHeightFidelity resolve_arb_height_fidelity(const ArbProgramOptions& options);

/// One parameter vector of a program.
struct ArbParameterInfo {
    int index = 0;             ///< absolute: program.local[index] (or env), parameter_base added
    const char* name = "";     ///< the name the program text declares it by: "eye", "scale", ...
    const char* meaning = "";  ///< one line: what each component holds
};

/// The parameter layout of the program `options` describe, in index order: the frame's vectors
/// (what arb_program_parameters returns first), then with options.model_matrix the rows
/// "model0", "model1", "model2". The source of truth: the program declares each as
/// `PARAM name = program.local[index];  # meaning`. Empty for a model without a program.
std::vector<ArbParameterInfo> arb_parameter_layout(const ArbProgramOptions& options);

/// The absolute index of the first model-matrix row (options.model_matrix): parameter_base plus
/// the frame's parameter count. Rows 0, 1, 2 of M go to this index and the next two.
int arb_model_matrix_parameter_index(const ArbProgramOptions& options);

/// The 3 top rows of a column-major 4x4 model matrix (glLoadMatrixf order, engine units), as the
/// program reads them: row i = (m[i], m[4 + i], m[8 + i], m[12 + i]). Upload per draw.
std::array<std::array<float, 4>, 3> arb_model_matrix_parameters(const float column_major[16]);

/// What a program uses, counted as the spec counts it (section 2.14.3.7).
struct ArbResources {
    int instructions = 0;  ///< executable instructions (not declarations, OPTION or END)
    int temporaries = 0;   ///< TEMP variables
    int parameters = 0;    ///< distinct parameter bindings: state vectors, local/env, constants
    int attributes = 0;    ///< distinct vertex attributes
};

/// A generated program.
struct ArbProgram {
    std::string text;  ///< exactly what goes to glProgramStringARB; "!!ARBvp1.0" ... "END\n"
    ArbResources resources;
    int instruction_count = 0;  ///< resources.instructions, for convenience
    /// What it was generated with; for the height model, height_fidelity is the level chosen
    /// (never automatic). Pass these to arb_program_parameters.
    ArbProgramOptions options;
};

/// Generates the program for options.model. Errors name the field: "model" (reference has no
/// program), "parameter_base", "texcoord_units", or the exceeded limit ("instructions",
/// "temporaries", "parameters", "attributes").
Result<ArbProgram> generate_arb_program(const ArbProgramOptions& options = {});

/// The arb_parameter_count(options) parameter vectors of one frame (element i goes to
/// index options.parameter_base + i; arb_parameter_layout describes each). With
/// options.model_matrix the last 3 are the identity's rows (world = model space) until the
/// engine uploads a draw's arb_model_matrix_parameters over them. Requires frame.model ==
/// options.model, a finite display.exposure > 0 and display.tone == ToneCurve::clamp (GL clamps the
/// secondary colour; the exponential curve has no room in the program). Every value is finite.
///
/// Extinction close to 0: the program computes L_in = A (1 - 2^(k s)) with A proportional to
/// beta_sc / beta_ex, which is <= 1 and never overflows; only beta_ex = 0 (0/0) needs care, so
/// each channel's beta_ex is raised to beta_min = max(1e-12 * max_c beta_ex, 1e-30 /m). In a
/// raised channel (beta_sc <= beta_ex < beta_min) F_ex then differs from exp(-beta_ex s) by at
/// most beta_min s, and L_in from the closed form by a relative beta_min s / 2. With
/// beta_min s = 1e-12 tau_max (the optical depth of the densest channel), both stay below
/// 0.5 LSB up to tau_max = 2e9: 2000 km of the densest fog the validation accepts (1 /m).
Result<std::vector<std::array<float, 4>>> arb_program_parameters(
    const Frame<float>& frame, const Display& display, const ArbProgramOptions& options = {});

/// Checks counts against limits. `position_invariant` lowers the instruction limit by 4 (spec
/// section 2.14.4.5.1). The error names the resource ("instructions", ...) and the GL limit.
std::optional<Error> check_arb_limits(const ArbResources& resources, const ArbLimits& limits,
                                      bool position_invariant);

}  // namespace aerial
