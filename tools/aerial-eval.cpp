// aerial-eval: evaluates one model of the physics core at points read from a file or stdin and
// prints CSV of raw linear values (docs/conventions.md, Interfaces).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "aerial/aerial.hpp"
#include "aerial/arb_program.hpp"
#include "eval/shader_tests.hpp"
#include "support/cli.hpp"

namespace {

constexpr const char* kTool = "aerial-eval";

constexpr const char* kDescription =
    "Evaluates extinction F_ex, in-scattering L_in and the sun irradiance E_sun of one model at\n"
    "points x,y,z (metres, one per line; blank lines and # comments ignored) read from --points\n"
    "or stdin, and writes CSV of raw linear values (before exposure, unclamped):\n"
    "  x,y,z,fex_r,fex_g,fex_b,lin_r,lin_g,lin_b,esun_r,esun_g,esun_b\n"
    "esun is the sun irradiance reaching the point in that model. Vector flags take X,Y,Z; write\n"
    "--eye=X,Y,Z when a value is negative. Exit status: 0 on success, 2 on bad input.\n"
    "--model: hoffman-preetham (the 2002 model), height (the default), single-scattering (single\n"
    "scattering integrated numerically, ozone included) or reference (single-scattering plus "
    "every\n"
    "higher order of scattering and the ground's reflection, from tables computed for the\n"
    "atmosphere: each run takes seconds more).\n"
    "--print-arb-program prints the ARB vertex program of --model (hoffman-preetham, the default\n"
    "here, or height) exactly as it is handed to glProgramStringARB (no other flag is needed) and\n"
    "exits; single-scattering and reference have no program.\n"
    "--arb-height-fidelity spec-minimum|exact-optical-depth|full|multiple-scattering (with\n"
    "--print-arb-program; implies --model height) chooses how much of the height model the\n"
    "program computes; exact-optical-depth and full are checked against 256 instructions (the\n"
    "native limit of Direct3D 9-class hardware) instead of the spec's 128, multiple-scattering\n"
    "against 512 instructions, 32 temporaries and 2048 parameters (Mesa's).\n"
    "--export-shader-tests DIR writes those programs (hoffman-preetham and each height level) as\n"
    "piglit shader_test files, for the presets earth and hazy at noon and at a low sun, with\n"
    "probes computed by the CPU executor of the same text, prints the files' paths and exits\n"
    "(no other flag; docs/arb-program.md).\n"
    "--reference-tables computes the reference model's tables of the higher orders for the\n"
    "atmosphere (--preset or --atmosphere, nothing else), prints one line\n"
    "  orders=N remainder_bound=R,G,B seconds=S\n"
    "then each order's share of the higher orders' light (G channel) as order=N share=F, and\n"
    "exits (docs/models.md, The reference).";

}  // namespace

