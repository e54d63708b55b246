// The stability map: one parameter swept at a time, every method against the `reference`
// model in 8-bit steps of what the fixed pipeline is handed, with the artefacts flagged. See
// stability.hpp; docs/benchmarks.md ("Where methods fail") documents the CSV and the findings.
#include "bench/stability.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/validation/arb_executor.hpp"
#include "aerial/validation/scene_render.hpp"
#include "support/cli.hpp"

namespace aerial::bench {
namespace {

using validation::ArbCpuProgram;
using validation::ArbInterpreterOptions;
using validation::ArbMachine;
using validation::ArbResults;
using validation::ArbVertex;
using validation::count_approximate_instructions;
using validation::parse_arb_program;
using validation::run_arb_program;

constexpr const char* kTool = "aerial-bench";
constexpr double kDegree = kPi / 180.0;

/// Display of every method: L_in times this exposure, clamped as GL clamps colours. At 8 a sky
/// of the `earth` preset at noon sits near 0.7 and the Mie lobe saturates, as a game would set it.
constexpr float kExposure = 8.0f;
/// The error the issue calls visible.
constexpr int kFailLsb = 2;
/// The sun's disc (0.27 degrees of radius) and the first degree around it, where no per-vertex
/// method is asked to follow the Mie peak (the CSV's max_lsb_off_sun leaves such probes out).
constexpr double kNearSunDeg = 1.27;
/// The precision ARB_vertex_program promises for EXP/LOG (~11 bits), applied to every
/// approximate instruction to emulate hardware of the era (tests '*OldHardware*').
constexpr float kOldHardwareError = 1.0f / 2048.0f;
/// Per-vertex interpolation: a triangle edge subtending this angle at the eye (about 43 pixels
/// of a 640-pixel-wide, 60-degree view) ...
constexpr double kScreenEdgeDeg = 4.0;
/// ... or this long in the world (a coarse terrain grid).
constexpr double kWorldEdgeM = 1000.0;

/// One sample: F_ex (3 channels) then exposure * L_in (3 channels), before any clamp.
using Values = std::array<double, 6>;

enum Method : int {
    kReference,
    kCpuHp,
    kCpuHeight,
    kArbHp,
    kArbHp10bit,
    kArbHeight,
    kArbHeight10bit,
    kGlFog,
    kFgFog,
    kLerpScreen,
    kLerpWorld,
    kMethodCount
};

const char* method_name(int m) {
    static const char* const names[kMethodCount] = {
        "reference",    "cpu-hp",           "cpu-height",       "arb-hp",
        "arb-hp-10bit", "arb-height",       "arb-height-10bit", "gl-fog",
        "fg-fog",       "lerp-screen-4deg", "lerp-world-1km"};
    return names[m];
}

/// What one sample of a sweep sets.
/// The base case is a low afternoon sun, whose Mie peak lies on the terrain.
struct Case {
    Atmosphere atmosphere;
    double sun_elevation_deg = 10.0;
    double altitude_m = 2.0;
    std::vector<double> distances_m{300.0, 3000.0, 30000.0};
};

struct Sweep {
    std::string name;  ///< the CSV's `sweep` column and the chart panel
    std::vector<double> values;
    std::function<Result<Case>(double)> make;
    /// For a slow motion (sun, camera): the value one frame later, at which popping is
    /// measured; empty for parameters that do not move during play.
    std::function<double(double)> next_frame;
};

/// A point the methods shade and how to name it in the CSV's worst_at column.
struct Probe {
    glm::dvec3 position;
    glm::dvec3 side;  ///< unit, perpendicular to the view ray: the interpolated edge's direction
    std::string where;
    bool near_sun = false;  ///< within kNearSunDeg of the sun's centre (the disc and 1 degree)
};

std::vector<double> linear(double a, double b, int n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(a + (b - a) * i / (n - 1));
    return v;
}

std::vector<double> logarithmic(double a, double b, int n) {
    std::vector<double> v;
    for (int i = 0; i < n; ++i) v.push_back(a * std::pow(b / a, double(i) / (n - 1)));
    return v;
}

glm::dvec3 direction(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

std::string format(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return buffer;
}

/// Per distance: ground points (sea level) at four azimuths from the sun's, points 5 degrees
/// above the horizon at the same azimuths, and the point towards the sun (the Mie peak; at the
/// horizon when the sun is below it).
std::vector<Probe> probes(const Case& c) {
    const glm::dvec3 eye(0.0, 0.0, c.altitude_m), up(0.0, 0.0, 1.0);
    std::vector<Probe> out;
    const glm::dvec3 sun = direction(c.sun_elevation_deg, 0.0);
    const auto add = [&](const glm::dvec3& p, const std::string& where) {
        const glm::dvec3 ray = glm::normalize(p - eye);
        // Across the view, horizontal; for a ray straight up (the sun at the zenith) any
        // horizontal direction is.
        const glm::dvec3 across = glm::cross(ray, up);
        const glm::dvec3 side =
            glm::length(across) > 1e-6 ? glm::normalize(across) : glm::dvec3(0.0, 1.0, 0.0);
        const bool near_sun =
            std::acos(std::clamp(glm::dot(ray, sun), -1.0, 1.0)) < kNearSunDeg * kDegree;
        out.push_back({p, side, where, near_sun});
    };
    for (double d : c.distances_m) {
        const std::string at = "d=" + format(d);
        for (double azimuth : {0.0, 60.0, 120.0, 180.0}) {
            const glm::dvec3 h = direction(0.0, azimuth);
            const std::string az = " az=" + format(azimuth);
            add({d * h.x, d * h.y, 0.0}, at + " ground" + az);
            add(eye + d * direction(5.0, azimuth), at + " up5" + az);
        }
        add(eye + d * direction(std::max(c.sun_elevation_deg, 0.0), 0.0), at + " sun");
    }
    return out;
}

Values from_scattering(const glm::dvec3& extinction, const glm::dvec3& in_scattering) {
    return {extinction.r,
            extinction.g,
            extinction.b,
            double(kExposure) * in_scattering.r,
            double(kExposure) * in_scattering.g,
            double(kExposure) * in_scattering.b};
}

double clamp01(double v) { return std::isfinite(v) ? std::min(1.0, std::max(0.0, v)) : 0.0; }

/// The 8-bit code the display shows (batch.hpp's rule, in double).
int code(double v) { return int(std::floor(clamp01(v) * 255.0 + 0.5)); }

/// The ARB programs as the CPU interpreter runs them.
struct Programs {
    ArbCpuProgram hp, height;
    ArbProgramOptions hp_options, height_options;
    std::vector<std::uint32_t> hp_patterns, height_patterns;
};

/// Sign patterns of the 2^-11 perturbation: all of them when there are few approximate
/// instructions, else all-plus, all-minus and seeded ones.
std::vector<std::uint32_t> sign_patterns(int approximate) {
    std::vector<std::uint32_t> patterns;
    if (approximate <= 6) {
        for (std::uint32_t p = 0; p < (1u << approximate); ++p) patterns.push_back(p);
        return patterns;
    }
    patterns = {0u, ~0u};
    std::uint32_t seed = 12345u;
    while (patterns.size() < 24) {
        seed = seed * 1664525u + 1013904223u;
        patterns.push_back(seed);
    }
    return patterns;
}

Result<Programs> make_programs() {
    Programs p;
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        ArbProgramOptions options;
        options.model = model;
        auto generated = generate_arb_program(options);
        if (!generated) return generated.error();
        auto parsed = parse_arb_program(generated->text);
        if (!parsed) return parsed.error();
        const auto patterns = sign_patterns(count_approximate_instructions(*parsed));
        if (model == Model::hoffman_preetham) {
            p.hp = *parsed;
            p.hp_options = generated->options;
            p.hp_patterns = patterns;
        } else {
            p.height = *parsed;
            p.height_options = generated->options;
            p.height_patterns = patterns;
        }
    }
    return p;
}

Values arb_values(const ArbResults& r) {
    return {r.color_primary.value[0],   r.color_primary.value[1],   r.color_primary.value[2],
            r.color_secondary.value[0], r.color_secondary.value[1], r.color_secondary.value[2]};
}

/// The farthest from `reference` (in displayed codes) of each value over the sign patterns; each
/// pattern's values are appended to per_pattern[pattern].
Values arb_worst(const ArbCpuProgram& program, const ArbMachine& machine, const ArbVertex& vertex,
                 const std::vector<std::uint32_t>& patterns, const Values& reference,
                 std::vector<std::vector<Values>>& per_pattern) {
    per_pattern.resize(patterns.size());
    Values worst{};
    std::array<int, 6> worst_lsb{};
    worst_lsb.fill(-1);
    for (std::size_t p = 0; p < patterns.size(); ++p) {
        ArbInterpreterOptions o;
        o.relative_error = kOldHardwareError;
        o.sign_pattern = patterns[p];
        const Values v = arb_values(run_arb_program(program, machine, vertex, o));
        per_pattern[p].push_back(v);
        for (std::size_t k = 0; k < 6; ++k) {
            const int lsb = std::isfinite(v[k]) ? std::abs(code(v[k]) - code(reference[k])) : 256;
            if (lsb > worst_lsb[k]) {
                worst_lsb[k] = lsb;
                worst[k] = v[k];
            }
        }
    }
    return worst;
}

/// Fog of one frame: F = f, L = (1 - f) colour, f from the distance.
Values fog_values(double f, const std::array<double, 3>& colour) {
    return {f, f, f, (1.0 - f) * colour[0], (1.0 - f) * colour[1], (1.0 - f) * colour[2]};
}

/// Every method's values at every probe of one case; [method][probe].
struct CaseResult {
    std::vector<std::vector<Values>> values;
    /// The 10-bit methods' values under each sign pattern, [method][pattern][probe] (empty for
    /// the other methods): each pattern is one consistent piece of hardware, so banding and
    /// popping are counted per pattern, while `values` keeps the worst error of each value.
    std::vector<std::vector<std::vector<Values>>> patterns;
    std::vector<std::string> where;
    std::vector<bool> near_sun;  ///< per probe (Probe::near_sun)

