// The generated ARB vertex program loaded into GL (aerial/gl.hpp, ArbVertexProgram).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include "../common/error_text.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "state_saver.hpp"

namespace aerial::gl {

namespace {

GLint program_integer(const Api& api, GLenum pname) {
    GLint value = 0;
    api.GetProgramiv(GL_VERTEX_PROGRAM_ARB, pname, &value);
    return value;
}

// Binds `id` for the lifetime of the object and then the program that was bound before.
class ProgramBinding {
  public:
    ProgramBinding(const Api& api, GLuint id) : api_(api) {
        previous_ = program_integer(api, GL_PROGRAM_BINDING_ARB);
        api_.BindProgram(GL_VERTEX_PROGRAM_ARB, id);
    }
    ProgramBinding(const ProgramBinding&) = delete;
    ProgramBinding& operator=(const ProgramBinding&) = delete;
    ~ProgramBinding() { api_.BindProgram(GL_VERTEX_PROGRAM_ARB, static_cast<GLuint>(previous_)); }

  private:
    const Api& api_;
    GLint previous_ = 0;
};

// One past the highest program.local[i] / program.env[i] index the text reads ("[i]" or
// "[a..b]"), or 0. Counted from the text, so that it holds for every model's program.
int parameters_end(std::string_view text, ParameterSpace space) {
    const std::string_view key = space == ParameterSpace::local ? "program.local[" : "program.env[";
    int end = 0;
    for (std::size_t at = text.find(key); at != std::string_view::npos;
         at = text.find(key, at + 1)) {
        std::size_t i = at + key.size();
        int value = 0;
        bool digits = false;
        while (i < text.size()) {
            const char c = text[i];
            if (c >= '0' && c <= '9') {
                value = value * 10 + (c - '0');
                digits = true;
            } else if (c == '.') {
                value = 0;  // "a..b": the upper bound counts
            } else {
                break;
            }
            ++i;
        }
        if (digits) end = std::max(end, value + 1);
    }
    return end;
}

}  // namespace

ArbLimits native_arb_limits(const Api& api) {
    ArbLimits native;
    if (!api.caps.vertex_program) return native;
    // A driver that answers 0 (none known to do so, but the query is cheap to distrust) is held
    // to the spec's minimums instead.
    auto limit = [&](GLenum pname, int spec_minimum) {
        const GLint value = program_integer(api, pname);
        return value > 0 ? static_cast<int>(value) : spec_minimum;
    };
    native.max_instructions =
        limit(GL_MAX_PROGRAM_NATIVE_INSTRUCTIONS_ARB, ArbLimits{}.max_instructions);
    native.max_temporaries =
        limit(GL_MAX_PROGRAM_NATIVE_TEMPORARIES_ARB, ArbLimits{}.max_temporaries);
    native.max_parameters = limit(GL_MAX_PROGRAM_NATIVE_PARAMETERS_ARB, ArbLimits{}.max_parameters);
    native.max_attributes = limit(GL_MAX_PROGRAM_NATIVE_ATTRIBS_ARB, ArbLimits{}.max_attributes);
    return native;
}

Result<ArbVertexProgram> ArbVertexProgram::create(const Api& api, const ArbProgram& program) {
    constexpr const char* kFunction = "gl::ArbVertexProgram::create";
    if (auto e = no_current_context(api)) return aerial::detail::from(kFunction, *e);
    if (!api.caps.vertex_program) {
        return aerial::detail::unsupported(
            kFunction, "GL_ARB_vertex_program",
            "the context does not offer it (GL " + api.caps.version + ", " + api.caps.renderer +
                "); use the fixed-function paths (draw_with_colours)");
    }
    const ArbLimits native = native_arb_limits(api);
    if (auto e = check_arb_limits(program.resources, native, program.options.position_invariant)) {
        Error limit = aerial::detail::from(kFunction, *e);
        limit.message += " (the driver's GL_MAX_PROGRAM_NATIVE_* limit, " + api.caps.renderer + ")";
        return limit;
    }
    // The parameter indices the program reads must exist in program.local / program.env.
    const GLenum index_limit = program.options.parameter_space == ParameterSpace::local
                                   ? GL_MAX_PROGRAM_LOCAL_PARAMETERS_ARB
                                   : GL_MAX_PROGRAM_ENV_PARAMETERS_ARB;
    const GLint max_index = program_integer(api, index_limit);
    const int last = parameters_end(program.text, program.options.parameter_space);
    if (last > max_index) {
        const char* space =
            program.options.parameter_space == ParameterSpace::local ? "local" : "env";
        return aerial::detail::invalid(
            kFunction, "parameter_base",
            "indices below the driver's " + aerial::detail::number(max_index) + " program." +
                space + " parameters",
            "a program reading " + aerial::detail::number(program.options.parameter_base) + " .. " +
                aerial::detail::number(last - 1));
    }
    if (program.text.size() > static_cast<std::size_t>(INT32_MAX)) {
        return aerial::detail::error(kFunction, "program",
                                     "the text is too long for glProgramStringARB");
    }

    GLuint id = 0;
    api.GenPrograms(1, &id);
    std::optional<Error> error;
    {
        ProgramBinding bound(api, id);
        api.ProgramString(GL_VERTEX_PROGRAM_ARB, GL_PROGRAM_FORMAT_ASCII_ARB,
                          static_cast<GLsizei>(program.text.size()), program.text.data());
        GLint position = -1;
        api.GetIntegerv(GL_PROGRAM_ERROR_POSITION_ARB, &position);
        const GLubyte* text = api.GetString(GL_PROGRAM_ERROR_STRING_ARB);
        const std::string driver_text = text ? reinterpret_cast<const char*>(text) : "";
        if (position != -1) {
            // Line and column of the position, for a person reading the text.
            int line = 1, column = 1;
            const std::size_t end = std::min(static_cast<std::size_t>(position < 0 ? 0 : position),
                                             program.text.size());
            for (std::size_t i = 0; i < end; ++i) {
                if (program.text[i] == '\n') {
                    ++line;
                    column = 1;
                } else {
                    ++column;
                }
            }
            error = aerial::detail::error(
                kFunction, "program",
                "rejected by the driver at GL_PROGRAM_ERROR_POSITION_ARB " +
                    std::to_string(position) + " (line " + std::to_string(line) + ", column " +
                    std::to_string(column) +
                    "): " + (driver_text.empty() ? "(no error string)" : driver_text));
        } else if (program_integer(api, GL_PROGRAM_UNDER_NATIVE_LIMITS_ARB) == 0) {
            error = aerial::detail::error(
                kFunction, "program",
                "loaded, but GL_PROGRAM_UNDER_NATIVE_LIMITS_ARB is false on " + api.caps.renderer +
                    " (it would run in software or not at all)" +
                    (driver_text.empty() ? "" : ": " + driver_text));
        }
    }
    if (error) {
        api.DeletePrograms(1, &id);
        return *error;
    }
    return ArbVertexProgram(&api, id, program);
}

ArbVertexProgram::ArbVertexProgram(const Api* api, unsigned id, ArbProgram program)
    : api_(api), id_(id), program_(std::move(program)) {}

ArbVertexProgram::ArbVertexProgram(ArbVertexProgram&& other) noexcept
    : api_(other.api_), id_(std::exchange(other.id_, 0u)), program_(std::move(other.program_)) {}

ArbVertexProgram& ArbVertexProgram::operator=(ArbVertexProgram&& other) noexcept {
    if (this != &other) {
        if (id_ != 0) {
            const GLuint id = id_;
            api_->DeletePrograms(1, &id);
        }
        api_ = other.api_;
        id_ = std::exchange(other.id_, 0u);
        program_ = std::move(other.program_);
    }
    return *this;
}

ArbVertexProgram::~ArbVertexProgram() {
    if (id_ != 0) {
        const GLuint id = id_;
        api_->DeletePrograms(1, &id);
    }
}

std::optional<Error> ArbVertexProgram::set_parameters(
    const std::vector<std::array<float, 4>>& parameters) const {
    constexpr const char* kFunction = "gl::ArbVertexProgram::set_parameters";
    // What the program reads from parameter_base on (kArbParameterCount for hoffman-preetham).
    const int expected =
        std::max(0, parameters_end(program_.text, program_.options.parameter_space) -
                        program_.options.parameter_base);
    if (parameters.size() != static_cast<std::size_t>(expected)) {
        return aerial::detail::invalid(
            kFunction, "parameters",
            aerial::detail::number(expected) + " vectors (aerial::arb_program_parameters)",
            aerial::detail::number(parameters.size()));
    }
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        for (float v : parameters[i]) {
            if (!std::isfinite(v)) {
                return aerial::detail::invalid(kFunction, "parameters[" + std::to_string(i) + "]",
                                               "finite values",
                                               aerial::detail::vector(parameters[i]));
            }
        }
    }
    const auto base = static_cast<GLuint>(program_.options.parameter_base);
    if (program_.options.parameter_space == ParameterSpace::env) {
        for (std::size_t i = 0; i < parameters.size(); ++i) {
            api_->ProgramEnvParameter4fv(GL_VERTEX_PROGRAM_ARB, base + static_cast<GLuint>(i),
                                         parameters[i].data());
        }
        return std::nullopt;
    }
    ProgramBinding bound(*api_, id_);  // program.local belongs to the bound program
    for (std::size_t i = 0; i < parameters.size(); ++i) {
        api_->ProgramLocalParameter4fv(GL_VERTEX_PROGRAM_ARB, base + static_cast<GLuint>(i),
                                       parameters[i].data());
    }
    return std::nullopt;
}

