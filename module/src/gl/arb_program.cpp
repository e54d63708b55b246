// The ARB vertex program of the hoffman-preetham model, its per-frame parameters and the resource
// limit check. The program is counted by parsing its own text (arb_interpreter.cpp), so that the
// figures always describe what GL receives.
//
// What the program computes per vertex (d = vertex - eye in engine units, s = |d|, y ~ 1/s from
// RSQ, u = d y - sun):
//   F_ex = exp(-beta_ex s)           = 2^(k s),  k = -beta_ex log2(e) per engine unit
//   w    = |u|^2                     = 2 (1 - cos theta), from d itself
//   L_in = [A (1 + c^2) + B h^-1.5] (1 - F_ex),  c = 1 - w/2,  h = (1 - g)^2 + g w
// (for g < 0 the sun parameter is negated, so that h = (1 - |g|)^2 + |g| w stays a sum of
// positive terms).
// with E_sun, exposure, 1/beta_ex and the phase constants folded into A and B once per frame: the
// closed form of scattering.cpp, beta_sc(theta) / beta_ex E_sun (1 - F_ex), rearranged.
//
// Why w: 1 - cos theta taken from a dot product cancels near the sun, where the Mie lobe is
// steepest, and a DPH of the raw position with (sun, -eye.sun) would cancel against the size of
// the coordinates. |d y - sun|^2 has neither problem: an RSQ off by a relative e gives
// w = 2 (1 - c)(1 + e) + e^2, so h (and the Mie peak) moves by e relative, not by 2 g e absolute.
// It is a sum of squares, so h >= (1 - |g|)^2 > 0 and POW never sees a negative base.
//
// Instruction budget (default options): 4 transform, 5 for s and w (the MAD that makes u also
// puts s in u.w), 1 fog, 1 + 3 + 1 for F_ex (EX2 is scalar), 6 for the phase functions and L_in,
// 1 per texture unit: 22. The optional guard against a coarse EX2 adds 7 (see the header).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>

#include "aerial/arb_program.hpp"
#include "aerial/phase.hpp"