    /// The value sets whose steps are compared: the patterns, or `values` itself.
    std::vector<const std::vector<Values>*> variants(int method) const {
        std::vector<const std::vector<Values>*> out;
        for (const auto& p : patterns[std::size_t(method)]) out.push_back(&p);
        if (out.empty()) out.push_back(&values[std::size_t(method)]);
        return out;
    }
};

Result<CaseResult> evaluate_case(const Case& c, const Programs& programs) {
    View view;
    view.eye = {0.0, 0.0, c.altitude_m};
    view.sun_dir = direction(c.sun_elevation_deg, 0.0);
    auto reference = prepare_frame<double>(c.atmosphere, view, Model::reference);
    if (!reference) return reference.error();
    auto hp = prepare_frame<float>(c.atmosphere, view, Model::hoffman_preetham);
    auto height = prepare_frame<float>(c.atmosphere, view, Model::height);
    if (!hp) return hp.error();
    if (!height) return height.error();
    Display display;
    display.exposure = kExposure;
    auto hp_parameters = arb_program_parameters(*hp, display, programs.hp_options);
    auto height_parameters = arb_program_parameters(*height, display, programs.height_options);
    if (!hp_parameters) return hp_parameters.error();
    if (!height_parameters) return height_parameters.error();
    ArbMachine hp_machine, height_machine;
    hp_machine.local = *hp_parameters;
    height_machine.local = *height_parameters;

    // gl-fog: GL_EXP with the density and colour aerial-render's fog backend fits (the G
    // channel's extinction and the isotropic haze colour at the eye's altitude).
    const validation::FogParameters fog = validation::fog_parameters(*height, display);
    const std::array<double, 3> fog_colour{fog.colour[0], fog.colour[1], fog.colour[2]};
    // fg-fog: FlightGear's exp(-x - x^4), x = d / lambda, with the same attenuation length
    // lambda = 1 / density, and its haze colour: grey haze (the G channel's single-scattering
    // albedo, isotropic) lit by the sun's colour at the eye.
    const double lambda_m = 1.0 / std::max(double(fog.density), 1e-30);
    std::array<double, 3> haze_colour{};
    {
        const double h = std::max(double(height->eye_altitude_m), double(height->min_altitude_m));
        const double r = std::exp(-h / c.atmosphere.rayleigh_scale_height_m);
        const double m = std::exp(-h / c.atmosphere.mie_scale_height_m);
        const double scattering =
            c.atmosphere.rayleigh_scattering.g * r + c.atmosphere.mie_scattering.g * m;
        const double extinction =
            c.atmosphere.rayleigh_scattering.g * r + c.atmosphere.mie_extinction().g * m;
        const double albedo = extinction > 0.0 ? scattering / extinction : 0.0;
        for (int k = 0; k < 3; ++k) {
            haze_colour[std::size_t(k)] = clamp01(
                double(kExposure) * double(height->sun_irradiance_eye[k]) * albedo / (4.0 * kPi));
        }
    }

    const auto exact = [&](const glm::dvec3& p) {
        const Scattering<double> s = scatter(*reference, p);
        return from_scattering(s.extinction, s.in_scattering);
    };
    // GL interpolates the clamped vertex colours; the edge is centred on the probe, so the
    // interpolated value there is the mean of its two ends.
    const auto lerp = [&](const glm::dvec3& a, const glm::dvec3& b) {
        const Values va = exact(a), vb = exact(b);
        Values v{};
        for (std::size_t k = 0; k < 6; ++k) v[k] = 0.5 * (clamp01(va[k]) + clamp01(vb[k]));
        return v;
    };

    CaseResult result;
    result.values.assign(kMethodCount, {});
    result.patterns.assign(kMethodCount, {});
    const glm::dvec3 eye = view.eye;
    for (const Probe& probe : probes(c)) {
        const glm::dvec3 p = probe.position;
        const glm::vec3 pf(p);
        const double distance = glm::length(p - eye);
        const Values ref = exact(p);
        const auto cpu = [&](const Frame<float>& f) {
            const Scattering<float> s = scatter(f, pf);
            return from_scattering(glm::dvec3(s.extinction), glm::dvec3(s.in_scattering));
        };
        ArbVertex vertex;
        vertex.position = {pf.x, pf.y, pf.z, 1.0f};
        const double x = distance / lambda_m;

        auto& v = result.values;
        v[kReference].push_back(ref);
        v[kCpuHp].push_back(cpu(*hp));
        v[kCpuHeight].push_back(cpu(*height));
        v[kArbHp].push_back(arb_values(run_arb_program(programs.hp, hp_machine, vertex)));
        v[kArbHp10bit].push_back(arb_worst(programs.hp, hp_machine, vertex, programs.hp_patterns,
                                           ref, result.patterns[kArbHp10bit]));
        v[kArbHeight].push_back(
            arb_values(run_arb_program(programs.height, height_machine, vertex)));
        v[kArbHeight10bit].push_back(arb_worst(programs.height, height_machine, vertex,
                                               programs.height_patterns, ref,
                                               result.patterns[kArbHeight10bit]));
        v[kGlFog].push_back(fog_values(std::exp(-double(fog.density) * distance), fog_colour));
        v[kFgFog].push_back(fog_values(std::exp(-x - x * x * x * x), haze_colour));
        const double half_screen = distance * std::tan(0.5 * kScreenEdgeDeg * kDegree);
        v[kLerpScreen].push_back(lerp(p - half_screen * probe.side, p + half_screen * probe.side));
        const double half_world = 0.5 * kWorldEdgeM;
        v[kLerpWorld].push_back(lerp(p - half_world * probe.side, p + half_world * probe.side));
        result.where.push_back(probe.where);
        result.near_sun.push_back(probe.near_sun);
    }
    return result;
}

/// One row of the CSV.
struct Row {
    int max_lsb = 0;
    int max_lsb_off_sun = 0;  ///< over the probes outside kNearSunDeg of the sun
    double mean_lsb = 0.0;
    double over2 = 0.0;  ///< fraction of values off by more than kFailLsb
    int nonfinite = 0, clamped = 0, banding = 0, popping = 0;
    std::string worst_at;
};

const char* const kChannel[6] = {"F_ex.r", "F_ex.g", "F_ex.b", "L_in.r", "L_in.g", "L_in.b"};

Row measure(const CaseResult& r, int method) {
    Row row;
    const auto& ref = r.values[kReference];
    const auto& m = r.values[std::size_t(method)];
    long count = 0, sum = 0, over = 0;
    const double half = 0.5 / 255.0;
    for (std::size_t i = 0; i < m.size(); ++i) {
        for (std::size_t k = 0; k < 6; ++k) {
            const double v = m[i][k], t = ref[i][k];
            if (!std::isfinite(v)) ++row.nonfinite;
            // Clamping: the method leaves [0, 1] where the truth is inside it (the display
            // saturates, or blacks out, where it should not).
            if (std::isfinite(v) && ((v > 1.0 + half && t < 1.0 - half) || (v < -half && t > half)))
                ++row.clamped;
            const int lsb = std::isfinite(v) ? std::abs(code(v) - code(t)) : 255;
            ++count;
            sum += lsb;
            if (lsb > kFailLsb) ++over;
            if (!r.near_sun[i]) row.max_lsb_off_sun = std::max(row.max_lsb_off_sun, lsb);
            if (row.worst_at.empty() || lsb > row.max_lsb) {
                row.max_lsb = lsb;
                row.worst_at = r.where[i] + " " + kChannel[k];
            }
        }
    }
    row.mean_lsb = count ? double(sum) / double(count) : 0.0;
    row.over2 = count ? double(over) / double(count) : 0.0;
    return row;
}

/// Banding at sample `now` of a sweep, counted over every value: the truth is monotonic through
/// `before`, `now` and `after` (steps of at least half a code, the same way), the method's
/// displayed code turns back (steps of at least one code each, opposite ways) - a visible band
/// edge on a smooth gradient. The most of any sign pattern for the 10-bit methods.
int count_banding(const CaseResult& before, const CaseResult& now, const CaseResult& after,
                  int method) {
    const auto& r0 = before.values[kReference];
    const auto& r1 = now.values[kReference];
    const auto& r2 = after.values[kReference];
    const auto v0 = before.variants(method), v1 = now.variants(method), v2 = after.variants(method);
    int most = 0;
    for (std::size_t p = 0; p < v1.size() && p < v0.size() && p < v2.size(); ++p) {
        const auto& m0 = *v0[p];
        const auto& m1 = *v1[p];
        const auto& m2 = *v2[p];
        int count = 0;
        for (std::size_t i = 0; i < m1.size() && i < m0.size() && i < m2.size(); ++i) {
            for (std::size_t k = 0; k < 6; ++k) {
                const double t1 = (clamp01(r1[i][k]) - clamp01(r0[i][k])) * 255.0;
                const double t2 = (clamp01(r2[i][k]) - clamp01(r1[i][k])) * 255.0;
                const int s1 = code(m1[i][k]) - code(m0[i][k]);
                const int s2 = code(m2[i][k]) - code(m1[i][k]);
                const bool monotonic = (t1 >= 0.5 && t2 >= 0.5) || (t1 <= -0.5 && t2 <= -0.5);
                if (monotonic && ((s1 >= 1 && s2 <= -1) || (s1 <= -1 && s2 >= 1))) ++count;
            }
        }
        most = std::max(most, count);
    }
    return most;
}

/// Popping between a sample and the next frame of a slow motion (`moved`): the method's
/// displayed code jumps by more than kFailLsb beyond the truth's jump, and by more than the truth
/// itself moves (near sunset the truth changes by many steps a frame; a method that follows it a
/// little faster or slower does not pop). Counted over every value,
/// the most of any sign pattern for the 10-bit methods.
int count_popping(const CaseResult& now, const CaseResult& moved, int method) {
    const auto& r0 = now.values[kReference];
    const auto& r1 = moved.values[kReference];
    const auto v0 = now.variants(method), v1 = moved.variants(method);
    int most = 0;
    for (std::size_t p = 0; p < v1.size() && p < v0.size(); ++p) {
        const auto& m0 = *v0[p];
        const auto& m1 = *v1[p];
        int count = 0;
        for (std::size_t i = 0; i < m1.size() && i < m0.size(); ++i) {
            for (std::size_t k = 0; k < 6; ++k) {
                const int step = code(m1[i][k]) - code(m0[i][k]);
                const int truth = code(r1[i][k]) - code(r0[i][k]);
                const int excess = std::abs(step - truth);
                if (excess > kFailLsb && excess > std::abs(truth)) ++count;
            }
        }
        most = std::max(most, count);
    }
    return most;
}

Result<Case> with_atmosphere(Result<Atmosphere> atmosphere) {
    if (!atmosphere) return atmosphere.error();
    Case c;
    c.atmosphere = *atmosphere;
    return c;
}

std::vector<Sweep> sweeps(bool quick) {
    const auto n = [quick](int full, int coarse) { return quick ? coarse : full; };
    std::vector<Sweep> s;
    // One frame of a slow motion: the sun 0.05 degrees (12 s of the real sun, or a time-lapse),
    // the camera climbing or approaching by 0.5 %.
    s.push_back({"sun_elevation_deg", linear(-10.0, 90.0, n(201, 11)),
                 [](double v) {
                     Case c;
                     c.sun_elevation_deg = v;
                     return Result<Case>(c);
                 },
                 [](double v) { return v + 0.05; }});
    s.push_back({"altitude_m", logarithmic(2.0, 30000.0, n(97, 7)),
                 [](double v) {
                     Case c;
                     c.altitude_m = v;
                     return Result<Case>(c);
                 },
                 [](double v) { return v * 1.005; }});
    s.push_back({"distance_m", logarithmic(10.0, 100000.0, n(81, 9)),
                 [](double v) {
                     Case c;
                     c.distances_m = {v};
                     return Result<Case>(c);
                 },
                 [](double v) { return v * 0.995; }});
    s.push_back({"mie_g",
                 linear(0.0, 0.99, n(100, 3)),
                 [](double v) {
                     Case c;
                     c.atmosphere.mie_g = v;
                     return Result<Case>(c);
                 },
                 {}});
    s.push_back({"turbidity",
                 logarithmic(kMinTurbidity, 32.0, n(49, 3)),
                 [](double v) { return with_atmosphere(atmosphere_from_turbidity(v)); },
                 {}});
    s.push_back({"visibility_m",
                 logarithmic(200.0, 200000.0, n(73, 3)),
                 [](double v) { return with_atmosphere(atmosphere_from_visibility(v)); },
                 {}});
    return s;
}

/// Every sample of a sweep, and of its next frame when it is a motion.
Result<std::vector<std::pair<CaseResult, CaseResult>>> run_sweep(const Sweep& sweep,
                                                                 const Programs& programs) {
    std::vector<std::pair<CaseResult, CaseResult>> results;
    for (double value : sweep.values) {
        std::pair<CaseResult, CaseResult> both;
        for (int moved = 0; moved < (sweep.next_frame ? 2 : 1); ++moved) {
            const double v = moved ? sweep.next_frame(value) : value;
            auto c = sweep.make(v);
            if (!c)
                return Error{sweep.name, sweep.name + "=" + format(v) + ": " + c.error().message};
            auto result = evaluate_case(*c, programs);
            if (!result)
                return Error{sweep.name,
                             sweep.name + "=" + format(v) + ": " + result.error().message};
            (moved ? both.second : both.first) = std::move(*result);
        }
        results.push_back(std::move(both));
    }
    return results;
}

}  // namespace

int run_stability(const std::string& out_dir, bool quick, const std::vector<std::string>& names) {
    if (out_dir.empty()) return tools::fail(kTool, "--out: required with --stability");
    std::vector<Sweep> selected;
    for (Sweep& sweep : sweeps(quick)) {
        if (names.empty() || std::find(names.begin(), names.end(), sweep.name) != names.end())
            selected.push_back(std::move(sweep));
    }
    for (const std::string& name : names) {
        if (std::none_of(selected.begin(), selected.end(),
                         [&](const Sweep& s) { return s.name == name; }))
            return tools::fail(kTool,
                               "--sweep: expected sun_elevation_deg, altitude_m, "
                               "distance_m, mie_g, turbidity or visibility_m, got '" +
                                   name + "'");
    }
    const auto start = std::chrono::steady_clock::now();
    const auto programs = make_programs();
    if (!programs) return tools::fail(kTool, "ARB program: " + programs.error().message);
    if (std::system(("mkdir -p '" + out_dir + "'").c_str()) != 0)
        return tools::fail(kTool, "--out: cannot create directory '" + out_dir + "'");
    const std::string csv_path = out_dir + "/stability.csv";
    std::FILE* csv = std::fopen(csv_path.c_str(), "w");
    if (!csv) return tools::fail(kTool, "--out: cannot write '" + csv_path + "'");
    std::fprintf(csv,
                 "sweep,value,method,max_lsb,mean_lsb,over2,nonfinite,clamped,banding,popping,"
                 "fails,worst_at,max_lsb_off_sun\n");

    // Per method: the samples where it fails, for the summary.
    std::vector<std::vector<std::string>> summary(kMethodCount);
    std::vector<int> worst(kMethodCount, 0);
    for (const Sweep& sweep : selected) {
        std::printf("sweep %s: %zu samples%s\n", sweep.name.c_str(), sweep.values.size(),
                    sweep.next_frame ? " and their next frames" : "");
        std::fflush(stdout);
        const auto results = run_sweep(sweep, *programs);
        if (!results) {
            std::fclose(csv);
            return tools::fail(kTool, results.error().message);
        }
        std::vector<int> failing(kMethodCount, 0);
        const std::size_t count = results->size();
        for (std::size_t i = 0; i < count; ++i) {
            const CaseResult& now = (*results)[i].first;
            for (int m = 0; m < kMethodCount; ++m) {
                Row row = measure(now, m);
                if (i > 0 && i + 1 < count) {
                    row.banding =
                        count_banding((*results)[i - 1].first, now, (*results)[i + 1].first, m);
                }
                if (sweep.next_frame) row.popping = count_popping(now, (*results)[i].second, m);
                const bool fails = row.max_lsb > kFailLsb || row.nonfinite || row.clamped ||
                                   row.banding || row.popping;
                failing[std::size_t(m)] += fails;
                worst[std::size_t(m)] = std::max(worst[std::size_t(m)], row.max_lsb);
                std::fprintf(csv, "%s,%s,%s,%d,%.4f,%.4f,%d,%d,%d,%d,%d,%s,%d\n",
                             sweep.name.c_str(), format(sweep.values[i]).c_str(), method_name(m),
                             row.max_lsb, row.mean_lsb, row.over2, row.nonfinite, row.clamped,
                             row.banding, row.popping, int(fails), row.worst_at.c_str(),
                             row.max_lsb_off_sun);
            }
        }
        for (int m = 0; m < kMethodCount; ++m) {
            summary[std::size_t(m)].push_back(sweep.name + " " +
                                              std::to_string(failing[std::size_t(m)]) + "/" +
                                              std::to_string(count));
        }
    }
    std::fclose(csv);

    std::printf("%-18s %8s  samples failing (> %d LSB or an artefact) per sweep\n", "method",
                "max_lsb", kFailLsb);
    for (int m = 0; m < kMethodCount; ++m) {
        std::string line;
        for (const std::string& s : summary[std::size_t(m)]) line += "  " + s;
        std::printf("%-18s %8d %s\n", method_name(m), worst[std::size_t(m)], line.c_str());
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("total %.1f s; wrote %s\n", seconds, csv_path.c_str());
    const std::string png_path = out_dir + "/stability.png";
    const std::string command = std::string("'") + AERIAL_STABILITY_PYTHON + "' '" +
                                AERIAL_STABILITY_PLOT_SCRIPT + "' '" + csv_path + "' '" + png_path +
                                "'";
    if (std::system(command.c_str()) != 0)
        return tools::fail(kTool, "the chart failed: " + command);
    std::printf("wrote %s\n", png_path.c_str());
    return 0;
}

}  // namespace aerial::bench
