// The ARB vertex programs' options, their checks and the resource limit check, and the dispatch
// between the models' generators (arb_program_hoffman_preetham.cpp, arb_program_height.cpp); the
// pieces of program text both share. The program is counted by parsing its own text
// (arb_parser.cpp), so that the figures always describe what GL receives.
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>

#include "../common/error_text.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/sun.hpp"
#include "arb_parser.hpp"
#include "arb_program_internal.hpp"

namespace aerial {
namespace detail::arb {

/// A float constant for program text: 9 significant digits (round-trips a float), '.' as the
/// decimal point whatever the C locale says.
std::string format_float(double value) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, static_cast<float>(value),
                                      std::chars_format::general, 9);
    return std::string(buffer, result.ptr);
}

std::string format_float4(double a, double b, double c, double d) {
    return "{ " + format_float(a) + ", " + format_float(b) + ", " + format_float(c) + ", " +
           format_float(d) + " }";
}

std::string parameter_name(const ArbProgramOptions& o, int i) {
    const std::string space = o.parameter_space == ParameterSpace::local ? "local" : "env";
    return "program." + space + "[" + std::to_string(o.parameter_base + i) + "]";
}

namespace {

constexpr ParameterRow kModelMatrixLayout[kModelMatrixRows] = {
    {"model0", "model matrix row 0 (engine units): world x = model0 . vertex.position"},
    {"model1", "model matrix row 1: world y = model1 . vertex.position"},
    {"model2", "model matrix row 2: world z = model2 . vertex.position"},
};

}  // namespace

std::vector<ParameterRow> parameter_layout(const ArbProgramOptions& o, ArbHeightFidelity fidelity) {
    std::vector<ParameterRow> rows = o.model == Model::height ? height_layout(fidelity)
                                     : o.model == Model::hoffman_preetham
                                         ? hoffman_preetham_layout()
                                         : std::vector<ParameterRow>{};
    if (o.model_matrix && !rows.empty()) {
        rows.insert(rows.end(), std::begin(kModelMatrixLayout), std::end(kModelMatrixLayout));
    }
    return rows;
}

void write_parameter_declarations(ProgramWriter& w, const ArbProgramOptions& o,
                                  ArbHeightFidelity fidelity) {
    const std::vector<ParameterRow> rows = parameter_layout(o, fidelity);
    for (std::size_t i = 0; i < rows.size();) {
        // Consecutive rows of one name are an array (read through the address register).
        std::size_t end = i + 1;
        while (end < rows.size() && std::string_view(rows[end].name) == rows[i].name) ++end;
        if (end - i == 1) {
            w.line("PARAM " + std::string(rows[i].name) + " = " +
                       parameter_name(o, static_cast<int>(i)) + ";",
                   rows[i].meaning);
        } else {
            const std::string first = parameter_name(o, static_cast<int>(i));
            const std::string last = std::to_string(o.parameter_base + int(end) - 1);
            w.line("PARAM " + std::string(rows[i].name) + "[" + std::to_string(end - i) + "] = { " +
                       first.substr(0, first.size() - 1) + ".." + last + "] };",
                   rows[i].meaning);
        }
        i = end;
    }
}

void write_world_segment(ProgramWriter& w, const ArbProgramOptions& o, const std::string& reg,
                         const std::string& scale, const std::string& comment) {
    if (o.model_matrix) {
        w.line("DP4 " + reg + ".x, model0, pos;", "world position M * vertex.position");
        w.line("DP4 " + reg + ".y, model1, pos;");
        w.line("DP4 " + reg + (scale.empty() ? ".z" : ".zw") + ", model2, pos;");
        if (scale.empty()) {
            w.line("SUB " + reg + ".xyz, " + reg + ", eye;");
            w.line("SUB " + reg + ".w, pos.w, eye.w;", comment);
        } else {
            w.line("MAD " + reg + ", " + reg + ", " + scale + ", -eye;", comment);
        }
        return;
    }
    if (scale.empty()) {
        w.line("SUB " + reg + ", pos, eye;", comment);
    } else {
        w.line("MAD " + reg + ", pos, " + scale + ", -eye;", comment);
    }
}

void write_clip_space_position(ProgramWriter& w, const ArbProgramOptions& o) {
    if (o.position_invariant) return;
    w.comment("Clip-space position.");
    for (int row = 0; row < 4; ++row) {
        w.line("DP4 result.position." + std::string(1, "xyzw"[row]) + ", mvp[" +
               std::to_string(row) + "], pos;");
    }
}

