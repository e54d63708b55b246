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
// aerial::scatter takes), and vertex.position.w must be 1 (glVertex3*, 3-component arrays).
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
    /// 127 instructions (with one texture unit), 11 temporaries: within the spec minimums of 128
    /// instructions and 12 temporaries. Leaves out three parts of the model (listed at
    /// kArbHeightParameterCount).
    spec_minimum,
    /// spec_minimum plus the weights' correction by the exact optical depth: 150 instructions.
    exact_optical_depth,
    /// All of the CPU model: exact_optical_depth plus the sun's column factors at the vertex
    /// (an erfcx fit and the below-horizon branch) interpolated along the segment as the model
    /// does, the planet's shadow per sunlight point and the eye's or the vertex's blocked sun:
    /// 249 instructions, 12 temporaries and kArbHeightFullParameterCount parameters: within 1
    /// LSB of the CPU model. Needs a driver whose MAX_PROGRAM_NATIVE_INSTRUCTIONS is at least
    /// 249 (256 on Direct3D 9-class hardware; Mesa's are far larger).
    full,
};

/// "automatic", "spec-minimum", "exact-optical-depth" or "full".
const char* arb_height_fidelity_name(ArbHeightFidelity fidelity);
/// The inverse of arb_height_fidelity_name; an error names the field "height_fidelity" and lists
/// the known names.
Result<ArbHeightFidelity> parse_arb_height_fidelity(std::string_view name);

/// Options of generate_arb_program and arb_program_parameters (use the same for both).
struct ArbProgramOptions {
    /// hoffman_preetham (22 instructions) or height (127 to 249 by height_fidelity).
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
    ArbLimits limits;  ///< checked by generate_arb_program
};

/// How many program.local / program.env vectors the hoffman-preetham program reads, starting at
/// parameter_base.
///
/// Layout (index relative to parameter_base; x, y, z are the R, G, B channels where it applies):
///   0  eye        xyz: eye position, engine units;  w: 1 - 2^-20 (vertex.w - eye.w = 2^-20
///                 exactly, which keeps |vertex - eye|^2 >= 2^-40 for RSQ)
///   1  sun        xyz: sun_dir (unit, towards the sun), negated when g < 0;  w: 0
///   2  extinction xyz: -beta_ex * meters_per_unit * log2(e), per engine unit (EX2 argument / s);
///                 w: 0
///   3  rayleigh   xyz: exposure * E_sun * beta_R * 3/(16 pi) / beta_ex;  w: 0
///   4  mie        xyz: exposure * E_sun * beta_M * (1 - g^2)/(4 pi) / beta_ex;  w: 0
///   5  phase      (|g|, 1/4, (1 - |g|)^2, -1)
/// with E_sun = frame.sun_irradiance_eye and beta_ex clamped per channel to at least
/// 1e-12 * (largest channel) and 1e-30 /m, so that a channel without extinction stays finite (see
/// arb_program_parameters). The program also declares the constant { 2, -1.5, 0, 0 }.
inline constexpr int kArbParameterCount = 6;

