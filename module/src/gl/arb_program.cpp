// The ARB vertex programs' options, their checks and the resource limit check, and the dispatch
// between the models' generators (arb_program_hoffman_preetham.cpp, arb_program_height.cpp); the
// pieces of program text both share. The program is counted by parsing its own text
// (arb_parser.cpp), so that the figures always describe what GL receives.
#include <charconv>
#include <cmath>

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
    }
    return "?";
}

Result<ArbHeightFidelity> parse_arb_height_fidelity(std::string_view name) {
    for (ArbHeightFidelity f : {ArbHeightFidelity::automatic, ArbHeightFidelity::spec_minimum,
                                ArbHeightFidelity::exact_optical_depth, ArbHeightFidelity::full}) {
        if (name == arb_height_fidelity_name(f)) return f;
    }
    return invalid("parse_arb_height_fidelity", "height_fidelity",
                   "one of automatic, spec-minimum, exact-optical-depth, full",
                   detail::quoted(name));
}

ArbHeightFidelity resolve_arb_height_fidelity(const ArbProgramOptions& options) {
    if (options.height_fidelity != ArbHeightFidelity::automatic) return options.height_fidelity;
    for (ArbHeightFidelity f : {ArbHeightFidelity::full, ArbHeightFidelity::exact_optical_depth}) {
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

    if (options.model == Model::height) {
        return detail::arb::height_parameters(frame, display, resolve_arb_height_fidelity(options));
    }
    return detail::arb::hoffman_preetham_parameters(frame, display);
}

}  // namespace aerial
