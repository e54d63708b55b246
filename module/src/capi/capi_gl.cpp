// The C interface (aerial/aerial.h), GL part: the engine's context, the fixed-function paths and
// the ARB vertex program. Each entry point runs inside capi::guard, so no exception leaves it
// (nor one thrown by a C++ draw callback: the GL layer restores its state, then the guard turns
// the exception into AERIAL_ERROR_INTERNAL).
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "../common/error_text.hpp"
#include "aerial/aerial.h"
#include "aerial/arb_program.hpp"
#include "aerial/gl.hpp"
#include "aerial/gl_api.hpp"
#include "capi_internal.hpp"

struct aerial_gl {
    aerial::gl::Api api;
    /// The combiner path's 3D texture, created on the first combiner draw.
    std::optional<aerial::gl::CombinerTexture> combiner;
    /// What aerial_gl_set_program_state saved, until aerial_gl_restore_program_state.
    std::optional<aerial::gl::ProgramDrawState> program_state;
    std::string last_error;
};

struct aerial_arb_program {
    aerial_gl* gl = nullptr;
    std::optional<aerial::gl::ArbVertexProgram> program;
    std::string last_error;
};

namespace aerial::capi {
namespace {

bool starts_with(const std::string& s, const char* prefix) {
    return s.compare(0, std::strlen(prefix), prefix) == 0;
}

/// A GL layer error: the context lacks something (named by its extension, or the feature the
/// fixed-function lighting or the combiner texture needs), or the caller passed a bad value.
[[noreturn]] void fail_gl(const Error& error) {
    if (starts_with(error.field, "engine.")) fail(AERIAL_ERROR_ENGINE_STATE, error);
    const bool unsupported = starts_with(error.field, "GL_") ||
                             error.field == "fixed_function_lighting" || error.field == "combiner";
    fail(unsupported ? AERIAL_ERROR_GL_UNSUPPORTED : AERIAL_ERROR_INVALID_ARGUMENT, error);
}

constexpr EnumValue<gl::Path> kPaths[] = {{AERIAL_PATH_AUTOMATIC, gl::Path::automatic},
                                          {AERIAL_PATH_SECONDARY_COLOR, gl::Path::secondary_color},
                                          {AERIAL_PATH_COMBINER, gl::Path::combiner},
                                          {AERIAL_PATH_TWO_PASS, gl::Path::two_pass}};

gl::Path to_cpp_path(int path) {
    return to_cpp_enum(path, kPaths, "path",
                       "AERIAL_PATH_AUTOMATIC (0) .. AERIAL_PATH_TWO_PASS (3)");
}

aerial_path to_c_path(gl::Path path) {
    for (const EnumValue<gl::Path>& p : kPaths) {
        if (p.cpp == path) return aerial_path(p.c);
    }
    return AERIAL_PATH_AUTOMATIC;
}

gl::ApplyOptions to_cpp_draw(const aerial_draw_options* c) {
    gl::ApplyOptions o;
    if (c == nullptr) return o;
    o.path = to_cpp_path(c_enum_value(c->path));
    o.texture_unit = c->texture_unit;
    o.textured = c->untextured == 0;
    o.fixed_function_lighting = c->fixed_function_lighting != 0;
    o.cull_back_faces = c->cull_back_faces != 0;
    return o;
}

/// The C limits: a field left 0 is the spec minimum; a negative one is an error.
ArbLimits to_cpp_limits(const aerial_arb_limits& c) {
    ArbLimits l;
    const struct {
        const char* field;
        int value;
        int* target;
    } fields[] = {{"options.limits.max_instructions", c.max_instructions, &l.max_instructions},
                  {"options.limits.max_temporaries", c.max_temporaries, &l.max_temporaries},
                  {"options.limits.max_parameters", c.max_parameters, &l.max_parameters},
                  {"options.limits.max_attributes", c.max_attributes, &l.max_attributes}};
    for (const auto& f : fields) {
        if (f.value < 0) {
            fail(AERIAL_ERROR_INVALID_ARGUMENT, f.field,
                 "expected >= 0 (0: the spec minimum), got " + std::to_string(f.value));
        }
        if (f.value > 0) *f.target = f.value;
    }
    return l;
}

aerial_arb_limits to_c_limits(const ArbLimits& l) {
    aerial_arb_limits c;
    c.max_instructions = l.max_instructions;
    c.max_temporaries = l.max_temporaries;
    c.max_parameters = l.max_parameters;
    c.max_attributes = l.max_attributes;
    return c;
}

constexpr EnumValue<ArbHeightFidelity> kFidelities[] = {
    {AERIAL_HEIGHT_FIDELITY_AUTOMATIC, ArbHeightFidelity::automatic},
    {AERIAL_HEIGHT_FIDELITY_SPEC_MINIMUM, ArbHeightFidelity::spec_minimum},
    {AERIAL_HEIGHT_FIDELITY_EXACT_OPTICAL_DEPTH, ArbHeightFidelity::exact_optical_depth},
    {AERIAL_HEIGHT_FIDELITY_FULL, ArbHeightFidelity::full},
    {AERIAL_HEIGHT_FIDELITY_MULTIPLE_SCATTERING, ArbHeightFidelity::multiple_scattering}};

/// The level a generated program has (AUTOMATIC for a model without levels).
aerial_height_fidelity to_c_fidelity(const ArbProgramOptions& o) {
    if (o.model != Model::height) return AERIAL_HEIGHT_FIDELITY_AUTOMATIC;
    for (const EnumValue<ArbHeightFidelity>& f : kFidelities) {
        if (f.cpp == o.height_fidelity) return aerial_height_fidelity(f.c);
    }
    return AERIAL_HEIGHT_FIDELITY_AUTOMATIC;
}

ArbProgramOptions to_cpp_arb(const aerial_arb_options* c) {
    ArbProgramOptions o;
    if (c == nullptr) return o;
    o.model = to_cpp_model(c_enum_value(c->model), "options.model");
    static constexpr EnumValue<ParameterSpace> kSpaces[] = {
        {AERIAL_PARAMETERS_LOCAL, ParameterSpace::local},
        {AERIAL_PARAMETERS_ENV, ParameterSpace::env}};
    o.parameter_space =
        to_cpp_enum(c_enum_value(c->parameter_space), kSpaces, "options.parameter_space",
                    "AERIAL_PARAMETERS_LOCAL (0) or _ENV (1)");
    o.parameter_base = c->parameter_base;
    // 0 keeps the default; AERIAL_NO_TEXCOORDS asks for none; other values are checked by the
    // generator.
    if (c->texcoord_units == AERIAL_NO_TEXCOORDS) {
        o.texcoord_units = 0;
    } else if (c->texcoord_units != 0) {
        o.texcoord_units = c->texcoord_units;
    }
    o.position_invariant = c->position_invariant != 0;
    o.guard_coarse_ex2 = c->guard_coarse_ex2 != 0;
    o.height_fidelity =
        to_cpp_enum(c_enum_value(c->height_fidelity), kFidelities, "options.height_fidelity",
                    "AERIAL_HEIGHT_FIDELITY_AUTOMATIC (0) .. _FULL (3)");
    o.limits = to_cpp_limits(c->limits);
    o.model_matrix = c->model_matrix != 0;
    return o;
}

/// Generates the program; option values out of range are AERIAL_ERROR_INVALID_ARGUMENT, a
/// model without a program or an exceeded limit AERIAL_ERROR_ARB_PROGRAM.
ArbProgram generate(const ArbProgramOptions& options) {
    auto program = generate_arb_program(options);
    if (!program) {
        const std::string& field = program.error().field;
        const bool bad_value =
            field == "parameter_base" || field == "texcoord_units" || field == "height_fidelity";
        fail(bad_value ? AERIAL_ERROR_INVALID_ARGUMENT : AERIAL_ERROR_ARB_PROGRAM, program.error());
    }
    return std::move(program.value());
}

std::vector<std::array<float, 4>> parameters(const aerial_context& context,
                                             const ArbProgramOptions& options,
                                             const aerial_display* display) {
    const Frame<float>& frame = current_frame(context);
    auto p = arb_program_parameters(frame, to_cpp(display), options);
    if (!p) {
        // frame.model, display.exposure, display.tone: the caller's choice; anything else is a
        // value the program cannot hold.
        const std::string& field = p.error().field;
        const bool bad_value = starts_with(field, "frame.model") || starts_with(field, "display");
        fail(bad_value ? AERIAL_ERROR_INVALID_ARGUMENT : AERIAL_ERROR_ARB_PROGRAM, p.error());
    }
    return std::move(p.value());
}

std::function<void()> callback(aerial_draw_function draw, void* user) {
    return [draw, user] { draw(user); };
}

gl::VertexColours to_cpp_colours(const aerial_vertex_colours& c) {
    gl::VertexColours v;
    v.primary = c.primary;
    v.secondary = c.secondary;
    v.primary_stride_bytes = c.primary_stride_bytes;
    v.secondary_stride_bytes = c.secondary_stride_bytes;
    v.vertex_count = c.vertex_count;
    return v;
}

}  // namespace
}  // namespace aerial::capi

