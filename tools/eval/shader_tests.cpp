// aerial-eval --export-shader-tests: the generated ARB vertex programs as piglit shader_test
// files whose probes come from aerial::validation's CPU executor of the same text.
#include "eval/shader_tests.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "aerial/aerial.hpp"
#include "aerial/validation/arb_executor.hpp"

namespace aerial::eval {

ArbProgramOptions arb_program_options(Model model, std::optional<ArbHeightFidelity> fidelity) {
    ArbProgramOptions options;
    options.model = model;
    if (fidelity) {
        options.height_fidelity = *fidelity;
        options.limits = arb_reference_limits(*fidelity);
    }
    return options;
}

namespace {

constexpr const char* kFlag = "--export-shader-tests";
constexpr double kDegree = kPi / 180.0;

/// World units are pixels (ortho 0 250 0 250) and this many metres: the probes' rays run from
/// 250 m to 30 km.
constexpr double kMetersPerUnit = 250.0;
/// The eye: above pixel corner (125, 125), this high above the ground plane z = 0.
constexpr int kEyeX = 125, kEyeY = 125;
constexpr double kEyeAltitudeM = 100.0;
/// The brightest L_in channel of the probes' vertices is mapped to this display value.
constexpr double kBrightestLin = 0.9;

struct Frame {
    const char* name;
    const char* preset;
    double sun_elevation_deg;
    double sun_azimuth_deg;
};
constexpr std::array<Frame, 4> kFrames{{
    {"noon", "earth", 60.0, 30.0},
    {"low-sun", "earth", 5.0, 30.0},
    {"noon", "hazy", 60.0, 30.0},
    {"low-sun", "hazy", 5.0, 30.0},
}};

struct Program {
    Model model;
    std::optional<ArbHeightFidelity> fidelity;
};
const std::array<Program, 5> kPrograms{{
    {Model::hoffman_preetham, std::nullopt},
    {Model::height, ArbHeightFidelity::spec_minimum},
    {Model::height, ArbHeightFidelity::exact_optical_depth},
    {Model::height, ArbHeightFidelity::full},
    {Model::height, ArbHeightFidelity::multiple_scattering},
}};

/// The probed pixels: 8 radii (1 to 120 pixels) in 8 directions around the eye.
std::vector<std::pair<int, int>> probe_pixels() {
    std::vector<std::pair<int, int>> pixels;
    for (const int r : {1, 3, 6, 12, 24, 48, 96, 120}) {
        for (int k = 0; k < 8; ++k) {
            const double a = 45.0 * k * kDegree;
            pixels.emplace_back(kEyeX + static_cast<int>(std::lround(r * std::cos(a))),
                                kEyeY + static_cast<int>(std::lround(r * std::sin(a))));
        }
    }
    return pixels;
}

std::string format(const char* pattern, double a) {
    char text[64];
    std::snprintf(text, sizeof text, pattern, a);
    return text;
}

/// %.9g: a float printed this way reads back as the same float (piglit reads with %f).
std::string g9(float x) { return format("%.9g", static_cast<double>(x)); }

/// %.17g: a double printed this way reads back as the same double (the frame is in double).
std::string vec3_text(const glm::dvec3& v) {
    return format("%.17g", v.x) + "," + format("%.17g", v.y) + "," + format("%.17g", v.z);
}

/// glOrtho(0, 250, 0, 250, -1, 1), row-major: what state.matrix.mvp holds under `ortho`.
std::array<std::array<float, 4>, 4> ortho_mvp() {
    const float s = 2.0f / float(kShaderTestSize);
    return {{{s, 0, 0, -1}, {0, s, 0, -1}, {0, 0, -1, 0}, {0, 0, 0, 1}}};
}

/// The clamped primary and secondary colours of the executor at the vertex (x, y, 0, 1).
std::pair<std::array<double, 4>, std::array<double, 4>> colours(
    const validation::ArbCpuProgram& program, const validation::ArbMachine& machine, float x,
    float y) {
    validation::ArbVertex vertex;
    vertex.position = {x, y, 0.0f, 1.0f};
    const validation::ArbResults r = validation::run_arb_program(program, machine, vertex);
    std::pair<std::array<double, 4>, std::array<double, 4>> c;
    for (std::size_t i = 0; i < 4; ++i) {
        // GL clamps the vertex colours to [0, 1] before they are interpolated.
        c.first[i] = std::clamp(static_cast<double>(r.color_primary.value[i]), 0.0, 1.0);
        c.second[i] = std::clamp(static_cast<double>(r.color_secondary.value[i]), 0.0, 1.0);
    }
    return c;
}

validation::ArbMachine machine_for(const ArbProgramOptions& options,
                                   const std::vector<std::array<float, 4>>& params) {
    validation::ArbMachine machine;
    std::vector<std::array<float, 4>> space(static_cast<std::size_t>(options.parameter_base));
    space.insert(space.end(), params.begin(), params.end());
    (options.parameter_space == ParameterSpace::env ? machine.env : machine.local) = space;
    machine.mvp = ortho_mvp();
    return machine;
}

constexpr const char* kFragmentProgram =
    "!!ARBfp1.0\n"
    "# One of the vertex program's colours: program.local[0] = (1, 0, 0, 0) shows the primary\n"
    "# colour (F_ex), (0, 1, 0, 0) the secondary (L_in); x * 1 + y * 0 is exact.\n"
    "PARAM select = program.local[0];\n"
    "TEMP c;\n"
    "MUL c, fragment.color.primary, select.x;\n"
    "MAD result.color, fragment.color.secondary, select.y, c;\n"
    "END\n";

Result<std::string> shader_test(const Program& p, const Frame& f, std::string& file_name) {
    const ArbProgramOptions options = arb_program_options(p.model, p.fidelity);
    auto program = generate_arb_program(options);
    if (!program) return program.error();
    auto parsed = validation::parse_arb_program(program->text);
    if (!parsed) return parsed.error();
    auto atmosphere = atmosphere_preset(f.preset);
    if (!atmosphere) return atmosphere.error();

    View view;
    view.meters_per_unit = kMetersPerUnit;
    view.eye = {double(kEyeX), double(kEyeY), kEyeAltitudeM / kMetersPerUnit};
    view.up = {0.0, 0.0, 1.0};
    const double e = f.sun_elevation_deg * kDegree, a = f.sun_azimuth_deg * kDegree;
    view.sun_dir = {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
    auto frame = prepare_frame<float>(*atmosphere, view, p.model);
    if (!frame) return frame.error();

    // The exposure that maps the brightest L_in channel of the probes' vertices to
    // kBrightestLin (L_in is proportional to the exposure).
    const std::vector<std::pair<int, int>> pixels = probe_pixels();
    Display display;
    auto unit = arb_program_parameters(*frame, display, program->options);
    if (!unit) return unit.error();
    double brightest = 0.0;
    {
        const validation::ArbMachine m = machine_for(program->options, *unit);
        for (const auto& [i, j] : pixels) {
            for (const auto& [x, y] : {std::pair<int, int>{i + 1, j}, {i, j + 1}}) {
                validation::ArbVertex vertex;
                vertex.position = {float(x), float(y), 0.0f, 1.0f};
                const auto r = validation::run_arb_program(*parsed, m, vertex);
                for (std::size_t c = 0; c < 3; ++c) {
                    brightest = std::max(brightest, double(r.color_secondary.value[c]));
                }
            }
        }
    }
    display.exposure = brightest > 0.0 ? static_cast<float>(kBrightestLin / brightest) : 1.0f;
    auto params = arb_program_parameters(*frame, display, program->options);
    if (!params) return params.error();
    const validation::ArbMachine machine = machine_for(program->options, *params);

    const std::string model(model_name(p.model));
    std::string print_flags = "--print-arb-program --model " + model;
    std::string title = model;
    if (p.fidelity) {
        const std::string level = arb_height_fidelity_name(*p.fidelity);
        print_flags += " --arb-height-fidelity " + level;
        title += "-" + level;
    }
    file_name = title + "-" + f.preset + "-" + f.name + ".shader_test";

    std::string s;
    s += "# aerial: the " + title +
         " ARB vertex program (aerial::generate_arb_program) on the driver, against\n"
         "# aerial::validation's CPU executor of the same text. Written by aerial-eval\n"
         "# --export-shader-tests (docs/arb-program.md, \"piglit shader_test files\").\n";
    s += "# program: aerial-eval " + print_flags + "\n";
    s += "# frame: preset=" + std::string(f.preset) + " eye=" + vec3_text(view.eye) +
         " sun=" + vec3_text(view.sun_dir) + " up=" + vec3_text(view.up) +
         " meters_per_unit=" + format("%.17g", kMetersPerUnit) +
         " exposure=" + g9(display.exposure) + "\n";
    s += "# (sun elevation " + format("%g", f.sun_elevation_deg) + " deg, azimuth " +
         format("%g", f.sun_azimuth_deg) +
         " deg; the exposure maps the brightest L_in channel to " + format("%g", kBrightestLin) +
         ")\n";
    s += "# Geometry: `ortho 0 250 0 250` makes world x, y the pixel coordinates; every rect is\n"
         "# one pixel of the ground plane z = 0 (up = +z), and the eye is " +
         format("%g", kEyeAltitudeM) +
         " m above pixel corner\n"
         "# (125, 125). A probe expects the mean of the executor's colours (clamped to [0, 1])\n"
         "# at the rect's vertices (x + 1, y) and (x, y + 1): the pixel centre lies on that edge,\n"
         "# which the strip's two triangles share. The fragment program shows F_ex (primary\n"
         "# colour) in the first pass and L_in (secondary) in the second.\n";
    s += "# Tolerance: 1.5/255 per channel, the 8-bit value within one step of the expectation\n"
         "# rounded to 8 bits.\n";
    s += "\n[require]\nSIZE 250 250\nGL_ARB_vertex_program\nGL_ARB_fragment_program\n";
    s += "\n[vertex program]\n" + program->text;
    s += "\n[fragment program]\n" + std::string(kFragmentProgram);
    s += "\n[test]\northo 0 250 0 250\n";
    const std::string t = format("%.9f", kShaderTestTolerance);
    s += "tolerance " + t + " " + t + " " + t + " " + t + "\n";
    const char* space =
        program->options.parameter_space == ParameterSpace::env ? "env_vp" : "local_vp";
    for (std::size_t i = 0; i < params->size(); ++i) {
        const auto& v = (*params)[i];
        s += "parameter " + std::string(space) + " " +
             std::to_string(program->options.parameter_base + static_cast<int>(i)) + " (" +
             g9(v[0]) + ", " + g9(v[1]) + ", " + g9(v[2]) + ", " + g9(v[3]) + ")\n";
    }
    s += "clear color 0.0 0.0 0.0 0.0\n";
    for (int pass = 0; pass < 2; ++pass) {
        s += pass == 0 ? "\n# F_ex: the primary colour.\nparameter local_fp 0 (1, 0, 0, 0)\n"
                       : "\n# L_in: the secondary colour.\nparameter local_fp 0 (0, 1, 0, 0)\n";
        s += "clear\n";
        for (const auto& [i, j] : pixels) {
            s += "draw rect " + std::to_string(i) + " " + std::to_string(j) + " 1 1\n";
        }
        for (const auto& [i, j] : pixels) {
            const auto c1 = colours(*parsed, machine, float(i + 1), float(j));
            const auto c2 = colours(*parsed, machine, float(i), float(j + 1));
            const auto& a1 = pass == 0 ? c1.first : c1.second;
            const auto& a2 = pass == 0 ? c2.first : c2.second;
            s += "probe rgba " + std::to_string(i) + " " + std::to_string(j);
            for (std::size_t c = 0; c < 4; ++c) s += format(" %.6f", 0.5 * (a1[c] + a2[c]));
            s += "\n";
        }
    }
    return s;
}

}  // namespace

Result<std::vector<std::string>> export_shader_tests(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
        return Error{kFlag, std::string(kFlag) + ": " + dir + ": cannot create the directory"};
    }
    std::vector<std::string> names;
    for (const Program& p : kPrograms) {
        for (const Frame& f : kFrames) {
            std::string name;
            auto text = shader_test(p, f, name);
            if (!text) return Error{kFlag, std::string(kFlag) + ": " + text.error().message};
            const std::filesystem::path path = std::filesystem::path(dir) / name;
            std::ofstream file(path, std::ios::binary);
            file << *text;
            file.close();
            if (!file) {
                return Error{kFlag, std::string(kFlag) + ": " + path.string() + ": cannot write"};
            }
            names.push_back(name);
        }
    }
    return names;
}

}  // namespace aerial::eval