void write_texcoords_and_end(ProgramWriter& w, const ArbProgramOptions& o) {
    if (o.texcoord_units > 0) w.comment("Texture coordinates, unchanged.");
    for (int u = 0; u < o.texcoord_units; ++u) {
        const std::string unit = "[" + std::to_string(u) + "]";
        w.line("MOV result.texcoord" + unit + ", vertex.texcoord" + unit + ";");
    }
    w.line("END");
}

Result<std::vector<std::array<float, 4>>> to_float_parameters(
    const std::vector<std::array<double, 4>>& p) {
    std::vector<std::array<float, 4>> out(p.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        for (std::size_t j = 0; j < 4; ++j) {
            const float v = static_cast<float>(p[i][j]);
            if (!std::isfinite(v)) {
                return detail::invalid(
                    "arb_program_parameters", "frame",
                    "parameters within float range (eye or meters_per_unit too large?)",
                    "parameter " + detail::number(i) + " component " + detail::number(j) + " = " +
                        detail::number(p[i][j]));
            }
            out[i][j] = v;
        }
    }
    return out;
}

}  // namespace detail::arb

namespace {

using detail::arb::height_program_text;

using detail::invalid;
using detail::number;

std::optional<Error> validate_options(const ArbProgramOptions& o, const char* function) {
    if (o.model != Model::hoffman_preetham && o.model != Model::height) {
        return invalid(function, "model",
                       "hoffman-preetham or height (the models with an ARB program)",
                       std::string(model_name(o.model)));
    }
    ArbProgramOptions counted = o;
    if (o.model == Model::height && o.height_fidelity == ArbHeightFidelity::automatic) {
        counted.height_fidelity = ArbHeightFidelity::spec_minimum;  // the smallest
    }
    const int count = arb_parameter_count(counted);
    if (o.parameter_base < 0)
        return invalid(function, "parameter_base", ">= 0", number(o.parameter_base));
    if (o.parameter_base + count > o.limits.max_parameters) {
        return invalid(function, "parameter_base",
                       "at most " + number(o.limits.max_parameters - count) +
                           " (the program reads " + number(count) + " of the " +
                           number(o.limits.max_parameters) +
                           " program parameters, MAX_PROGRAM_PARAMETERS_ARB)",
                       number(o.parameter_base));
    }
    if (o.texcoord_units < 0 || o.texcoord_units > kArbMaxTexcoordUnits) {
        return invalid(function, "texcoord_units", "0 to " + number(kArbMaxTexcoordUnits),
                       number(o.texcoord_units));
    }
    return std::nullopt;
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
        case ArbHeightFidelity::multiple_scattering:
            return "multiple-scattering";
    }
    return "?";
}

Result<ArbHeightFidelity> parse_arb_height_fidelity(std::string_view name) {
    for (ArbHeightFidelity f : {ArbHeightFidelity::automatic, ArbHeightFidelity::spec_minimum,
                                ArbHeightFidelity::exact_optical_depth, ArbHeightFidelity::full,
                                ArbHeightFidelity::multiple_scattering}) {
        if (name == arb_height_fidelity_name(f)) return f;
    }
    return invalid("parse_arb_height_fidelity", "height_fidelity",
                   "one of automatic, spec-minimum, exact-optical-depth, full, multiple-scattering",
                   detail::quoted(name));
}

ArbLimits arb_reference_limits(ArbHeightFidelity fidelity) {
    ArbLimits limits;
    switch (fidelity) {
        case ArbHeightFidelity::automatic:
        case ArbHeightFidelity::spec_minimum:
            break;
        case ArbHeightFidelity::exact_optical_depth:
        case ArbHeightFidelity::full:
            limits.max_instructions = 256;
            break;
        case ArbHeightFidelity::multiple_scattering:
            limits.max_instructions = 512;
            limits.max_temporaries = 32;
            limits.max_parameters = 2048;
            break;
    }
    return limits;
}