namespace aerial {
namespace {

/// d.w = vertex.w - eye.w = 2^-20 exactly (eye.w = 1 - 2^-20 is a float): the DP4 of d with
/// itself adds 2^-40 square units to s^2, so that RSQ never sees 0 (a vertex at the eye).
constexpr double kEpsilon = 1.0 / 1048576.0;
constexpr double kLog2E = 1.44269504088896340736;

/// Indices of the parameters, relative to parameter_base (layout in arb_program.hpp).
enum ParameterIndex { kEye, kSun, kExtinction, kRayleigh, kMie, kPhase };

std::optional<Error> validate_options(const ArbProgramOptions& o, const char* function) {
    const std::string fn = std::string("aerial::") + function + "(): ";
    if (o.model != Model::hoffman_preetham) {
        return Error{"model", "model: " + fn + "only hoffman-preetham has an ARB program, got " +
                                  std::string(model_name(o.model))};
    }
    if (o.parameter_base < 0) {
        return Error{"parameter_base", "parameter_base: " + fn + "expected >= 0, got " +
                                           std::to_string(o.parameter_base)};
    }
    if (o.parameter_base + kArbParameterCount > o.limits.max_parameters) {
        return Error{"parameter_base",
                     "parameter_base: " + fn + "the program reads indices " +
                         std::to_string(o.parameter_base) + " to " +
                         std::to_string(o.parameter_base + kArbParameterCount - 1) +
                         ", beyond the " + std::to_string(o.limits.max_parameters) +
                         " program parameters (MAX_PROGRAM_PARAMETERS_ARB); expected at most " +
                         std::to_string(o.limits.max_parameters - kArbParameterCount)};
    }
    if (o.texcoord_units < 0 || o.texcoord_units > kArbMaxTexcoordUnits) {
        return Error{"texcoord_units", "texcoord_units: " + fn + "expected 0 to " +
                                           std::to_string(kArbMaxTexcoordUnits) + ", got " +
                                           std::to_string(o.texcoord_units)};
    }
    return std::nullopt;
}

/// A float constant for program text: 9 significant digits (round-trips a float), '.' as the
/// decimal point whatever the C locale says.
std::string format_float(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(value),
                                      std::chars_format::general, 9);
    return std::string(buffer, result.ptr);
}

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

std::string program_text(const ArbProgramOptions& o) {
    const std::string space = o.parameter_space == ParameterSpace::local ? "local" : "env";
    const auto param = [&](int i) {
        return "program." + space + "[" + std::to_string(o.parameter_base + i) + "]";
    };
    ProgramWriter w;
    w.line("!!ARBvp1.0");
    if (o.position_invariant) w.line("OPTION ARB_position_invariant;");
    w.comment("aerial: Hoffman & Preetham (2002) aerial perspective per vertex, hoffman-preetham");
    w.comment("model. Generated by aerial::generate_arb_program; the parameters come from");
    w.comment("aerial::arb_program_parameters, once per frame.");
    w.comment("In:  vertex.position = world position in engine units, w = 1.");
    w.comment("Out: primary = F_ex (extinction; a = 1), secondary = L_in (in-scattering, exposure");
    w.comment("     applied), fogcoord = distance eye -> vertex (engine units).");
    w.line("ATTRIB pos = vertex.position;");
    if (!o.position_invariant) w.line("PARAM mvp[4] = { state.matrix.mvp };");
    w.line("PARAM eye = " + param(kEye) + ";", "eye position; w = 1 - 2^-20");
    w.line("PARAM sun = " + param(kSun) + ";", "towards the sun (away if g < 0); w = 0");
    w.line("PARAM ext = " + param(kExtinction) + ";", "-beta_ex log2(e) per engine unit");
    w.line("PARAM ray = " + param(kRayleigh) + ";", "E_sun beta_R 3/(16 pi) / beta_ex");
    w.line("PARAM mie = " + param(kMie) + ";", "E_sun beta_M (1 - g^2)/(4 pi) / beta_ex");
    w.line("PARAM hg = " + param(kPhase) + ";", "(|g|, 1/4, (1 - |g|)^2, -1)");
    w.line("PARAM num = { 2, -1.5, 0, 0 };");
    if (o.guard_coarse_ex2) {
        // Coefficients of the series of 1 - F_ex in arg = log2(F_ex) = -tau / ln(2).
        const double l = std::log(2.0);
        w.line("PARAM ser = { " + format_float(-l) + ", " + format_float(-l * l / 2.0) + ", " +
                   format_float(-l * l * l / 6.0) + ", 1 };",
               "-ln2, -ln2^2/2, -ln2^3/6, 1");
    }
    w.line(o.guard_coarse_ex2 ? "TEMP view, dir, arg, fex, lo, hi, phase, lin;"
                              : "TEMP view, dir, arg, fex, phase, lin;");
    if (!o.position_invariant) {
        w.comment("Clip-space position.");
        for (int row = 0; row < 4; ++row) {
            w.line("DP4 result.position." + std::string(1, "xyzw"[row]) + ", mvp[" +
                   std::to_string(row) + "], pos;");
        }
    }
    w.comment("Distance s and w = |d/s - sun|^2 = 2 (1 - cos theta), d = vertex - eye.");
    w.line("SUB view, pos, eye;", "(d, 2^-20)");
    w.line("DP4 view.w, view, view;", "s^2 + 2^-40, never 0");
    w.line("RSQ dir.x, view.w;", "1/s");
    w.line("MAD dir, view, dir.x, -sun;", "(d/s - sun, s)");
    w.line("DP3 dir.x, dir, dir;", "w");
    w.line("MOV result.fogcoord.x, dir.w;", "s");
    w.comment("Extinction F_ex = exp(-beta_ex s), per channel (EX2 is scalar).");
    w.line("MUL arg.xyz, ext, dir.w;", "log2 F_ex = -beta_ex s log2(e)");
    w.line("EX2 fex.xw, arg.x;");
    w.line("EX2 fex.y, arg.y;");
    w.line("EX2 fex.z, arg.z;");
    if (o.guard_coarse_ex2) {
        w.comment("Guard against a coarse EX2: clamp F_ex between its series in tau = -ln(2) arg.");
        w.line("MAD lo.xyz, arg, ser.z, ser.y;");
        w.line("MAD lo.xyz, lo, arg, ser.x;");
        w.line("MAD lo.xyz, -lo, arg, ser.w;", "1 - tau + tau^2/2 - tau^3/6");
        w.line("MAD hi.xyz, arg, ser.y, ser.x;");
        w.line("MAD hi.xyz, -hi, arg, ser.w;", "1 - tau + tau^2/2");
        w.line("MAX fex.xyz, fex, lo;");
        w.line("MIN fex.xyz, fex, hi;");
    }
    w.line("SWZ result.color.primary, fex, x, y, z, 1;");
    w.comment("In-scattering L_in = (Rayleigh + Mie) (1 - F_ex), exposure included.");
    w.line("MAD phase.xy, dir.x, hg.xyxy, hg.zwzw;", "(h = 1 + g^2 - 2 g c, w/4 - 1)");
    w.line("MAD phase.y, phase.y, dir.x, num.x;", "1 + c^2");
    w.line("POW phase.x, phase.x, num.y;", "h^-1.5");
    w.line("MUL lin, ray, phase.y;", "Rayleigh");
    w.line("MAD lin, mie, phase.x, lin;", "+ Henyey-Greenstein = L_in at infinity");
    w.line("MAD result.color.secondary, -lin, fex, lin;", "lin (1 - F_ex)");
    if (o.texcoord_units > 0) w.comment("Texture coordinates, unchanged.");
    for (int u = 0; u < o.texcoord_units; ++u) {
        const std::string unit = "[" + std::to_string(u) + "]";
        w.line("MOV result.texcoord" + unit + ", vertex.texcoord" + unit + ";");
    }
    w.line("END");
    return w.str();
}

}  // namespace