using namespace aerial;  // NOLINT(google-build-using-namespace): this file implements the C API
using capi::fail;
using capi::guard;
using capi::require;

extern "C" {

aerial_status aerial_gl_create(aerial_gl_load_function load, void* user, aerial_gl** out) {
    return guard("aerial_gl_create", nullptr, [&] {
        require(out, "out");
        *out = nullptr;
        require(load, "load");
        gl::Api api = capi::value_or_fail(gl::load_api(load, user), AERIAL_ERROR_GL_UNAVAILABLE);
        auto created = std::make_unique<aerial_gl>();
        created->api = std::move(api);
        *out = created.release();
    });
}

void aerial_gl_destroy(aerial_gl* gl) { delete gl; }

const char* aerial_gl_last_error(const aerial_gl* gl) { return gl ? gl->last_error.c_str() : ""; }
const char* aerial_gl_renderer(const aerial_gl* gl) {
    return gl ? gl->api.caps.renderer.c_str() : "";
}
const char* aerial_gl_version(const aerial_gl* gl) {
    return gl ? gl->api.caps.version.c_str() : "";
}

aerial_status aerial_gl_choose_path(aerial_gl* gl, aerial_path requested,
                                    int fixed_function_lighting, aerial_path* chosen) {
    return guard("aerial_gl_choose_path", capi::last_error_of(gl), [&] {
        require(gl, "gl");
        require(chosen, "chosen");
        auto path = gl::choose_path(gl->api.caps, capi::to_cpp_path(capi::c_enum_value(requested)),
                                    fixed_function_lighting != 0);
        if (!path) capi::fail_gl(path.error());
        *chosen = capi::to_c_path(*path);
    });
}

aerial_status aerial_gl_draw_colours(aerial_gl* gl, const aerial_draw_options* options,
                                     const aerial_vertex_colours* colours,
                                     aerial_draw_function draw, void* user,
                                     aerial_path* path_used) {
    return guard("aerial_gl_draw_colours", capi::last_error_of(gl), [&] {
        require(gl, "gl");
        require(colours, "colours");
        require(draw, "draw");
        gl::ApplyOptions o = capi::to_cpp_draw(options);
        auto path = gl::choose_path(gl->api.caps, o.path, o.fixed_function_lighting);
        if (!path) capi::fail_gl(path.error());
        if (*path == gl::Path::combiner) {
            if (!gl->combiner) {
                auto texture = gl::CombinerTexture::create(gl->api);
                if (!texture) capi::fail_gl(texture.error());
                gl->combiner.emplace(std::move(texture.value()));
            }
            o.combiner = &*gl->combiner;
        }
        auto stats = gl::draw_with_colours(gl->api, o, capi::to_cpp_colours(*colours),
                                           capi::callback(draw, user));
        if (!stats) capi::fail_gl(stats.error());
        if (path_used != nullptr) *path_used = capi::to_c_path(stats->path);
    });
}

aerial_status aerial_gl_draw_two_pass(aerial_gl* gl, const aerial_draw_options* options,
                                      const aerial_vertex_colours* colours,
                                      aerial_draw_pass_function draw, void* user) {
    return guard("aerial_gl_draw_two_pass", capi::last_error_of(gl), [&] {
        require(gl, "gl");
        require(draw, "draw");
        gl::ApplyOptions o = capi::to_cpp_draw(options);
        if (o.path != gl::Path::automatic && o.path != gl::Path::two_pass) {
            fail(AERIAL_ERROR_INVALID_ARGUMENT, "options.path",
                 "expected AERIAL_PATH_AUTOMATIC (0) or _TWO_PASS (3), got " +
                     std::to_string(capi::c_enum_value(options->path)));
        }
        std::optional<gl::VertexColours> v;
        if (colours) v = capi::to_cpp_colours(*colours);
        auto stats = gl::draw_two_pass(gl->api, o, v ? &*v : nullptr, [draw, user](gl::Pass pass) {
            draw(user,
                 pass == gl::Pass::extinction ? AERIAL_PASS_EXTINCTION : AERIAL_PASS_IN_SCATTERING);
        });
        if (!stats) capi::fail_gl(stats.error());
    });
}

aerial_status aerial_gl_set_program_state(aerial_gl* gl, const aerial_draw_options* options) {
    return guard("aerial_gl_set_program_state", capi::last_error_of(gl), [&] {
        require(gl, "gl");
        if (gl->program_state) {
            fail(AERIAL_ERROR_INVALID_ARGUMENT, "gl",
                 "expected aerial_gl_restore_program_state before setting the state again, got "
                 "a second set");
        }
        const gl::ApplyOptions o = capi::to_cpp_draw(options);
        gl->program_state = capi::value_or_fail(gl::ProgramDrawState::set(gl->api, o),
                                                AERIAL_ERROR_INVALID_ARGUMENT);
    });
}

aerial_status aerial_gl_restore_program_state(aerial_gl* gl) {
    return guard("aerial_gl_restore_program_state", capi::last_error_of(gl), [&] {
        require(gl, "gl");
        if (!gl->program_state) {
            fail(AERIAL_ERROR_INVALID_ARGUMENT, "gl",
                 "expected aerial_gl_set_program_state first, got no saved state");
        }
        gl->program_state.reset();  // the destructor restores
    });
}

// ---- ARB vertex program ----------------------------------------------------------------------

aerial_status aerial_gl_arb_limits(aerial_gl* gl, aerial_arb_limits* out) {
    return guard("aerial_gl_arb_limits", capi::last_error_of(gl), [&] {
        require(gl, "gl");
        require(out, "out");
        if (!gl->api.caps.vertex_program) {
            fail(AERIAL_ERROR_GL_UNSUPPORTED, "GL_ARB_vertex_program",
                 "expected the extension, got a context without it (" + gl->api.caps.renderer +
                     ", " + gl->api.caps.version + ")");
        }
        *out = capi::to_c_limits(gl::native_arb_limits(gl->api));
    });
}

aerial_status aerial_arb_describe(const aerial_arb_options* options, aerial_arb_info* out) {
    return guard("aerial_arb_describe", nullptr, [&] {
        require(out, "out");
        const ArbProgram program = capi::generate(capi::to_cpp_arb(options));
        aerial_arb_info info;
        std::memset(&info, 0, sizeof info);
        info.model = program.options.model == Model::height ? AERIAL_MODEL_HEIGHT
                                                            : AERIAL_MODEL_HOFFMAN_PREETHAM;
        info.height_fidelity = capi::to_c_fidelity(program.options);
        info.instructions = program.resources.instructions;
        info.temporaries = program.resources.temporaries;
        info.parameter_bindings = program.resources.parameters;
        info.attributes = program.resources.attributes;
        info.parameter_base = program.options.parameter_base;
        info.parameter_count = arb_parameter_count(program.options);
        info.model_matrix_index =
            program.options.model_matrix ? arb_model_matrix_parameter_index(program.options) : -1;
        *out = info;
    });
}

aerial_status aerial_arb_parameter_layout(const aerial_arb_options* options,
                                          aerial_arb_parameter* out, size_t capacity,
                                          size_t* count) {
    return guard("aerial_arb_parameter_layout", nullptr, [&] {
        if (capacity > 0) require(out, "out");
        const ArbProgram program = capi::generate(capi::to_cpp_arb(options));
        const std::vector<ArbParameterInfo> layout = arb_parameter_layout(program.options);
        if (count != nullptr) *count = layout.size();
        if (capacity == 0 && out == nullptr) return;  // asking the count
        if (capacity < layout.size()) {
            fail(AERIAL_ERROR_BUFFER_TOO_SMALL, "capacity",
                 "expected >= " + std::to_string(layout.size()) +
                     " entries (the program's parameter vectors), got " + std::to_string(capacity));
        }
        for (std::size_t i = 0; i < layout.size(); ++i) {
            out[i].index = layout[i].index;
            out[i].name = layout[i].name;
            out[i].meaning = layout[i].meaning;
        }
    });
}

aerial_status aerial_arb_model_matrix(const aerial_arb_options* options, const float model[16],
                                      float vectors[12]) {
    return guard("aerial_arb_model_matrix", nullptr, [&] {
        require(options, "options");
        require(model, "model");
        require(vectors, "vectors");
        if (options->model_matrix == 0) {
            fail(AERIAL_ERROR_INVALID_ARGUMENT, "options.model_matrix",
                 "expected non-zero (a program that reads a model matrix), got 0");
        }
        if (auto e = validate_model_matrix(model)) {
            fail(AERIAL_ERROR_INVALID_ARGUMENT, "model", std::string(detail::text_of(*e)));
        }
        const auto rows = arb_model_matrix_parameters(model);
        for (std::size_t r = 0; r < 3; ++r) std::memcpy(vectors + 4 * r, rows[r].data(), 16);
    });
}

aerial_status aerial_arb_generate(const aerial_arb_options* options, char* text, size_t capacity,
                                  size_t* length, int* parameter_count) {
    return guard("aerial_arb_generate", nullptr, [&] {
        if (capacity > 0) require(text, "text");
        const ArbProgram program = capi::generate(capi::to_cpp_arb(options));
        if (length != nullptr) *length = program.text.size();
        if (parameter_count != nullptr) *parameter_count = arb_parameter_count(program.options);
        if (capacity == 0 && text == nullptr) return;  // asking the size
        if (capacity < program.text.size() + 1) {
            fail(AERIAL_ERROR_BUFFER_TOO_SMALL, "capacity",
                 "expected >= " + std::to_string(program.text.size() + 1) +
                     " bytes (the program with its terminating 0), got " +
                     std::to_string(capacity));
        }
        std::memcpy(text, program.text.c_str(), program.text.size() + 1);
    });
}

aerial_status aerial_arb_parameters(const aerial_context* context,
                                    const aerial_arb_options* options,
                                    const aerial_display* display, float* vectors,
                                    size_t capacity_vectors, size_t* count) {
    return guard("aerial_arb_parameters", nullptr, [&] {
        require(context, "context");
        if (capacity_vectors > 0) require(vectors, "vectors");
        ArbProgramOptions o = capi::to_cpp_arb(options);
        // The parameters of the program generate_arb_program makes (the fidelity it resolves).
        o = capi::generate(o).options;
        const auto p = capi::parameters(*context, o, display);
        if (count != nullptr) *count = p.size();
        if (capacity_vectors < p.size()) {
            fail(AERIAL_ERROR_BUFFER_TOO_SMALL, "capacity_vectors",
                 "expected >= " + std::to_string(p.size()) +
                     " vectors (what the program reads), got " + std::to_string(capacity_vectors));
        }
        for (size_t i = 0; i < p.size(); ++i) std::memcpy(vectors + 4 * i, p[i].data(), 16);
    });
}

aerial_status aerial_arb_program_create(aerial_gl* gl, const aerial_arb_options* options,
                                        aerial_arb_program** out) {
    return guard("aerial_arb_program_create", capi::last_error_of(gl), [&] {
        require(out, "out");
        *out = nullptr;
        require(gl, "gl");
        ArbProgramOptions o = capi::to_cpp_arb(options);
        if (options != nullptr && options->use_native_limits != 0) {
            o.limits = gl::native_arb_limits(gl->api);
        }
        const ArbProgram generated = capi::generate(o);
        auto program = gl::ArbVertexProgram::create(gl->api, generated);
        if (!program) {
            fail(program.error().field == "GL_ARB_vertex_program" ? AERIAL_ERROR_GL_UNSUPPORTED
                                                                  : AERIAL_ERROR_ARB_PROGRAM,
                 program.error());
        }
        auto created = std::make_unique<aerial_arb_program>();
        created->gl = gl;
        created->program.emplace(std::move(program.value()));
        *out = created.release();
    });
}

void aerial_arb_program_destroy(aerial_arb_program* program) { delete program; }

const char* aerial_arb_program_last_error(const aerial_arb_program* program) {
    return program ? program->last_error.c_str() : "";
}

const char* aerial_arb_program_text(const aerial_arb_program* program) {
    return program ? program->program->program().text.c_str() : "";
}

unsigned int aerial_arb_program_id(const aerial_arb_program* program) {
    return program ? program->program->id() : 0u;
}

aerial_status aerial_arb_program_set_frame(aerial_arb_program* program,
                                           const aerial_context* context,
                                           const aerial_display* display) {
    return guard("aerial_arb_program_set_frame", capi::last_error_of(program), [&] {
        require(program, "program");
        require(context, "context");
        const auto p = capi::parameters(*context, program->program->program().options, display);
        if (auto error = program->program->set_parameters(p)) {
            fail(AERIAL_ERROR_ARB_PROGRAM, *error);
        }
    });
}

aerial_status aerial_arb_program_draw(aerial_arb_program* program,
                                      const aerial_draw_options* options, aerial_draw_function draw,
                                      void* user) {
    return guard("aerial_arb_program_draw", capi::last_error_of(program), [&] {
        require(program, "program");
        require(draw, "draw");
        gl::ApplyOptions o;
        if (options != nullptr) {
            o.texture_unit = options->texture_unit;
            o.textured = options->untextured == 0;
        }
        auto stats = program->program->draw(capi::callback(draw, user), o);
        if (!stats) capi::fail_gl(stats.error());
    });
}

}  // extern "C"
