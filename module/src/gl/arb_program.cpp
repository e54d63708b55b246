// The ARB vertex programs of the hoffman-preetham and height models, their per-frame parameters
// and the resource limit check. The program is counted by parsing its own text
// (arb_interpreter.cpp), so that the figures always describe what GL receives.
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
#include "arb_parser.hpp"

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
    if (o.model != Model::hoffman_preetham && o.model != Model::height) {
        return Error{"model", "model: " + fn +
                                  "only hoffman-preetham and height have an ARB program, got " +
                                  std::string(model_name(o.model))};
    }
    ArbProgramOptions counted = o;
    if (o.model == Model::height && o.height_fidelity == ArbHeightFidelity::automatic) {
        counted.height_fidelity = ArbHeightFidelity::spec_minimum;  // the smallest
    }
    const int count = arb_parameter_count(counted);
    if (o.parameter_base < 0) {
        return Error{"parameter_base", "parameter_base: " + fn + "expected >= 0, got " +
                                           std::to_string(o.parameter_base)};
    }
    if (o.parameter_base + count > o.limits.max_parameters) {
        return Error{"parameter_base",
                     "parameter_base: " + fn + "the program reads indices " +
                         std::to_string(o.parameter_base) + " to " +
                         std::to_string(o.parameter_base + count - 1) + ", beyond the " +
                         std::to_string(o.limits.max_parameters) +
                         " program parameters (MAX_PROGRAM_PARAMETERS_ARB); expected at most " +
                         std::to_string(o.limits.max_parameters - count)};
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

/// The parameters rounded to float; an error names the first one out of float range.
Result<std::vector<std::array<float, 4>>> to_float_parameters(
    const std::vector<std::array<double, 4>>& p) {
    std::vector<std::array<float, 4>> out(p.size());
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

/// Indices of the height program's parameters, relative to parameter_base (layout in
/// arb_program.hpp).
enum HeightParameterIndex {
    kHeightEye,
    kHeightScale,
    kHeightSun,
    kHeightCentre,
    kHeightPlanet,
    kHeightEyeAltitude,
    kHeightInverseScaleHeights,
    kHeightRayleighExtinction,
    kHeightMieExtinction,
    kHeightRayleigh,
    kHeightMie,
    kHeightPhase,
    kHeightSunColumn,
    kHeightParameterCount,
    kHeightTrueSun = kHeightParameterCount,
    kHeightChapmanX,
    kHeightChapmanH,
    kHeightFitClamp,
    kHeightFullParameterCount
};
static_assert(kHeightParameterCount == kArbHeightParameterCount, "layout and count disagree");
static_assert(kHeightFullParameterCount == kArbHeightFullParameterCount,
              "layout and count disagree");

/// 3-point Gauss-Legendre nodes and weights on [0, 1] (the height model's kSunNodes/kSunWeights).
constexpr double kGaussNodes[3] = {0.11270166537925831148, 0.5, 0.88729833462074168852};
constexpr double kGaussWeights[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
/// phi(x) = (1 - e^-x)/x is taken from its series below x = kSeriesLimit and from the quotient
/// above it (the quotient loses 2^-24 / x to rounding, 2^-11 / x with a coarse EX2).
constexpr double kSeriesLimit = 0.25;
/// The slope b of the fitted extinction profile (log2 units over the segment) is kept at least
/// this far from 0, where the node placement would divide 0 by 0; a shift this small moves the
/// nodes by < 1e-3 of the segment.
constexpr double kMinFitSlope = 1.0 / 1024.0;
/// The height model clamps its fitted slope to +-80 (natural units) and so does the program (from
/// above; below it the float range suffices).
constexpr double kMaxFitSlope = 80.0;
/// Below this log factor (natural units) the sun column at the eye is used as it is; a blocked sun
/// (factor >= 80) or a larger one is capped here: e^(40 + 40) still fits a float, and a column of
/// e^40 H_i exp(-h/H_i) puts the sun out up to 100 km.
constexpr double kMaxLogColumnFactor = 40.0;
/// The height model's log column factor of a blocked sun (scattering.cpp's kBlockedLogColumn).
constexpr double kBlockedLogColumn = 80.0;
/// Added to a log2 exponent, makes EX2 give 0 (or +inf for a column, whose transmittance is
/// then 0): no sun.
constexpr double kBlocked = 1e30;

/// (1 - e^-x)/x in double.
double one_minus_exp_over_x(double x) { return x == 0.0 ? 1.0 : -std::expm1(-x) / x; }

/// The full height program's erfcx: erfcx(y) = exp(y^2) erfc(y) ~ t Q(t), t = C / (y + C) in
/// (0, 1], Q a polynomial of degree kErfcxDegree interpolated at Chebyshev nodes of [0, 1] when
/// the program is generated (relative error 1.2e-6 over y >= 0 in float; the CPU model's erfcx is
/// within 2e-5).
constexpr double kErfcxScale = 2.0;  // C
constexpr int kErfcxDegree = 8;

/// erfcx in double for y >= 0 (the fit's data): the product below y = 25, the asymptotic series
/// (relative error < 1e-16 there) above.
double erfcx_double(double y) {
    if (y < 25.0) return std::exp(y * y) * std::erfc(y);
    const double inv2 = 1.0 / (y * y);
    double sum = 1.0, term = 1.0;
    for (int k = 1; k < 8; ++k) {
        term *= -(2.0 * k - 1.0) * 0.5 * inv2;
        sum += term;
    }
    return sum / (y * std::sqrt(kPi));
}

/// Q's monomial coefficients, constant term first.
std::array<double, kErfcxDegree + 1> erfcx_fit() {
    constexpr int n = kErfcxDegree + 1;
    std::array<double, n> t{}, c{};
    for (int k = 0; k < n; ++k) {
        t[k] = 0.5 - 0.5 * std::cos(kPi * (k + 0.5) / n);
        const double y = kErfcxScale * (1.0 - t[k]) / t[k];
        c[k] = erfcx_double(y) / t[k];
    }
    for (int j = 1; j < n; ++j) {  // Newton's divided differences
        for (int i = n - 1; i >= j; --i) c[i] = (c[i] - c[i - 1]) / (t[i] - t[i - j]);
    }
    std::array<double, n> p{};
    for (int i = n - 1; i >= 0; --i) {  // p = p (t - t_i) + c_i
        std::array<double, n> q{};
        for (int k = 0; k + 1 < n; ++k) {
            q[k + 1] += p[k];
            q[k] -= p[k] * t[i];
        }
        q[0] += c[i];
        p = q;
    }
    return p;
}

// The height program. Per vertex, like height_model() in scattering.cpp (metres; d = p - eye,
// s = |d|, the G channel drives the quadrature):
//   h1 = n / (|p - centre| + R), n = |p|^2 + 2 R p.up (from the eye's n: no cancellation);
//   rho_i = exp(-h_low/H_i) phi(|h1 - h0|/H_i), h_low = min(h0, h1) - s^2/(12 R),
//     phi(x) = (1 - e^-x)/x as S(min(x, c)) + Q(max(x, c)) - phi(c): the series S is right below
//     c, the quotient Q above it, and neither needs a branch (c = 0.25);
//   F_ex = exp(-beta s), beta = beta_R rho_R + beta_M rho_M per channel;
//   the fitted G profile k0 exp(-a u), a = ln(k0 / k(h1)) (b = a log2(e), kept >= 2^-10 from 0);
//   nodes y_n (3-point Gauss) in the share of the attenuation: f_n = -ln(1 - y_n (1 - F_G))/tau_G,
//     u_n = -ln(1 - f_n (1 - e^-a))/a, altitude h_n = h0 + (h1 - h0) u_n - sag u_n (1 - u_n);
//   weights W_n rho_i(h_n) e^(a u_n), sun transmittance at each node from the eye's Chapman
//     factors and the node's densities;
//   L_in = E0 s phi(tau_c) phi(a) sum_i beta_i P_i sum_n weight_in T_n (exposure in the params).
// What the model does and the program does not (128 instructions): the weights' correction by
// exp(tau_fit(u_n) - tau(u_n)) (about 20 instructions: six more EX2 and a guarded division), the
// sun column factors interpolated to the vertex (an erfcx and its below-horizon branch, about 30)
// and the planet-shadow test per node (about 10). Budget: 4 transform, 6 distance and fog, 3
// phase, 12 altitude, 17 densities, 8 fit, 11 F_ex, 14 nodes, 6 node altitudes, 9 weights,
// 8 columns, 21 transmittance sums, 6 L_in, 1 per texture unit: 127 with one unit.
// exact_optical_depth adds the correction (23 more: 150). full adds the rest of the model (99
// more: 249): the vertex's column factors (the erfcx fit, the below-horizon branch, the choice
// between them, the blocked tests and the ends' interpolation), the shadow per node, tau_total
// without the sag for the node placement and the scale phi(tau_total)/phi(tau_G), the model's
// bounds on the fit, the weights and the columns, and the interpolated factors at the nodes.
std::string height_program_text(const ArbProgramOptions& o, ArbHeightFidelity fidelity) {
    const bool exact = fidelity != ArbHeightFidelity::spec_minimum;
    const bool full = fidelity == ArbHeightFidelity::full;
    const std::string space = o.parameter_space == ParameterSpace::local ? "local" : "env";
    const auto param = [&](int i) {
        return "program." + space + "[" + std::to_string(o.parameter_base + i) + "]";
    };
    const auto vec = [](double a, double b, double c, double d) {
        return "{ " + format_float(a) + ", " + format_float(b) + ", " + format_float(c) + ", " +
               format_float(d) + " }";
    };
    const double ln2 = std::log(2.0);
    ProgramWriter w;
    // colm = (y_R, y_M, C_R, C_M) of the exact optical depth tau(u) (see there).
    const auto optical_depth_coefficients = [&w] {
        w.line("MUL colm.xy, alt.w, inv.zwzw;", "y");
        w.line("SGE colm.zw, colm.xyxy, fit.z;");
        w.line("MAD colm.zw, colm, fit.y, fit.x;");
        w.line("ADD colm.xy, colm, colm.zwzw;");
        w.line("MAX colm.xy, colm, cst.w;", "y, |y| >= eps");
        w.line("RCP colm.z, colm.x;");
        w.line("RCP colm.w, colm.y;");
        w.line("MUL colm.z, colm.z, ray.w;");
        w.line("MUL colm.w, colm.w, mie.w;");
        w.line("MUL colm.zw, colm, view.w;", "C_i = s k_i0 log2(e)^2 / y_i");
    };
    w.line("!!ARBvp1.0");
    if (o.position_invariant) w.line("OPTION ARB_position_invariant;");
    w.comment("aerial: aerial perspective per vertex, height model: exponential Rayleigh and Mie");
    w.comment("profiles averaged along the segment, sunlight at 3 points of it. Generated by");
    w.comment("aerial::generate_arb_program; parameters from aerial::arb_program_parameters, once");
    w.comment("per frame.");
    w.comment("In:  vertex.position = world position in engine units, w = 1.");
    w.comment("Out: primary = F_ex (extinction; a = 1), secondary = L_in (in-scattering, exposure");
    w.comment("     applied), fogcoord = distance eye -> vertex (engine units).");
    w.line("ATTRIB pos = vertex.position;");
    if (!o.position_invariant) w.line("PARAM mvp[4] = { state.matrix.mvp };");
    w.line("PARAM eye = " + param(kHeightEye) + ";", "eye (m); w = 1 - 2^-20");
    w.line("PARAM scale = " + param(kHeightScale) + ";", "(m per unit x3, 1)");
    w.line("PARAM sun = " + param(kHeightSun) + ";", "towards the sun (away if g < 0); w = 0");
    w.line("PARAM centre = " + param(kHeightCentre) + ";", "(2 c, |eye|^2 + 2 R eye.up)");
    w.line("PARAM planet = " + param(kHeightPlanet) + ";", "(R^2, R, lowest altitude, units/m)");
    w.line("PARAM eyealt = " + param(kHeightEyeAltitude) + ";", "(h0, 1/(12 R), 1/(2 R), 0)");
    w.line("PARAM inv = " + param(kHeightInverseScaleHeights) + ";",
           "(-1, -1, 1, 1) log2(e) / (H_R, H_M)");
    w.line("PARAM extr = " + param(kHeightRayleighExtinction) + ";", "-log2(e) beta_R; w = 0");
    w.line("PARAM extm = " + param(kHeightMieExtinction) + ";", "-log2(e) beta_M,ext; w = 0");
    w.line("PARAM ray = " + param(kHeightRayleigh) + ";", "log2(e)^2 E0 beta_R 3/(16 pi)");
    w.line("PARAM mie = " + param(kHeightMie) + ";", "log2(e)^2 E0 beta_M (1 - g^2)/(4 pi)");
    w.line("PARAM hg = " + param(kHeightPhase) + ";", "(|g|, 1/4, (1 - |g|)^2, -1)");
    w.line("PARAM sky = " + param(kHeightSunColumn) + ";", "log2 sun column factors, fit offsets");
    const double c = kSeriesLimit * kLog2E;  // the limit in log2 units
    w.line("PARAM num = " + vec(2.0, -1.5, c, kLog2E) + ";", "2, -1.5, series limit, log2(e)");
    w.line(
        "PARAM ser = " +
            vec(std::pow(ln2, 4) / 120.0, -std::pow(ln2, 3) / 24.0, ln2 * ln2 / 6.0, -ln2 / 2.0) +
            ";",
        "series of (1 - 2^-y)/(y ln 2)");
    w.line("PARAM cst = " +
           vec(1.0 - one_minus_exp_over_x(kSeriesLimit), -1e-30, 1.0, -kMaxFitSlope * kLog2E) +
           ";");
    w.line("PARAM fit = " + vec(-kMinFitSlope, 2.0 * kMinFitSlope, 0.0, 0.0) + ";");
    w.line("PARAM ynode = " + vec(kGaussNodes[0], kGaussNodes[1], kGaussNodes[2], 0.0) + ";",
           "Gauss nodes in the attenuation share");
    w.line("PARAM ynode1 = " +
           vec(1.0 - kGaussNodes[0], 1.0 - kGaussNodes[1], 1.0 - kGaussNodes[2], 0.0) + ";");
    w.line("PARAM logw = " +
               vec(std::log2(kGaussWeights[0]), std::log2(kGaussWeights[1]),
                   std::log2(kGaussWeights[2]), 0.0) +
               ";",
           "log2 of the Gauss weights");
    if (full) {
        const std::array<double, kErfcxDegree + 1> q = erfcx_fit();
        w.line("PARAM sunc = " + param(kHeightTrueSun) + ";", "(sun, c.sun), c = eye + R up");
        w.line("PARAM chx = " + param(kHeightChapmanX) + ";", "(1/H_R, 1/H_M, R/H_R, R/H_M)");
        w.line("PARAM chh = " + param(kHeightChapmanH) + ";", "(1, 1, 2, 2) sqrt(pi/2) H_i");
        w.line("PARAM chc = " +
                   vec(std::sqrt(0.5) / kErfcxScale, kBlockedLogColumn * kLog2E, kBlocked, q[0]) +
                   ";",
               "sqrt(1/2)/C, log2 of the blocked factor, 'no sun', Q_0");
        w.line("PARAM erfa = " + vec(q[8], q[7], q[6], q[5]) + ";", "erfcx(y) ~ t Q(t)");
        w.line("PARAM erfb = " + vec(q[4], q[3], q[2], q[1]) + ";", "t = C/(y + C), C = 2");
        w.line("PARAM lim = " + vec(-ln2, 0.0, 0.0, 0.0) + ";");
        w.line("PARAM fitc = " + param(kHeightFitClamp) + ";", "clamp of the fit's end");
        w.line("TEMP seg, view, alt, work, rho, ext, sphi, node, colr, colm, acc, chp;");
    } else {
        w.line("TEMP seg, view, alt, work, rho, ext, sphi, node, colr, colm, acc;");
    }
    if (!o.position_invariant) {
        w.comment("Clip-space position.");
        for (int row = 0; row < 4; ++row) {
            w.line("DP4 result.position." + std::string(1, "xyzw"[row]) + ", mvp[" +
                   std::to_string(row) + "], pos;");
        }
    }
    w.comment("Segment d = vertex - eye (m), s = |d|, w = |d/s - sun|^2 = 2 (1 - cos theta).");
    w.line("MAD seg, pos, scale, -eye;", "(d, 2^-20)");
    w.line("DP4 seg.w, seg, seg;", "s^2 + 2^-40, never 0");
    w.line("RSQ node.w, seg.w;", "1/s");
    w.line("MAD view, seg, node.w, -sun;", "(d/s - sun, s)");
    w.line("DP3 view.x, view, view;", "w");
    w.line("MUL result.fogcoord.x, view.w, planet.w;", "s in engine units");
    w.comment("Phase functions without their constants: view = (w, h^-1.5, 1 + c^2, s).");
    w.line("MAD view.yz, view.x, hg.xxyx, hg.zzwz;", "h = 1 + g^2 - 2 g c, w/4 - 1");
    w.line("MAD view.z, view.z, view.x, num.x;", "1 + c^2");
    w.line("POW view.y, view.y, num.y;", "h^-1.5");
    w.comment(
        "Vertex altitude h1 = n / (|p - centre| + R), n = |p|^2 + 2 R p.up (no cancellation);");
    w.comment("alt = (h1, ., h_low, h1 - h0), h_low = min(h0, h1) - s^2/(12 R) (the mean sag).");
    w.line("DPH alt.x, seg, centre;", "2 d.c + n(eye)");
    w.line("ADD alt.x, alt.x, seg.w;", "n");
    w.line("ADD alt.y, alt.x, planet.x;", "|p - centre|^2");
    w.line("RSQ alt.z, alt.y;");
    w.line("MAD alt.y, alt.y, alt.z, planet.y;", "|p - centre| + R");
    w.line("RCP alt.y, alt.y;");
    w.line("MUL alt.x, alt.x, alt.y;");
    w.line("MAX alt.x, alt.x, planet.z;", "h1, clamped like the density");
    if (full) {
        w.line("DPH chp.x, seg, sunc;", "(c + d).sun");
        w.line("MUL chp.x, chp.x, alt.z;", "mu: cosine of the sun's zenith angle at the vertex");
    }
    w.line("MIN alt.z, alt.x, eyealt.x;");
    w.line("MAD alt.z, seg.w, -eyealt.y, alt.z;");
    w.line("MAX alt.z, alt.z, planet.z;", "h_low");
    w.line("SUB alt.w, alt.x, eyealt.x;", "rise");
    if (full) {
        w.comment("Sun column factors at the vertex, log2(H_i Ch(x_i, mu)), x_i = (R + h1)/H_i:");
        w.comment("upwards H sqrt(pi x/2) erfcx(y), y = sqrt(x/2) |mu|, with erfcx(y) ~ t Q(t).");
        w.line("MAD colr.xy, alt.x, chx, chx.zwzw;", "x_i");
        w.line("RSQ colr.z, colr.x;");
        w.line("RSQ colr.w, colr.y;");
        w.line("MUL colr.zw, colr.xyxy, colr;", "sqrt(x_i)");
        w.line("MAX colm.x, chp.x, -chp.x;", "|mu|");
        w.line("MUL colm.x, colm.x, chc.x;");
        w.line("MAD colm.xy, colr.zwzw, colm.x, cst.z;", "1 + y_i/C");
        w.line("RCP colm.x, colm.x;");
        w.line("RCP colm.y, colm.y;", "t_i");
        w.line("MAD acc.xy, colm, erfa.x, erfa.y;");
        for (const char* coefficient :
             {"erfa.z", "erfa.w", "erfb.x", "erfb.y", "erfb.z", "erfb.w"}) {
            w.line(std::string("MAD acc.xy, acc, colm, ") + coefficient + ";");
        }
        w.line("MAD acc.xy, acc, colm, chc.w;", "Q(t_i)");
        w.line("MUL acc.xy, acc, colm;", "erfcx(y_i)");
        w.line("MUL acc.xy, acc, colr.zwzw;");
        w.line("MUL acc.xy, acc, chh;", "H_i x upward Chapman factor");
        w.comment("Below the horizon: tangent altitude t = h1 sin chi - R mu^2/(1 + sin chi),");
        w.comment("H factor = 2 H sqrt(pi x_t/2) - H upward e^-(h1 - t)/H, x_t = (R + t)/H.");
        w.line("MUL ext.w, chp.x, chp.x;", "mu^2");
        w.line("ADD ext.x, cst.z, -ext.w;");
        w.line("MAX ext.x, ext.x, -cst.y;");
        w.line("RSQ ext.y, ext.x;");
        w.line("MUL ext.y, ext.x, ext.y;", "sin chi");
        w.line("ADD ext.z, ext.y, cst.z;");
        w.line("RCP ext.z, ext.z;");
        w.line("MUL ext.w, ext.w, planet.y;");
        w.line("MUL ext.z, ext.w, ext.z;");
        w.line("MAD ext.x, alt.x, ext.y, -ext.z;", "t");
        w.line("SUB ext.y, alt.x, ext.x;", "h1 - t");
        w.line("MAD rho.xy, ext.x, chx, chx.zwzw;", "x_t");
        w.line("MAX rho.xy, rho, -cst.y;");
        w.line("RSQ rho.z, rho.x;");
        w.line("RSQ rho.w, rho.y;");
        w.line("MUL rho.xy, rho, rho.zwzw;");
        w.line("MUL rho.xy, rho, chh.zwzw;", "2 H sqrt(pi x_t/2)");
        w.line("MUL rho.zw, ext.y, inv.zwzw;", "(h1 - t) log2(e)/H");
        w.line("EX2 work.x, -rho.z;");
        w.line("EX2 work.y, -rho.w;");
        w.line("MAD rho.xy, -acc, work, rho;");
        w.line("MAX rho.xy, rho, -cst.y;", "H factor below the horizon");
        w.line("SLT work.x, chp.x, fit.z;", "below the horizon");
        w.line("SGE work.y, chp.x, fit.z;", "above");
        w.line("MUL acc.xy, acc, work.y;");
        w.line("MAD acc.xy, rho, work.x, acc;");
        w.line("LG2 acc.x, acc.x;");
        w.line("LG2 acc.y, acc.y;");
        w.line("MAD acc.xy, rho.zwzw, work.x, acc;");
        w.line("MIN acc.xy, acc, chc.y;", "log2 column factors at the vertex");
        w.line("MIN ext.z, alt.x, fit.z;");
        w.line("SLT ext.z, ext.x, ext.z;");
        w.line("MUL ext.z, ext.z, work.x;", "the planet blocks the sun at the vertex,");
        w.line("SGE work.zw, acc.xyxy, chc.y;");
        w.line("MAX ext.z, ext.z, work.z;");
        w.line("MAX ext.z, ext.z, work.w;", "or a factor reaches the model's blocked value");
        w.comment(
            "Factors along the segment lr0 + (lr1 - lr0) u, as the model: a blocked end takes");
        w.comment("the other end's; both blocked: no sun (chp.xy raised beyond float range).");
        w.line("SUB work.xy, sky, acc;");
        w.line("MAD chp.xy, work, eyealt.w, acc;", "lr0");
        w.line("SUB work.xy, acc, chp;");
        w.line("SUB work.z, cst.z, ext.z;", "the vertex sees the sun");
        w.line("MUL chp.zw, work.xyxy, work.z;", "lr1 - lr0");
        w.line("MAX work.w, work.z, eyealt.w;");
        w.line("SUB work.w, cst.z, work.w;");
        w.line("MAD chp.xy, work.w, chc.z, chp;");
    }
    w.comment(
        "Path-averaged densities rho_i = exp(-h_low/H_i) phi(|rise|/H_i), phi(x) = (1-e^-x)/x:");
    w.comment("its series below c plus the quotient above c, minus phi(c) (no branch).");
    w.line("MUL work, alt.zzww, inv;", "(log2 e^(-h_low/H), y = rise log2(e)/H)");
    w.line("MAX work.zw, work, -work;", "|y|");
    w.line("MAX ext.zw, work, num.z;", "max(|y|, c)");
    w.line("MIN work.zw, work, num.z;", "min(|y|, c)");
    w.line("EX2 rho.x, work.x;");
    w.line("EX2 rho.y, work.y;");
    w.line("EX2 rho.z, -ext.z;");
    w.line("EX2 rho.w, -ext.w;");
    w.line("RCP ext.z, ext.z;");
    w.line("RCP ext.w, ext.w;");
    w.line("MAD ext.zw, -rho, ext, ext;", "quotient (1 - 2^-y)/y at max(|y|, c)");
    w.line("MAD rho.zw, work, ser.x, ser.y;");
    w.line("MAD rho.zw, rho, work, ser.z;");
    w.line("MAD rho.zw, rho, work, ser.w;");
    w.line("MAD rho.zw, rho, work, cst.x;", "series at min(|y|, c), minus phi(c)");
    w.line("MAD rho.zw, ext, num.w, rho;", "phi");
    w.line("MUL rho.xy, rho, rho.zwzw;", "rho_R, rho_M");
    w.comment("Fitted extinction profile k0 exp(-a u) through the G extinction at both ends:");
    w.comment("b = a log2(e) = log2(k0 / k(h1)), clamped like the model's, then kept off 0.");
    w.line("MAD ext.xy, alt.x, inv, sky.zwzw;", "log2(beta_i exp(-h1/H_i) / k0) + eps");
    if (full) w.line("MIN ext.xy, ext, fitc;", "the model's k_end: exp(-rise/H_i) <= e^80");
    w.line("EX2 ext.x, ext.x;");
    w.line("EX2 ext.y, ext.y;");
    w.line("ADD ext.x, ext.x, ext.y;");
    w.line("LG2 ext.x, ext.x;", "eps - b");
    w.line("MAX ext.x, ext.x, cst.w;");
    w.line("SGE ext.y, -ext.x, fit.x;");
    w.line("MAD alt.y, ext.y, fit.y, -ext.x;", "b, |b| >= eps");
    w.comment("Extinction F_ex = exp(-beta s), beta = beta_R rho_R + beta_M rho_M per channel.");
    w.line("MUL ext, extr, rho.x;");
    w.line("MAD ext, extm, rho.y, ext;");
    w.line("MUL ext, ext, view.w;", "log2 F_ex; w = 0");
    w.line("MIN ext.xyz, ext, cst.y;", "never 0");
    w.line("RCP sphi.xw, ext.x;");
    w.line("RCP sphi.y, ext.y;");
    w.line("RCP sphi.z, ext.z;");
    w.line("EX2 work.xw, ext.x;");
    w.line("EX2 work.y, ext.y;");
    w.line("EX2 work.z, ext.z;");
    w.line("SWZ result.color.primary, work, x, y, z, 1;");
    w.comment(
        "Sunlight points: Gauss nodes y_n in the share of the G attenuation. The share of the");
    w.comment("optical depth f = -ln(1 - y (1 - F_G)) / tau_G, then the fitted profile's");
    w.comment("u = -ln(1 - f (1 - 2^-b)) / (b ln 2).");
    if (full) {
        w.comment("The model places them by the G optical depth along the straight altitude");
        w.comment("profile (no sag), tau_total = tau(1) (see below), not by F_G: acc = (tau_total");
        w.comment("log2(e), ., 2^-tau_total log2(e), -1/(tau_total log2(e))).");
        optical_depth_coefficients();
        w.line("EX2 acc.x, -colm.x;");
        w.line("EX2 acc.y, -colm.y;");
        w.line("ADD acc.xy, cst.z, -acc;");
        w.line("MUL acc.xy, acc, colm.zwzw;");
        w.line("ADD acc.x, acc.x, acc.y;");
        w.line("MAX acc.x, acc.x, -cst.y;", "tau_total log2(e), never 0");
        w.line("EX2 acc.z, -acc.x;");
        w.line("RCP acc.w, -acc.x;");
        w.line("MAD node.xyz, ynode, acc.z, ynode1;");
    } else {
        w.line("MAD node.xyz, ynode, work.y, ynode1;");
    }
    w.line("LG2 rho.x, node.x;");
    w.line("LG2 rho.y, node.y;");
    w.line("LG2 rho.z, node.z;", "-tau_fit log2(e)");
    w.line(full ? "MUL node.xyz, rho, acc.w;" : "MUL node.xyz, rho, sphi.y;", "f");
    w.line("MAD sphi, -work, sphi, sphi;", "(1 - F_ex) / log2(F_ex)");
    if (full) {
        w.comment("The model's scale phi(tau_total) / phi(tau_G), tau_G with the sag; where float");
        w.comment("rounds F to 1, (1 - F)/log2(F) is 0 and takes its limit -ln(2) instead.");
        w.line("MAD acc.y, -acc.z, acc.w, acc.w;", "(1 - F_total) / log2(F_total)");
        w.line("SGE acc.z, acc.y, fit.z;");
        w.line("MAD acc.y, acc.z, lim.x, acc.y;");
        w.line("SGE acc.z, sphi.y, fit.z;");
        w.line("MAD acc.z, acc.z, lim.x, sphi.y;");
        w.line("RCP acc.z, acc.z;");
        w.line("MUL acc.y, acc.y, acc.z;");
    }
    w.line("EX2 ext.w, -alt.y;");
    w.line("ADD ext.w, ext.w, hg.w;", "E = 2^-b - 1");
    w.line("MAD node.xyz, node, ext.w, cst.z;");
    w.line("LG2 node.x, node.x;");
    w.line("LG2 node.y, node.y;");
    w.line("LG2 node.z, node.z;", "-b u");
    w.line("RCP ext.z, alt.y;", "1/b");
    w.line("MUL work.xyz, node, -ext.z;", "u");
    w.line("MUL ext.w, ext.w, ext.z;");
    w.line("MUL ext.w, ext.w, view.w;", "s E/b = -s ln(2) phi(a)");
    if (full) w.line("MUL ext.w, ext.w, acc.y;");
    if (exact) {
        w.comment("Exact optical depth to the points along the straight altitude profile,");
        w.comment(
            "tau(u) = sum_i s k_i0 (1 - 2^(-y_i u)) / (y_i ln 2), y_i = rise log2(e)/H_i kept off");
        w.comment(
            "0; the weights get exp(tau_fit - tau) (log2 units, k_i0 log2(e)^2 in ray.w, mie.w).");
        if (!full) optical_depth_coefficients();
        w.line("MUL colr.xyz, work, -colm.x;");
        w.line("MUL acc.xyz, work, -colm.y;");
        for (const char* reg : {"colr", "acc"}) {
            for (char lane : {'x', 'y', 'z'}) {
                const std::string r = std::string(reg) + "." + lane;
                w.line("EX2 " + r + ", " + r + ";");
            }
        }
        w.line("ADD ext.x, colm.z, colm.w;");
        w.line("MAD colr.xyz, -colr, colm.z, ext.x;");
        w.line("MAD colr.xyz, -acc, colm.w, colr;", "tau log2(e)");
        w.line("ADD node.xyz, node, rho;");
        w.line("ADD node.xyz, node, colr;", "-b u - (tau_fit - tau) log2(e)");
    }
    w.comment("Altitudes of the points, h0 + rise u - sag u (1 - u), sag = s^2/(2 R).");
    w.line("MUL ext.y, seg.w, eyealt.z;", "sag");
    w.line("SUB ext.x, alt.w, ext.y;");
    w.line("MAD colm.xyz, work, ext.y, ext.x;");
    w.line("MAD colm.xyz, colm, work, eyealt.x;");
    w.line("MAX colm.xyz, colm, planet.z;", "h_n");
    w.comment("Weights W_n rho_i(u_n) e^(a u_n) (the Jacobian of the fitted profile).");
    w.line("SUB node.xyz, logw, node;");
    if (full) {
        w.comment(
            "Planet shadow at each point p = eye + u d, c = eye + R up: along = (c + u d).sun < 0");
        w.comment("and |c + u d|^2 - along^2 < R^2; a shadowed point gets no weight.");
        w.line("DP3 colr.w, seg, sunc;", "d.sun");
        w.line("MAD colr.xyz, work, colr.w, sunc.w;", "along");
        w.line("DP3 acc.w, seg, centre;", "2 d.c");
        w.line("MAD acc.xyz, work, seg.w, acc.w;");
        w.line("MAD acc.xyz, acc, work, centre.w;", "|c + u d|^2 - R^2");
        w.line("MAD acc.xyz, -colr, colr, acc;");
        w.line("SLT acc.xyz, acc, fit.z;");
        w.line("SLT colr.xyz, colr, fit.z;");
        w.line("MUL acc.xyz, acc, colr;", "in the shadow");
        w.line("MAD node.xyz, acc, -chc.z, node;");
    }
    w.line("MAD seg.xyz, colm, inv.x, node;");
    w.line("MAD alt.xyz, colm, inv.y, node;");
    if (full) {
        w.line("MIN seg.xyz, seg, chc.y;", "the model's bound e^80 on the weights");
        w.line("MIN alt.xyz, alt, chc.y;");
    }
    for (const char* reg : {"seg", "alt"}) {
        for (char lane : {'x', 'y', 'z'}) {
            const std::string r = std::string(reg) + "." + lane;
            w.line("EX2 " + r + ", " + r + ";");
        }
    }
    w.comment("Sun columns at the points: the eye's Chapman factors, the points' densities.");
    if (full) {
        w.line("MAD colr.xyz, work, chp.z, chp.x;", "log2 factors at the points");
        w.line("MAD colr.xyz, colm, inv.x, colr;");
        w.line("MAD acc.xyz, work, chp.w, chp.y;");
        w.line("MAD colm.xyz, colm, inv.y, acc;");
        w.line("MIN colr.xyz, colr, chc.y;", "and on the columns (no inf: alpha stays 0)");
        w.line("MIN colm.xyz, colm, chc.y;");
    } else {
        w.line("MAD colr.xyz, colm, inv.x, sky.x;");
        w.line("MAD colm.xyz, colm, inv.y, sky.y;");
    }
    for (const char* reg : {"colr", "colm"}) {
        for (char lane : {'x', 'y', 'z'}) {
            const std::string r = std::string(reg) + "." + lane;
            w.line("EX2 " + r + ", " + r + ";");
        }
    }
    w.comment("Sun transmittance at each point, summed with the weights (node: R, acc: M).");
    for (int n = 0; n < 3; ++n) {
        const std::string lane(1, "xyz"[n]);
        w.line("MUL work, extr, colr." + lane + ";");
        w.line("MAD work, extm, colm." + lane + ", work;");
        w.line("EX2 work.x, work.x;");
        w.line("EX2 work.y, work.y;");
        w.line("EX2 work.z, work.z;", "T at point " + std::to_string(n));
        if (n == 0) {
            w.line("MUL node, work, seg.x;");
            w.line("MUL acc, work, alt.x;");
        } else {
            w.line("MAD node, work, seg." + lane + ", node;");
            w.line("MAD acc, work, alt." + lane + ", acc;");
        }
    }
    w.comment(
        "L_in = E0 s phi(tau) phi(a) (beta_R P_R sum_R + beta_M P_M sum_M), exposure included.");
    w.line("MUL colr.xy, view.zyzz, ext.w;");
    w.line("MUL colm, ray, colr.x;");
    w.line("MUL node, node, colm;");
    w.line("MUL colm, mie, colr.y;");
    w.line("MAD node, acc, colm, node;");
    w.line("MUL result.color.secondary, node, sphi;");
    if (o.texcoord_units > 0) w.comment("Texture coordinates, unchanged.");
    for (int u = 0; u < o.texcoord_units; ++u) {
        const std::string unit = "[" + std::to_string(u) + "]";
        w.line("MOV result.texcoord" + unit + ", vertex.texcoord" + unit + ";");
    }
    w.line("END");
    return w.str();
}

Result<std::vector<std::array<float, 4>>> height_parameters(const Frame<float>& frame,
                                                            const Display& display,
                                                            ArbHeightFidelity fidelity) {
    const bool full = fidelity == ArbHeightFidelity::full;
    const glm::dvec3 up = frame.view.up;
    const glm::dvec3 sun = frame.view.sun_dir;
    const double mpu = frame.view.meters_per_unit;
    const glm::dvec3 eye = frame.view.eye * mpu;  // metres
    const double r = frame.planet_radius_m;
    const double g = frame.mie_g;
    const double exposure = display.exposure;
    const glm::dvec3 centre = eye + r * up;  // from the planet centre to the eye
    const double h0 = frame.eye_altitude_m;

    // The sun column factors at the eye, capped (natural log units).
    // `full` takes them as they are where the sun reaches the eye, and its eyealt.w says whether
    // it does (the model's blocked value is kBlockedLogColumn for both components).
    const bool eye_lit = double(frame.eye_log_chapman_rayleigh) < kBlockedLogColumn &&
                         double(frame.eye_log_chapman_mie) < kBlockedLogColumn;
    const double cap = full ? kBlockedLogColumn : kMaxLogColumnFactor;
    double lf[2] = {std::min(double(frame.eye_log_chapman_rayleigh), cap),
                    std::min(double(frame.eye_log_chapman_mie), cap)};
    if (full && !eye_lit) lf[0] = lf[1] = 0.0;
    // G extinction at the eye without the sag (the model's k_total), for the fitted profile.
    const double beta_g[2] = {std::max(double(frame.rayleigh_scattering.y), 1e-30),
                              std::max(double(frame.mie_extinction.y), 1e-30)};
    const double k0_rayleigh =
        double(frame.rayleigh_scattering.y) * std::exp(-h0 * frame.inv_rayleigh_scale_height);
    const double k0_mie =
        double(frame.mie_extinction.y) * std::exp(-h0 * frame.inv_mie_scale_height);
    const double k0 = k0_rayleigh + k0_mie;
    const double log2_k0 = std::log2(std::max(k0, 1e-300));

    const double sign = g < 0.0 ? -1.0 : 1.0;
    std::vector<std::array<double, 4>> p(full ? kHeightFullParameterCount : kHeightParameterCount);
    p[kHeightEye] = {eye.x, eye.y, eye.z, 1.0 - kEpsilon};
    p[kHeightScale] = {mpu, mpu, mpu, 1.0};
    p[kHeightSun] = {sign * sun.x, sign * sun.y, sign * sun.z, 0.0};
    p[kHeightCentre] = {2.0 * centre.x, 2.0 * centre.y, 2.0 * centre.z,
                        glm::dot(eye, eye) + 2.0 * r * glm::dot(eye, up)};
    p[kHeightPlanet] = {r * r, r, frame.min_altitude_m, 1.0 / mpu};
    p[kHeightEyeAltitude] = {h0, 1.0 / (12.0 * r), 1.0 / (2.0 * r), full && eye_lit ? 1.0 : 0.0};
    const double inv_r = frame.inv_rayleigh_scale_height, inv_m = frame.inv_mie_scale_height;
    p[kHeightInverseScaleHeights] = {-kLog2E * inv_r, -kLog2E * inv_m, kLog2E * inv_r,
                                     kLog2E * inv_m};
    const double rayleigh_constant = 3.0 / (16.0 * kPi);
    const double mie_constant = (1.0 - g * g) / (4.0 * kPi);
    for (std::size_t c = 0; c < 3; ++c) {
        const int i = static_cast<int>(c);
        // Strictly negative, so that an overflowing column gives -inf, never 0 * inf.
        p[kHeightRayleighExtinction][c] = std::min(-kLog2E * frame.rayleigh_scattering[i], -1e-30);
        p[kHeightMieExtinction][c] = std::min(-kLog2E * frame.mie_extinction[i], -1e-30);
        const double light = kLog2E * kLog2E * exposure * frame.sun_irradiance_top[i];
        p[kHeightRayleigh][c] = light * frame.rayleigh_scattering[i] * rayleigh_constant;
        p[kHeightMie][c] = light * frame.mie_scattering[i] * mie_constant;
    }
    // The G extinction of each component at the eye (log2(e)^2 per metre), for the optical depth
    // of the exact_optical_depth and full levels; in the w of two vectors whose w is otherwise
    // unused.
    p[kHeightRayleigh][3] = kLog2E * kLog2E * k0_rayleigh;
    p[kHeightMie][3] = kLog2E * kLog2E * k0_mie;
    const double abs_g = std::abs(g);
    p[kHeightPhase] = {abs_g, 0.25, (1.0 - abs_g) * (1.0 - abs_g), -1.0};
    p[kHeightSunColumn] = {kLog2E * lf[0], kLog2E * lf[1],
                           std::log2(beta_g[0]) - log2_k0 + kMinFitSlope,
                           std::log2(beta_g[1]) - log2_k0 + kMinFitSlope};
    if (full) {
        const double hr = frame.rayleigh_scale_height_m, hm = frame.mie_scale_height_m;
        const double root = std::sqrt(0.5 * kPi);
        p[kHeightTrueSun] = {sun.x, sun.y, sun.z, glm::dot(centre, sun)};
        p[kHeightChapmanX] = {1.0 / hr, 1.0 / hm, r / hr, r / hm};
        p[kHeightChapmanH] = {root * hr, root * hm, 2.0 * root * hr, 2.0 * root * hm};
        // The model's k_end takes exp(min(-rise/H_i, 80)): the same bound on the exponent of
        // sky.zw's fitted end, log2(beta_i/k0) + eps + (80 - h0/H_i) log2(e).
        p[kHeightFitClamp] = {p[kHeightSunColumn][2] + (kBlockedLogColumn - h0 * inv_r) * kLog2E,
                              p[kHeightSunColumn][3] + (kBlockedLogColumn - h0 * inv_m) * kLog2E,
                              0.0, 0.0};
    }
    return to_float_parameters(p);
}

}  // namespace

const char* arb_height_fidelity_name(ArbHeightFidelity fidelity) {
    switch (fidelity) {
        case ArbHeightFidelity::automatic:
            return "automatic";
        case ArbHeightFidelity::spec_minimum:
            return "spec-minimum";
        case ArbHeightFidelity::exact_optical_depth:
            return "exact-optical-depth";
        case ArbHeightFidelity::full:
            return "full";
    }
    return "?";
}

Result<ArbHeightFidelity> parse_arb_height_fidelity(std::string_view name) {
    for (ArbHeightFidelity f : {ArbHeightFidelity::automatic, ArbHeightFidelity::spec_minimum,
                                ArbHeightFidelity::exact_optical_depth, ArbHeightFidelity::full}) {
        if (name == arb_height_fidelity_name(f)) return f;
    }
    return Error{"height_fidelity", "height_fidelity: '" + std::string(name) +
                                        "' is unknown; known: automatic, spec-minimum, "
                                        "exact-optical-depth, full"};
}

ArbHeightFidelity resolve_arb_height_fidelity(const ArbProgramOptions& options) {
    if (options.height_fidelity != ArbHeightFidelity::automatic) return options.height_fidelity;
    for (ArbHeightFidelity f : {ArbHeightFidelity::full, ArbHeightFidelity::exact_optical_depth}) {
        ArbProgramOptions o = options;
        o.model = Model::height;
        o.height_fidelity = f;
        if (o.parameter_base + arb_parameter_count(o) > o.limits.max_parameters) continue;
        const auto parsed = detail::parse_arb_text(height_program_text(o, f));
        if (parsed && !check_arb_limits(parsed->resources, o.limits, o.position_invariant)) {
            return f;
        }
    }
    return ArbHeightFidelity::spec_minimum;
}

int arb_parameter_count(const ArbProgramOptions& options) {
    if (options.model == Model::height && options.height_fidelity == ArbHeightFidelity::full) {
        return kArbHeightFullParameterCount;
    }
    if (options.model == Model::height && options.height_fidelity == ArbHeightFidelity::automatic) {
        ArbProgramOptions resolved = options;
        resolved.height_fidelity = resolve_arb_height_fidelity(options);
        return arb_parameter_count(resolved);
    }
    return arb_parameter_count(options.model);
}

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
    program.options = options;
    if (options.model == Model::height) {
        program.options.height_fidelity = resolve_arb_height_fidelity(options);
        program.text = height_program_text(options, program.options.height_fidelity);
        if (auto e = validate_options(program.options, "generate_arb_program")) return *e;
    } else {
        program.text = program_text(options);
    }
    auto parsed = detail::parse_arb_text(program.text);
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
    if (frame.model != options.model) {
        return Error{"frame.model",
                     "frame.model: aerial::arb_program_parameters(): the ARB program computes " +
                         std::string(model_name(options.model)) + " (options.model), got a frame " +
                         "prepared for " + std::string(model_name(frame.model))};
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

    if (options.model == Model::height) {
        return height_parameters(frame, display, resolve_arb_height_fidelity(options));
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

    return to_float_parameters(std::vector<std::array<double, 4>>(p.begin(), p.end()));
}

}  // namespace aerial