std::optional<Error> check_arb_limits(const ArbResources& r, const ArbLimits& limits,
                                      bool position_invariant) {
    const int max_instructions = limits.max_instructions - (position_invariant ? 4 : 0);
    const struct {
        const char* field;
        int used;
        int limit;
        const char* gl_name;
    } checks[] = {
        {"instructions", r.instructions, max_instructions, "MAX_PROGRAM_INSTRUCTIONS_ARB"},
        {"temporaries", r.temporaries, limits.max_temporaries, "MAX_PROGRAM_TEMPORARIES_ARB"},
        {"parameters", r.parameters, limits.max_parameters, "MAX_PROGRAM_PARAMETERS_ARB"},
        {"attributes", r.attributes, limits.max_attributes, "MAX_PROGRAM_ATTRIBS_ARB"},
    };
    for (const auto& c : checks) {
        if (c.used > c.limit) {
            std::string message = std::string(c.field) + ": the program uses " +
                                  std::to_string(c.used) + ", more than the limit " +
                                  std::to_string(c.limit) + " (" + c.gl_name;
            if (position_invariant && c.field == std::string("instructions")) {
                message += " minus 4 for ARB_position_invariant";
            }
            return Error{c.field, message + ")"};
        }
    }
    return std::nullopt;
}

Result<ArbProgram> generate_arb_program(const ArbProgramOptions& options) {
    if (auto e = validate_options(options, "generate_arb_program")) return *e;
    ArbProgram program;
    program.text = program_text(options);
    program.options = options;
    auto parsed = parse_arb_program(program.text);
    if (!parsed) {
        return Error{"text",
                     "text: aerial::generate_arb_program(): the generated program does not "
                     "parse (a bug): " +
                         parsed.error().message};
    }
    program.resources = parsed->resources;
    program.instruction_count = program.resources.instructions;
    if (auto e = check_arb_limits(program.resources, options.limits, options.position_invariant)) {
        return *e;
    }
    return program;
}