namespace {

/// What ProgramDrawState and ArbVertexProgram::draw set (the program's binding aside).
void program_draw_state(const Api& api, StateSaver& s, const ApplyOptions& options) {
    if (api.caps.fragment_program) s.enable(GL_FRAGMENT_PROGRAM_ARB, false);
    s.use_no_glsl_program();
    // COLOR_SUM_ARB is defined by ARB_vertex_program itself, so this is valid without
    // EXT_secondary_color.
    s.enable(GL_COLOR_SUM, true);
    if (options.textured) {
        s.tex_env(options.texture_unit, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    } else {
        s.unit_disable_all_targets(options.texture_unit);
    }
}

std::optional<Error> check_texture_unit(const Api& api, const char* function, int unit) {
    if (unit < 0 || unit >= api.caps.max_texture_units) {
        return aerial::detail::invalid(
            function, "texture_unit",
            "0 .. " + aerial::detail::number(api.caps.max_texture_units - 1),
            aerial::detail::number(unit));
    }
    return std::nullopt;
}

}  // namespace

Result<ProgramDrawState> ProgramDrawState::set(const Api& api, const ApplyOptions& options) {
    constexpr const char* kFunction = "gl::ProgramDrawState::set";
    if (auto e = no_current_context(api)) return aerial::detail::from(kFunction, *e);
    if (auto e = check_texture_unit(api, kFunction, options.texture_unit)) return *e;
    auto saver = std::make_unique<StateSaver>(api);
    program_draw_state(api, *saver, options);
    return ProgramDrawState(std::move(saver));
}

ProgramDrawState::ProgramDrawState(std::unique_ptr<StateSaver> saver) : saver_(std::move(saver)) {}
ProgramDrawState::ProgramDrawState(ProgramDrawState&&) noexcept = default;
ProgramDrawState& ProgramDrawState::operator=(ProgramDrawState&& other) noexcept {
    if (this != &other) {
        restore();
        saver_ = std::move(other.saver_);
    }
    return *this;
}
ProgramDrawState::~ProgramDrawState() { restore(); }

void ProgramDrawState::restore() {
    if (saver_) saver_->restore();
    saver_.reset();
}

Result<ApplyStats> ArbVertexProgram::draw(const std::function<void()>& draw,
                                          const ApplyOptions& options) const {
    constexpr const char* kFunction = "gl::ArbVertexProgram::draw";
    if (!draw) return aerial::detail::invalid(kFunction, "draw", "a draw callback", "an empty one");
    if (id_ == 0)
        return aerial::detail::error(kFunction, "program", "this ArbVertexProgram was moved from");
    if (auto e = no_current_context(*api_)) return aerial::detail::from(kFunction, *e);
    if (auto e = check_texture_unit(*api_, kFunction, options.texture_unit)) return *e;
    StateSaver s(*api_);
    program_draw_state(*api_, s, options);
    s.bind_program(id_);
    s.enable(GL_VERTEX_PROGRAM_ARB, true);
    draw();
    s.restore();
    ApplyStats stats;
    stats.path = Path::secondary_color;
    stats.passes = 1;
    return stats;
}

}  // namespace aerial::gl