int main(int argc, char** argv) {
    using namespace aerial;
    CLI::App app{kDescription, kTool};
    std::string preset, atmosphere_file, eye_text, sun_text, up_text = "0,0,1",
                                                             model_text = "height", points_file;
    auto* preset_opt =
        app.add_option("--preset", preset, "Atmosphere preset: earth, hp2002, hazy, foggy, mars");
    auto* file_opt = app.add_option("--atmosphere", atmosphere_file, "Atmosphere JSON file");
    preset_opt->excludes(file_opt);
    // --eye and --sun are required unless --print-arb-program is given (checked below).
    auto* eye_opt = app.add_option("--eye", eye_text, "Eye position X,Y,Z in metres (required)");
    auto* sun_opt =
        app.add_option("--sun", sun_text, "Direction towards the sun X,Y,Z (normalised; required)");
    auto* model_opt =
        app.add_option("--model", model_text,
                       "hoffman-preetham, height (default), single-scattering or reference");
    bool print_arb_program = false;
    auto* print_opt =
        app.add_flag("--print-arb-program", print_arb_program,
                     "Print the ARB vertex program (hoffman-preetham) as loaded into GL, and exit");
    std::string fidelity_text;
    auto* fidelity_opt = app.add_option(
        "--arb-height-fidelity", fidelity_text,
        "With --print-arb-program: spec-minimum (default), exact-optical-depth, full or "
        "multiple-scattering");
    std::string export_dir;
    auto* export_opt =
        app.add_option("--export-shader-tests", export_dir,
                       "Write the ARB programs as piglit shader_test files into DIR, and exit");
    auto* up_opt =
        app.add_option("--up", up_text, "World up axis X,Y,Z (normalised; default 0,0,1)");
    auto* points_opt =
        app.add_option("--points", points_file, "File of points x,y,z (default: stdin)");
    bool reference_tables = false;
    auto* tables_opt = app.add_flag("--reference-tables", reference_tables,
                                    "Compute the reference's tables, report orders, bound and "
                                    "time, and exit");
    if (auto status = tools::parse_command_line(app, argc, argv, kTool)) return *status;

    if (export_opt->count() > 0) {
        for (const CLI::Option* other : {preset_opt, file_opt, eye_opt, sun_opt, model_opt,
                                         print_opt, fidelity_opt, up_opt, points_opt, tables_opt}) {
            if (other->count() > 0) {
                return tools::fail(
                    kTool, "--export-shader-tests: takes no other flag, got " + other->get_name());
            }
        }
        const auto files = eval::export_shader_tests(export_dir);
        if (!files) return tools::fail(kTool, files.error().message);
        for (const std::string& name : *files) {
            std::printf("%s\n", (std::filesystem::path(export_dir) / name).string().c_str());
        }
        if (std::fflush(stdout) != 0) return tools::fail(kTool, "cannot write output");
        return 0;
    }

    if (print_arb_program) {
        if (reference_tables) {
            return tools::fail(kTool, "--reference-tables: not with --print-arb-program");
        }
        Model program_model = Model::hoffman_preetham;
        std::optional<ArbHeightFidelity> program_fidelity;
        if (fidelity_opt->count() > 0) {
            const auto fidelity = parse_arb_height_fidelity(fidelity_text);
            if (!fidelity || *fidelity == ArbHeightFidelity::automatic) {
                return tools::fail(kTool,
                                   "--arb-height-fidelity: expected spec-minimum, "
                                   "exact-optical-depth, full or multiple-scattering, got '" +
                                       fidelity_text + "'");
            }
            program_model = Model::height;
            program_fidelity = *fidelity;
        }
        if (model_opt->count() > 0) {
            auto model = parse_model(model_text);
            if (!model) return tools::fail(kTool, "--model: " + model.error().message);
            if (is_numerical(*model)) {
                return tools::fail(kTool,
                                   "--model: the ARB vertex program exists for hoffman-preetham "
                                   "and height, got '" +
                                       std::string(model_name(*model)) + "'");
            }
            if (fidelity_opt->count() > 0 && *model != Model::height) {
                return tools::fail(kTool,
                                   "--arb-height-fidelity: only the height model has "
                                   "fidelity levels, got --model " +
                                       model_text);
            }
            program_model = *model;
        }
        const auto program =
            generate_arb_program(eval::arb_program_options(program_model, program_fidelity));
        if (!program) return tools::fail(kTool, program.error().message);
        const std::string& text = program->text;
        if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() ||
            std::fflush(stdout) != 0) {
            return tools::fail(kTool, "cannot write output");
        }
        return 0;
    }
    if (fidelity_opt->count() > 0) {
        return tools::fail(kTool, "--arb-height-fidelity: only with --print-arb-program");
    }
    if (reference_tables) {
        for (const CLI::Option* other :
             {eye_opt, sun_opt, model_opt, fidelity_opt, up_opt, points_opt}) {
            if (other->count() > 0) {
                return tools::fail(kTool,
                                   "--reference-tables: takes only --preset or "
                                   "--atmosphere, got " +
                                       other->get_name());
            }
        }
    } else {
        if (eye_opt->count() == 0) return tools::fail(kTool, "--eye is required (see --help)");
        if (sun_opt->count() == 0) return tools::fail(kTool, "--sun is required (see --help)");
    }

    Atmosphere atmosphere;
    if (preset_opt->count() == 0 && file_opt->count() == 0) {
        return tools::fail(kTool, "--preset or --atmosphere is required (see --help)");
    }
    if (preset_opt->count() > 0) {
        auto a = atmosphere_preset(preset);
        if (!a) return tools::fail(kTool, "--preset: " + a.error().message);
        atmosphere = *a;
    } else {
        auto a = load_atmosphere_json(atmosphere_file);
        if (!a) return tools::fail(kTool, "--atmosphere " + a.error().message);
        atmosphere = *a;
    }
    if (reference_tables) {
        const auto report = reference_multiple_scattering(atmosphere);
        if (!report) return tools::fail(kTool, report.error().message);
        const glm::dvec3& bound = report->remainder_bound;
        std::printf("orders=%d remainder_bound=%.3g,%.3g,%.3g seconds=%.2f\n", report->orders,
                    bound.x, bound.y, bound.z, report->seconds);
        double all = 0.0;
        for (const glm::dvec3& sum : report->order_sums) all += sum.y;
        for (std::size_t n = 0; n < report->order_sums.size(); ++n) {
            std::printf("order=%zu share=%.4f\n", n + 2,
                        all > 0.0 ? report->order_sums[n].y / all : 0.0);
        }
        if (std::fflush(stdout) != 0) return tools::fail(kTool, "cannot write output");
        return 0;
    }
    auto model = parse_model(model_text);
    if (!model) return tools::fail(kTool, "--model: " + model.error().message);
    auto eye = tools::parse_vec3(eye_text, "--eye");
    if (!eye) return tools::fail(kTool, eye.error().message);
    auto sun = tools::parse_direction(sun_text, "--sun");
    if (!sun) return tools::fail(kTool, sun.error().message);
    auto up = tools::parse_direction(up_text, "--up");
    if (!up) return tools::fail(kTool, up.error().message);

    std::string text;
    std::string source = "stdin";
    if (!points_file.empty()) {
        std::ifstream file(points_file, std::ios::binary);
        if (!file) return tools::fail(kTool, "--points " + points_file + ": cannot open file");
        text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
        if (file.bad()) return tools::fail(kTool, "--points " + points_file + ": cannot read file");
        source = points_file;
    } else {
        text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    }
    auto points = tools::parse_points(text, source);
    if (!points) return tools::fail(kTool, points.error().message);

    View view;
    view.eye = *eye;
    view.sun_dir = *sun;
    view.up = *up;
    auto frame = prepare_frame<double>(atmosphere, view, *model);
    if (!frame) return tools::fail(kTool, frame.error().message);

    std::printf("x,y,z,fex_r,fex_g,fex_b,lin_r,lin_g,lin_b,esun_r,esun_g,esun_b\n");
    for (const glm::dvec3& p : *points) {
        const Scattering<double> s = scatter(*frame, p);
        std::printf("%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", p.x, p.y, p.z,
                    s.extinction.x, s.extinction.y, s.extinction.z, s.in_scattering.x,
                    s.in_scattering.y, s.in_scattering.z, s.sun_irradiance.x, s.sun_irradiance.y,
                    s.sun_irradiance.z);
    }
    if (std::fflush(stdout) != 0) return tools::fail(kTool, "cannot write output");
    return 0;
}