Result<std::vector<std::array<float, 4>>> arb_program_parameters(const Frame<float>& frame,
                                                                 const Display& display,
                                                                 const ArbProgramOptions& options) {
    if (auto e = validate_options(options, "arb_program_parameters")) return *e;
    if (frame.model != Model::hoffman_preetham) {
        return Error{"frame.model",
                     "frame.model: aerial::arb_program_parameters(): the ARB program computes "
                     "hoffman-preetham, got a frame prepared for " +
                         std::string(model_name(frame.model))};
    }
    if (!std::isfinite(display.exposure) || display.exposure <= 0.0f) {
        return Error{"display.exposure",
                     "display.exposure: aerial::arb_program_parameters(): expected a finite value "
                     "> 0, got " +
                         std::to_string(display.exposure)};
    }
    if (display.tone != ToneCurve::clamp) {
        return Error{"display.tone",
                     "display.tone: aerial::arb_program_parameters(): the ARB program applies the "
                     "exposure and GL clamps (ToneCurve::clamp); ToneCurve::exponential is not "
                     "available"};
    }

    const glm::dvec3 eye = frame.view.eye;  // engine units
    const glm::dvec3 sun = frame.view.sun_dir;
    const double mpu = frame.view.meters_per_unit;
    const double g = frame.mie_g;
    const double exposure = display.exposure;

    glm::dvec3 beta_r, beta_m, beta_ex, sun_irradiance;
    for (int c = 0; c < 3; ++c) {
        beta_r[c] = frame.rayleigh_scattering[c];
        beta_m[c] = frame.mie_scattering[c];
        beta_ex[c] = double(frame.rayleigh_scattering[c]) + double(frame.mie_extinction[c]);
        sun_irradiance[c] = frame.sun_irradiance_eye[c];
    }
    const double beta_min = std::max(1e-12 * std::max({beta_ex.x, beta_ex.y, beta_ex.z}), 1e-30);
    const double rayleigh_constant = 3.0 / (16.0 * kPi);
    const double mie_constant = (1.0 - g * g) / (4.0 * kPi);

    // For g < 0 the program works with the anti-sun: w = |d/s + sun|^2 = 2 (1 + c) and
    // h = (1 - |g|)^2 + |g| w, the same sum of positive terms (1 + c^2 is even in c).
    const double sign = g < 0.0 ? -1.0 : 1.0;
    std::array<std::array<double, 4>, kArbParameterCount> p{};
    p[kEye] = {eye.x, eye.y, eye.z, 1.0 - kEpsilon};
    p[kSun] = {sign * sun.x, sign * sun.y, sign * sun.z, 0.0};
    for (int c = 0; c < 3; ++c) {
        const std::size_t i = static_cast<std::size_t>(c);
        const double b = std::max(beta_ex[c], beta_min);
        const double light = exposure * sun_irradiance[c] / b;
        p[kExtinction][i] = -b * mpu * kLog2E;
        p[kRayleigh][i] = light * beta_r[c] * rayleigh_constant;
        p[kMie][i] = light * beta_m[c] * mie_constant;
    }
    const double abs_g = std::abs(g);
    p[kPhase] = {abs_g, 0.25, (1.0 - abs_g) * (1.0 - abs_g), -1.0};

    std::vector<std::array<float, 4>> out(kArbParameterCount);
    for (std::size_t i = 0; i < out.size(); ++i) {
        for (std::size_t j = 0; j < 4; ++j) {
            const float v = static_cast<float>(p[i][j]);
            if (!std::isfinite(v)) {
                return Error{"frame", "frame: aerial::arb_program_parameters(): parameter " +
                                          std::to_string(i) + " component " + std::to_string(j) +
                                          " is " + std::to_string(p[i][j]) +
                                          ", beyond float range (eye or meters_per_unit too "
                                          "large?)"};
            }
            out[i][j] = v;
        }
    }
    return out;
}

}  // namespace aerial