/// How many parameter vectors the `height` program reads, starting at parameter_base.
///
/// Layout (index relative to parameter_base; lengths in metres, log2 = base-2 logarithm):
///   0  eye        xyz: eye position in metres (View::eye * meters_per_unit);  w: 1 - 2^-20
///   1  scale      (meters_per_unit, meters_per_unit, meters_per_unit, 1)
///   2  sun        xyz: sun_dir, negated when g < 0;  w: 0
///   3  centre     xyz: 2 c, c = eye + R up (from the planet centre to the eye);
///                 w: |eye|^2 + 2 R eye.up (m^2)
///   4  planet     (R^2, R, frame.min_altitude_m, 1 / meters_per_unit)
///   5  eye alt.   (frame.eye_altitude_m, 1/(12 R), 1/(2 R), w): w = 1 if the sun reaches the
///                 eye (its column factors are below the model's blocked value), else 0; read
///                 by `full` only
///   6  inverse H  log2(e) (-1/H_R, -1/H_M, 1/H_R, 1/H_M)
///   7  extr       xyz: -log2(e) beta_R (<= -1e-30);  w: 0 (keeps the secondary alpha 0)
///   8  extm       xyz: -log2(e) beta_M,extinction (<= -1e-30);  w: 0 (the same)
///   9  rayleigh   xyz: log2(e)^2 exposure E_sun0 beta_R 3/(16 pi);
///                 w: log2(e)^2 beta_R,G exp(-h0/H_R) (read from exact_optical_depth on)
///   10 mie        xyz: log2(e)^2 exposure E_sun0 beta_M (1 - g^2)/(4 pi);
///                 w: log2(e)^2 beta_M,ext,G exp(-h0/H_M) (the same)
///   11 phase      (|g|, 1/4, (1 - |g|)^2, -1)
///   12 sun column x, y: log2(e) times the eye's log Chapman factors (frame.eye_log_chapman_*),
///                 capped at 40 (a blocked sun becomes a column of e^40 H_i exp(-h/H_i)); for
///                 `full` not capped, and 0 when the sun is blocked at the eye;
///                 z, w: log2(beta_i,G / k0) + 2^-10, k0 = G extinction at the eye
/// The program computes what the CPU `height` model computes, F_ex exactly (within 1 LSB), L_in
/// with three approximations that fit it into 128 instructions:
///   - the quadrature weights use the fitted exponential extinction profile's Jacobian only,
///     without the model's correction by the exact optical depth to each node (exp(tau_fit -
///     tau)), which matters where two components with very different scale heights both carry
///     optical depth (rays leaving or entering a haze or fog layer); the exact_optical_depth
///     fidelity adds it, beyond 128 instructions;
///   - the sun's column factors are the eye's along the whole segment (the model interpolates to
///     the vertex's), which matters at a low sun on long rays;
///   - no per-node planet shadow: a sun below the eye's horizon is treated as blocked (the model
///     lights the parts of the segment that still see it: twilight is dark).
/// The `full` fidelity leaves none of them out. docs/arb-program.md gives the measured
/// error against the CPU and reference models.
inline constexpr int kArbHeightParameterCount = 13;

/// How many parameter vectors the `full` height program reads: the 13 above, then
///   13 sun (true) xyz: sun_dir (not negated);  w: c.sun_dir, c = eye + R up (m)
///   14 chapman x  (1/H_R, 1/H_M, R/H_R, R/H_M): x = (R + h)/H at altitude h
///   15 chapman h  (H_R sqrt(pi/2), H_M sqrt(pi/2), 2 H_R sqrt(pi/2), 2 H_M sqrt(pi/2)) (m)
///   16 fit clamp  x, y: sky.z, sky.w + (80 - h0/H_i) log2(e), the model's bound on the fitted
///                 profile's end (exp(-rise/H_i) <= e^80);  z, w: 0 (unused)
inline constexpr int kArbHeightFullParameterCount = 17;

/// kArbParameterCount or kArbHeightParameterCount (0 for a model without a program).
constexpr int arb_parameter_count(Model model) {
    return model == Model::hoffman_preetham ? kArbParameterCount
           : model == Model::height         ? kArbHeightParameterCount
                                            : 0;
}

/// The parameter count of the program `options` describe: arb_parameter_count(options.model),
/// or kArbHeightFullParameterCount for the height program at the `full` fidelity (`automatic`
/// resolved against options.limits as generate_arb_program resolves it).
int arb_parameter_count(const ArbProgramOptions& options);

/// The fidelity generate_arb_program uses for `options` (height model): options.height_fidelity,
/// or for `automatic` the highest level whose program fits options.limits, spec_minimum when
/// none does (generation then fails naming the exceeded limit).
ArbHeightFidelity resolve_arb_height_fidelity(const ArbProgramOptions& options);

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
/// index options.parameter_base + i; layouts above). Requires frame.model == options.model, a
/// finite display.exposure > 0 and display.tone == ToneCurve::clamp (GL clamps the secondary
/// colour; the exponential curve has no room in the program). Every value is finite.
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
