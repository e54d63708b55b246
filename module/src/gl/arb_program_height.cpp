// The ARB vertex program of the height model and its per-frame parameters (the options, their
// checks and the dispatch between the models are in arb_program.cpp). The program text is
// written stage by stage (write_*), in the order the program computes; its overview is above
// height_program_text.
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "aerial/scattering.hpp"

#include "../core/height_constants.hpp"
#include "aerial/phase.hpp"
#include "arb_program_internal.hpp"

namespace aerial::detail::arb {
namespace {

/// Indices of the height program's parameters, relative to parameter_base: the rows of the
/// layout tables below (kSharedLayout, then kLowerLayout or kFullLayout).
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
    kHeightSharedCount,
    // spec_minimum and exact_optical_depth:
    kHeightRayleighSlope = kHeightSharedCount,
    kHeightMieSlope,
    kHeightParameterCount,
    // full:
    kHeightTrueSun = kHeightSharedCount,
    kHeightChapmanX,
    kHeightChapmanH,
    kHeightFitClamp,
    kHeightFullParameterCount
};

/// The layout of every level (lengths in metres, log2 the base-2 logarithm, c = eye + R up
/// from the planet centre to the eye, h0 the eye's altitude, G the channel of the quadrature).
constexpr ParameterRow kSharedLayout[] = {
    {"eye", "xyz: eye (m, View::eye * meters_per_unit); w: -2^-20 (so that d.w = 2^-20)"},
    {"scale", "(meters_per_unit x3, 0)"},
    {"sun", "xyz: sun_dir (towards the sun), negated when g < 0; w: 0"},
    {"centre", "xyz: 2 c; w: |eye|^2 + 2 R eye.up (m^2)"},
    {"planet", "(R^2, R, frame.min_altitude_m, 1 / meters_per_unit)"},
    {"eyealt", "(h0, 1/(12 R), 1/(2 R), w): w = 1 if the sun reaches the eye (read by full)"},
    {"inv", "log2(e) (-1/H_R, -1/H_M, 1/H_R, 1/H_M)"},
    {"extr", "xyz: -log2(e) beta_R (<= -1e-30); w: 0"},
    {"extm", "xyz: -log2(e) beta_M,extinction (<= -1e-30); w: 0"},
    {"ray", "xyz: log2(e)^2 exposure E_sun0 beta_R 3/(16 pi); w: log2(e)^2 k_R,G(h0) (exact on)"},
    {"mie", "xyz: log2(e)^2 exposure E_sun0 beta_M (1-g^2)/(4 pi); w: log2(e)^2 k_M,G(h0) (same)"},
    {"hg", "(|g|, 1/4, (1 - |g|)^2, -1)"},
    {"sky",
     "xy: log2(e) eye's log Chapman factors (R, M; capped at 40 log2(e) below full, for "
     "full 0 where the eye's sun is blocked); zw: log2(beta_i,G / k_G(h0)) + 2^-10"},
};
/// spec_minimum and exact_optical_depth: the sun columns' change along the segment.
constexpr ParameterRow kLowerLayout[] = {
    {"slr", "xyz: gradient of sky.x along d = vertex - eye at the eye, per m (0 if blocked); w: 0"},
    {"slm", "xyz: the same for sky.y (Mie); w: 0"},
};
/// full: the sun's column factors at the vertex.
constexpr ParameterRow kFullLayout[] = {
    {"sunc", "xyz: sun_dir (not negated); w: c.sun_dir (m)"},
    {"chx", "(1/H_R, 1/H_M, R/H_R, R/H_M): x = (R + h)/H at altitude h"},
    {"chh", "(1, 1, 2, 2) sqrt(pi/2) (H_R, H_M, H_R, H_M) (m)"},
    {"fitc", "xy: sky.zw + (80 - h0/H_i) log2(e), the bound e^80 on the fit's end; zw: 0"},
};
// sky.xy's cap: a blocked sun becomes a column of e^40 H_i exp(-h/H_i), out up to 100 km.
// slr, slm: d lf_i/d mu at the eye (the model's own factors, a central difference) times
// d mu/d d = (sun - mu0 c/|c|)/|c| (column_slopes).
static_assert(std::size(kSharedLayout) == kHeightSharedCount &&
                  kHeightSharedCount + std::size(kLowerLayout) == kHeightParameterCount &&
                  kHeightSharedCount + std::size(kFullLayout) == kHeightFullParameterCount,
              "the layout tables and the indices disagree");
static_assert(kHeightParameterCount == kArbHeightParameterCount, "layout and count disagree");
static_assert(kHeightFullParameterCount == kArbHeightFullParameterCount,
              "layout and count disagree");

using height::kBlockedLogColumn;
using height::kMaxExponent;
using height::kMaxFitSlope;
/// 3-point Gauss-Legendre nodes and weights on [0, 1] (the height model's).
using height::kSunNodes;
using height::kSunWeights;
/// phi(x) = (1 - e^-x)/x is taken from its series below x = kSeriesLimit and from the quotient
/// above it (the quotient loses 2^-24 / x to rounding, 2^-11 / x with a coarse EX2).
constexpr double kSeriesLimit = 0.25;
/// The slope b of the fitted extinction profile (log2 units over the segment) is kept at least
/// this far from 0, where the node placement would divide 0 by 0; a shift this small moves the
/// nodes by < 1e-3 of the segment.
constexpr double kMinFitSlope = 1.0 / 1024.0;
/// spec_minimum takes phi(y) = (1 - 2^-y)/(y ln 2) at max(|y|, kMinDensityRise) (log2 units).
constexpr double kMinDensityRise = 1.0 / 1024.0;
// The height model clamps its fitted slope to +-kMaxFitSlope (natural units) and so does the
// program (from above; below it the float range suffices).
/// Below this log factor (natural units) the sun column at the eye is used as it is; a blocked sun
/// (factor >= 80) or a larger one is capped here: e^(40 + 40) still fits a float, and a column of
/// e^40 H_i exp(-h/H_i) puts the sun out up to 100 km.
constexpr double kMaxLogColumnFactor = 40.0;
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

/// The program's header comments and its declarations: the per-frame parameters (layout in
/// arb_program.hpp), the constants (`full` adds those of the erfcx fit and the blocked sun) and
/// the temporaries.
void write_height_declarations(ProgramWriter& w, const ArbProgramOptions& o, bool full,
                               bool quotient) {
    const double ln2 = std::log(2.0);
    w.line("!!ARBvp1.0");
    if (o.position_invariant) w.line("OPTION ARB_position_invariant;");
    w.comment("aerial: aerial perspective per vertex, height model: exponential Rayleigh and Mie");
    w.comment("profiles averaged along the segment, sunlight at 3 points of it. Generated by");
    w.comment("aerial::generate_arb_program; parameters from aerial::arb_program_parameters, once");
    w.comment("per frame.");
    w.comment(o.model_matrix ? "In:  vertex.position = model-space position, w = 1; model0..2: the"
                             : "In:  vertex.position = world position in engine units, w = 1.");
    if (o.model_matrix) w.comment("     model matrix's top rows (world = M * vertex.position).");
    w.comment("Out: primary = F_ex (extinction; a = 1), secondary = L_in (in-scattering, exposure");
    w.comment("     applied), fogcoord = distance eye -> vertex (engine units).");
    w.line("ATTRIB pos = vertex.position;");
    if (!o.position_invariant) w.line("PARAM mvp[4] = { state.matrix.mvp };");
    write_parameter_declarations(w, o,
                                 full ? ArbHeightFidelity::full : ArbHeightFidelity::spec_minimum);
    const double c = kSeriesLimit * kLog2E;  // the limit in log2 units
    w.line("PARAM num = " + format_float4(2.0, -1.5, c, kLog2E) + ";",
           "2, -1.5, series limit, log2(e)");
    if (!quotient) {
        w.line("PARAM ser = " +
                   format_float4(std::pow(ln2, 4) / 120.0, -std::pow(ln2, 3) / 24.0,
                                 ln2 * ln2 / 6.0, -ln2 / 2.0) +
                   ";",
               "series of (1 - 2^-y)/(y ln 2)");
    }
    w.line("PARAM cst = " +
           format_float4(1.0 - one_minus_exp_over_x(kSeriesLimit), -height::kMinChapmanFactor, 1.0,
                         -kMaxFitSlope * kLog2E) +
           ";");
    w.line("PARAM fit = " + format_float4(-kMinFitSlope, 2.0 * kMinFitSlope, 0.0, 0.0) + ";");
    if (quotient) {
        w.line("PARAM dens = " + format_float4(std::log2(kLog2E), kMinDensityRise, 0.0, 0.0) + ";",
               "log2(log2(e)), smallest |y|");
    }
    w.line("PARAM ynode = " + format_float4(kSunNodes[0], kSunNodes[1], kSunNodes[2], 0.0) + ";",
           "Gauss nodes in the attenuation share");
    w.line("PARAM ynode1 = " +
           format_float4(1.0 - kSunNodes[0], 1.0 - kSunNodes[1], 1.0 - kSunNodes[2], 0.0) + ";");
    w.line("PARAM logw = " +
               format_float4(std::log2(kSunWeights[0]), std::log2(kSunWeights[1]),
                             std::log2(kSunWeights[2]), 0.0) +
               ";",
           "log2 of the Gauss weights");
    if (full) {
        const std::array<double, kErfcxDegree + 1> q = erfcx_fit();
        w.line("PARAM chc = " +
                   format_float4(std::sqrt(0.5) / kErfcxScale, kBlockedLogColumn * kLog2E, kBlocked,
                                 q[0]) +
                   ";",
               "sqrt(1/2)/C, log2 of the blocked factor, 'no sun', Q_0");
        w.line("PARAM erfa = " + format_float4(q[8], q[7], q[6], q[5]) + ";", "erfcx(y) ~ t Q(t)");
        w.line("PARAM erfb = " + format_float4(q[4], q[3], q[2], q[1]) + ";",
               "t = C/(y + C), C = 2");
        w.line("PARAM lim = " + format_float4(-ln2, 0.0, 0.0, 0.0) + ";");
    }
    w.line(full ? "TEMP seg, view, alt, work, rho, ext, sphi, node, colr, colm, acc, chp;"
                : "TEMP seg, view, alt, work, rho, ext, sphi, node, colr, colm, acc;");
}

/// colm = (y_R, y_M, C_R, C_M) of the exact optical depth tau(u) (see write_exact_optical_depth).
void write_optical_depth_coefficients(ProgramWriter& w) {
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
}

/// The segment d = vertex - eye, its length s (and the fog coordinate), and both phase functions
/// without their constants.
void write_segment_and_phases(ProgramWriter& w, const ArbProgramOptions& o) {
    w.comment("Segment d = vertex - eye (m), s = |d|, w = |d/s - sun|^2 = 2 (1 - cos theta).");
    write_world_segment(w, o, "seg", "scale", "(d, 2^-20)");
    w.line("DP4 seg.w, seg, seg;", "s^2 + 2^-40, never 0");
    w.line("RSQ node.w, seg.w;", "1/s");
    w.line("MAD view, seg, node.w, -sun;", "(d/s - sun, s)");
    w.line("DP3 view.x, view, view;", "w");
    w.line("MUL result.fogcoord.x, view.w, planet.w;", "s in engine units");
    w.comment("Phase functions without their constants: view = (w, h^-1.5, 1 + c^2, s).");
    w.line("MAD view.yz, view.x, hg.xxyx, hg.zzwz;", "h = 1 + g^2 - 2 g c, w/4 - 1");
    w.line("MAD view.z, view.z, view.x, num.x;", "1 + c^2");
    w.line("POW view.y, view.y, num.y;", "h^-1.5");
}

/// The vertex altitude h1, h_low and the rise h1 - h0; `full` also the sun's zenith cosine there.
void write_vertex_altitude(ProgramWriter& w, bool full) {
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
    if (!full) {
        // view.x (w) is free after the phases, acc until the transmittance sums.
        w.line("DP3 view.x, seg, slr;", "lr1 - lr0 (log2), to first order in d");
        w.line("DP3 acc.w, seg, slm;");
    }
}

/// full: the upward sun column factors at the vertex, H_i sqrt(pi x_i/2) erfcx(y_i).
void write_vertex_upward_factors(ProgramWriter& w) {
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
    for (const char* coefficient : {"erfa.z", "erfa.w", "erfb.x", "erfb.y", "erfb.z", "erfb.w"}) {
        w.line(std::string("MAD acc.xy, acc, colm, ") + coefficient + ";");
    }
    w.line("MAD acc.xy, acc, colm, chc.w;", "Q(t_i)");
    w.line("MUL acc.xy, acc, colm;", "erfcx(y_i)");
    w.line("MUL acc.xy, acc, colr.zwzw;");
    w.line("MUL acc.xy, acc, chh;", "H_i x upward Chapman factor");
}

/// full: the column factors below the horizon, the choice between them and the upward ones, and
/// whether the planet blocks the sun at the vertex.
void write_vertex_below_horizon_factors(ProgramWriter& w) {
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
}

/// full: the log factors at the segment's ends as the model interpolates them.
void write_segment_end_factors(ProgramWriter& w) {
    w.comment("Factors along the segment lr0 + (lr1 - lr0) u, as the model: a blocked end takes");
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

/// spec_minimum: the path-averaged densities with phi from its quotient alone, |y| kept at least
/// kMinDensityRise (phi there is within 3.4e-4 of phi(0) = 1: F_ex within 0.04 LSB). Needs a
/// full-precision EX2 near |y| = 0, where 1 - 2^-y cancels (a 2^-11 EX2 puts 2^-11 / |y| into
/// phi); the higher levels take phi from its series there and do not.
void write_quotient_densities(ProgramWriter& w) {
    w.comment(
        "Path-averaged densities rho_i = exp(-h_low/H_i) phi(|rise|/H_i), phi(x) = (1-e^-x)/x");
    w.comment("= log2(e) (1 - 2^-y)/y, y = |rise| log2(e)/H_i kept >= 2^-10.");
    w.line("MAD work, alt.zzww, inv, dens.xxzz;", "(log2(log2(e) e^(-h_low/H)), y)");
    w.line("MAX work.zw, work, -work;", "|y|");
    w.line("MAX work.zw, work, dens.y;");
    w.line("EX2 rho.x, work.x;");
    w.line("EX2 rho.y, work.y;");
    w.line("EX2 rho.z, -work.z;");
    w.line("EX2 rho.w, -work.w;");
    w.line("RCP ext.z, work.z;");
    w.line("RCP ext.w, work.w;");
    w.line("MAD ext.zw, -rho, ext, ext;", "(1 - 2^-y)/y");
    w.line("MUL rho.xy, rho, ext.zwzw;", "rho_R, rho_M");
}

/// The path-averaged densities rho_R, rho_M.
void write_densities(ProgramWriter& w) {
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
}

/// The slope b of the fitted extinction profile.
void write_fitted_profile(ProgramWriter& w, bool full) {
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
}

/// F_ex per channel (the primary colour) and (1 - F_ex) / log2(F_ex)'s reciprocals.
void write_extinction(ProgramWriter& w) {
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
}

/// The sunlight points: the Gauss nodes' u along the segment, and the path factor s E/b.
void write_node_placement(ProgramWriter& w, bool full) {
    w.comment(
        "Sunlight points: Gauss nodes y_n in the share of the G attenuation. The share of the");
    w.comment("optical depth f = -ln(1 - y (1 - F_G)) / tau_G, then the fitted profile's");
    w.comment("u = -ln(1 - f (1 - 2^-b)) / (b ln 2).");
    if (full) {
        w.comment("The model places them by the G optical depth along the straight altitude");
        w.comment("profile (no sag), tau_total = tau(1) (see below), not by F_G: acc = (tau_total");
        w.comment("log2(e), ., 2^-tau_total log2(e), -1/(tau_total log2(e))).");
        write_optical_depth_coefficients(w);
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
}

/// exact_optical_depth and full: the weights' correction exp(tau_fit - tau) at the points.
void write_exact_optical_depth(ProgramWriter& w, bool full) {
    w.comment("Exact optical depth to the points along the straight altitude profile,");
    w.comment(
        "tau(u) = sum_i s k_i0 (1 - 2^(-y_i u)) / (y_i ln 2), y_i = rise log2(e)/H_i kept off");
    w.comment(
        "0; the weights get exp(tau_fit - tau) (log2 units, k_i0 log2(e)^2 in ray.w, mie.w).");
    if (!full) write_optical_depth_coefficients(w);
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

/// The points' altitudes and their weights (`full`: none in the planet's shadow, bounded like
/// the model's).
void write_node_weights(ProgramWriter& w, bool full) {
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
}

/// The sun columns at the points.
void write_node_columns(ProgramWriter& w, bool full) {
    w.comment("Sun columns at the points: the eye's Chapman factors, the points' densities.");
    if (full) {
        w.line("MAD colr.xyz, work, chp.z, chp.x;", "log2 factors at the points");
        w.line("MAD colr.xyz, colm, inv.x, colr;");
        w.line("MAD acc.xyz, work, chp.w, chp.y;");
        w.line("MAD colm.xyz, colm, inv.y, acc;");
        w.line("MIN colr.xyz, colr, chc.y;", "and on the columns (no inf: alpha stays 0)");
        w.line("MIN colm.xyz, colm, chc.y;");
    } else {
        w.line("MAD colr.xyz, work, view.x, sky.x;");
        w.line("MAD colr.xyz, colm, inv.x, colr;");
        w.line("MAD ext.xyz, work, acc.w, sky.y;");
        w.line("MAD colm.xyz, colm, inv.y, ext;");
    }
    for (const char* reg : {"colr", "colm"}) {
        for (char lane : {'x', 'y', 'z'}) {
            const std::string r = std::string(reg) + "." + lane;
            w.line("EX2 " + r + ", " + r + ";");
        }
    }
}

/// The sun transmittance at each point, summed with the weights.
void write_transmittance_sums(ProgramWriter& w) {
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
}

/// L_in (the secondary colour).
void write_in_scattering(ProgramWriter& w) {
    w.comment(
        "L_in = E0 s phi(tau) phi(a) (beta_R P_R sum_R + beta_M P_M sum_M), exposure included.");
    w.line("MUL colr.xy, view.zyzz, ext.w;");
    w.line("MUL colm, ray, colr.x;");
    w.line("MUL node, node, colm;");
    w.line("MUL colm, mie, colr.y;");
    w.line("MAD node, acc, colm, node;");
    w.line("MUL result.color.secondary, node, sphi;");
}

}  // namespace

std::vector<ParameterRow> height_layout(ArbHeightFidelity fidelity) {
    std::vector<ParameterRow> rows(std::begin(kSharedLayout), std::end(kSharedLayout));
    if (fidelity == ArbHeightFidelity::full) {
        rows.insert(rows.end(), std::begin(kFullLayout), std::end(kFullLayout));
    } else {
        rows.insert(rows.end(), std::begin(kLowerLayout), std::end(kLowerLayout));
    }
    return rows;
}

namespace {

/// The change of the log2 sun column factors (Rayleigh, Mie) per metre of d = vertex - eye, to
/// first order: d lf/d mu at the eye times d mu/d d = (sun - mu0 c/|c|)/|c|, c = eye + R up.
std::array<glm::dvec3, 2> column_slopes(const Frame<float>& frame, bool eye_lit) {
    if (!eye_lit) return {glm::dvec3(0), glm::dvec3(0)};
    const glm::dvec3 up = frame.view.up, sun = frame.view.sun_dir;
    const glm::dvec3 eye = frame.view.eye * frame.view.meters_per_unit;
    const glm::dvec3 c = eye + double(frame.planet_radius_m) * up;
    const double length = glm::length(c);
    const glm::dvec3 zenith = c / length;
    const double mu0 = glm::dot(zenith, sun);
    const glm::dvec3 side = sun - mu0 * zenith;  // the sun's horizontal direction at the eye
    const double side_length = glm::length(side);
    const glm::dvec3 horizontal = side_length > 1e-9 ? side / side_length : glm::dvec3(0);
    // The log factors of a sun at zenith cosine mu (same eye), by the model's own code.
    const auto factors = [&](double mu) {
        Frame<float> f = frame;
        const double m = std::clamp(mu, -1.0, 1.0);
        f.view.sun_dir = m * zenith + std::sqrt(std::max(0.0, 1.0 - m * m)) * horizontal;
        f.sun_dir = glm::vec3(f.view.sun_dir);
        const Frame<float> g = frame_with_eye(f, eye);
        return glm::dvec2(g.eye_log_chapman_rayleigh, g.eye_log_chapman_mie);
    };
    const double step = 1e-3;
    const double lo = std::max(mu0 - step, -1.0), hi = std::min(mu0 + step, 1.0);
    glm::dvec2 derivative = (factors(hi) - factors(lo)) / (hi - lo);
    const glm::dvec2 f_lo = factors(lo), f_hi = factors(hi);
    if (f_lo.x >= kBlockedLogColumn || f_hi.x >= kBlockedLogColumn || f_lo.y >= kBlockedLogColumn ||
        f_hi.y >= kBlockedLogColumn) {
        derivative = glm::dvec2(0);
    }
    const glm::dvec3 dmu = (sun - mu0 * zenith) / length;
    return {kLog2E * derivative.x * dmu, kLog2E * derivative.y * dmu};
}

}  // namespace

// The height program. Per vertex, like height_model() in scattering.cpp (metres; d = p - eye,
// s = |d|, the G channel drives the quadrature):
//   h1 = n / (|p - centre| + R), n = |p|^2 + 2 R p.up (from the eye's n: no cancellation);
//   rho_i = exp(-h_low/H_i) phi(|h1 - h0|/H_i), h_low = min(h0, h1) - s^2/(12 R),
//     phi(x) = (1 - e^-x)/x: at spec_minimum its quotient at max(x, 2^-10 ln 2); above, as
//     S(min(x, c)) + Q(max(x, c)) - phi(c): the series S is right below c, the quotient Q above
//     it, and neither needs a branch (c = 0.25), which a coarse EX2 does not upset;
//   F_ex = exp(-beta s), beta = beta_R rho_R + beta_M rho_M per channel;
//   the fitted G profile k0 exp(-a u), a = ln(k0 / k(h1)) (b = a log2(e), kept >= 2^-10 from 0);
//   nodes y_n (3-point Gauss) in the share of the attenuation: f_n = -ln(1 - y_n (1 - F_G))/tau_G,
//     u_n = -ln(1 - f_n (1 - e^-a))/a, altitude h_n = h0 + (h1 - h0) u_n - sag u_n (1 - u_n);
//   weights W_n rho_i(h_n) e^(a u_n), sun transmittance at each node from the eye's Chapman
//     factors plus their change along d to first order (slr, slm: lr0 + (d.sl) u_n, where the
//     model interpolates to the vertex's exact factors) and the node's densities;
//   L_in = E0 s phi(tau_c) phi(a) sum_i beta_i P_i sum_n weight_in T_n (exposure in the params).
// What the model does and spec_minimum does not (128 instructions): the node placement by the
// optical depth without the sag and the scale phi(tau_total)/phi(tau_G) (about 14 instructions),
// the weights' correction by exp(tau_fit(u_n) - tau(u_n)) (about 20: six more EX2 and a guarded
// division), the exact column factors at the vertex (an erfcx and its below-horizon branch,
// about 60 with the interpolation) and the planet-shadow test per node (about 10). Budget: 4
// transform (3 more for the model matrix), 6 distance and fog, 3 phase, 14 altitude and column
// slopes, 11 densities, 8 fit, 11 F_ex, 14 nodes, 6 node altitudes, 9 weights, 10 columns, 21
// transmittance sums, 6 L_in, 1 per texture unit: 125 with one unit.
// exact_optical_depth adds the correction and phi's series (29 more: 154). full adds the rest of
// the model (249): the vertex's column factors (the erfcx fit, the below-horizon branch, the
// choice between them, the blocked tests and the ends' interpolation), the shadow per node,
// tau_total without the sag for the node placement and the scale phi(tau_total)/phi(tau_G), the
// model's bounds on the fit, the weights and the columns, and the interpolated factors at the
// nodes.
std::string height_program_text(const ArbProgramOptions& o, ArbHeightFidelity fidelity) {
    const bool exact = fidelity != ArbHeightFidelity::spec_minimum;
    const bool full = fidelity == ArbHeightFidelity::full;
    ProgramWriter w;
    write_height_declarations(w, o, full, !exact);
    write_clip_space_position(w, o);
    write_segment_and_phases(w, o);
    write_vertex_altitude(w, full);
    if (full) {
        write_vertex_upward_factors(w);
        write_vertex_below_horizon_factors(w);
        write_segment_end_factors(w);
    }
    if (exact) {
        write_densities(w);
    } else {
        write_quotient_densities(w);
    }
    write_fitted_profile(w, full);
    write_extinction(w);
    write_node_placement(w, full);
    if (exact) write_exact_optical_depth(w, full);
    write_node_weights(w, full);
    write_node_columns(w, full);
    write_transmittance_sums(w);
    write_in_scattering(w);
    write_texcoords_and_end(w, o);
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
    // d = world * scale - eye: d.w = 0 - (-2^-20), whatever the world position's w.
    p[kHeightEye] = {eye.x, eye.y, eye.z, -kEpsilon};
    p[kHeightScale] = {mpu, mpu, mpu, 0.0};
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
    if (!full) {
        const std::array<glm::dvec3, 2> slope = column_slopes(frame, eye_lit);
        p[kHeightRayleighSlope] = {slope[0].x, slope[0].y, slope[0].z, 0.0};
        p[kHeightMieSlope] = {slope[1].x, slope[1].y, slope[1].z, 0.0};
    }
    if (full) {
        const double hr = frame.rayleigh_scale_height_m, hm = frame.mie_scale_height_m;
        const double root = std::sqrt(0.5 * kPi);
        p[kHeightTrueSun] = {sun.x, sun.y, sun.z, glm::dot(centre, sun)};
        p[kHeightChapmanX] = {1.0 / hr, 1.0 / hm, r / hr, r / hm};
        p[kHeightChapmanH] = {root * hr, root * hm, 2.0 * root * hr, 2.0 * root * hm};
        // The model's k_end takes exp(min(-rise/H_i, kMaxExponent)): the same bound on the exponent
        // of sky.zw's fitted end, log2(beta_i/k0) + eps + (80 - h0/H_i) log2(e).
        p[kHeightFitClamp] = {p[kHeightSunColumn][2] + (kMaxExponent - h0 * inv_r) * kLog2E,
                              p[kHeightSunColumn][3] + (kMaxExponent - h0 * inv_m) * kLog2E, 0.0,
                              0.0};
    }
    return to_float_parameters(p);
}

}  // namespace aerial::detail::arb