ArbHeightFidelity resolve_arb_height_fidelity(const ArbProgramOptions& options) {
    if (options.height_fidelity != ArbHeightFidelity::automatic) return options.height_fidelity;
    for (ArbHeightFidelity f : {ArbHeightFidelity::multiple_scattering, ArbHeightFidelity::full,
                                ArbHeightFidelity::exact_optical_depth}) {
        ArbProgramOptions o = options;
        o.model = Model::height;
        o.height_fidelity = f;
        if (o.parameter_base + arb_parameter_count(o) > o.limits.max_parameters) continue;
        const auto parsed =
            detail::parse_arb_text("generate_arb_program", height_program_text(o, f));
        if (parsed && !check_arb_limits(parsed->resources, o.limits, o.position_invariant)) {
            return f;
        }
    }
    return ArbHeightFidelity::spec_minimum;
}

int arb_parameter_count(const ArbProgramOptions& options) {
    return static_cast<int>(arb_parameter_layout(options).size());
}

std::vector<ArbParameterInfo> arb_parameter_layout(const ArbProgramOptions& options) {
    const ArbHeightFidelity fidelity = options.model == Model::height
                                           ? resolve_arb_height_fidelity(options)
                                           : ArbHeightFidelity::automatic;
    std::vector<ArbParameterInfo> out;
    for (const detail::arb::ParameterRow& row : detail::arb::parameter_layout(options, fidelity)) {
        out.push_back(
            {options.parameter_base + static_cast<int>(out.size()), row.name, row.meaning});
    }
    return out;
}

int arb_model_matrix_parameter_index(const ArbProgramOptions& options) {
    ArbProgramOptions frame_only = options;
    frame_only.model_matrix = false;
    return options.parameter_base + arb_parameter_count(frame_only);
}

std::array<std::array<float, 4>, 3> arb_model_matrix_parameters(const float column_major[16]) {
    std::array<std::array<float, 4>, 3> rows{};
    for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 4; ++j) rows[i][j] = column_major[4 * j + i];
    }
    return rows;
}

namespace {

/// check_arb_limits for `function`.
std::optional<Error> check_limits(const char* function, const ArbResources& r,
                                  const ArbLimits& limits, bool position_invariant) {
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
            std::string limit = "at most " + number(c.limit) + " (" + c.gl_name;
            if (position_invariant && c.field == std::string("instructions")) {
                limit += " minus 4 for ARB_position_invariant";
            }
            return invalid(function, c.field, limit + ")", number(c.used) + " in the program");
        }
    }
    return std::nullopt;
}

}  // namespace

std::optional<Error> check_arb_limits(const ArbResources& r, const ArbLimits& limits,
                                      bool position_invariant) {
    return check_limits("check_arb_limits", r, limits, position_invariant);
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
        program.text = detail::arb::hoffman_preetham_program_text(options);
    }
    auto parsed = detail::parse_arb_text("generate_arb_program", program.text);
    if (!parsed) {
        return detail::error(
            "generate_arb_program", "text",
            "the generated program does not parse (a bug): " + parsed.error().field + ": " +
                std::string(detail::text_of(parsed.error())));
    }
    program.resources = parsed->resources;
    program.instruction_count = program.resources.instructions;
    if (auto e = check_limits("generate_arb_program", program.resources, options.limits,
                              options.position_invariant)) {
        return *e;
    }
    return program;
}

Result<std::vector<std::array<float, 4>>> arb_program_parameters(const Frame<float>& frame,
                                                                 const Display& display,
                                                                 const ArbProgramOptions& options) {
    constexpr const char* kFunction = "arb_program_parameters";
    if (auto e = validate_options(options, kFunction)) return *e;
    if (frame.model != options.model) {
        return invalid(
            kFunction, "frame.model",
            "a frame prepared for " + std::string(model_name(options.model)) + " (options.model)",
            "one prepared for " + std::string(model_name(frame.model)));
    }
    if (!std::isfinite(display.exposure) || display.exposure <= 0.0f) {
        return invalid(kFunction, "display.exposure", "a finite value > 0",
                       number(display.exposure));
    }
    if (display.tone != ToneCurve::clamp) {
        return invalid(kFunction, "display.tone",
                       "clamp (the ARB program applies the exposure and GL clamps)",
                       std::string(tone_curve_name(display.tone)));
    }

    auto p =
        options.model == Model::height
            ? detail::arb::height_parameters(frame, display, resolve_arb_height_fidelity(options))
            : detail::arb::hoffman_preetham_parameters(frame, display);
    if (p && options.model_matrix) {
        constexpr float kIdentity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        for (const auto& row : arb_model_matrix_parameters(kIdentity)) p.value().push_back(row);
    }
    return p;
}

}  // namespace aerial
