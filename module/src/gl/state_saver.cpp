// Save-as-you-change GL state (aerial/gl_state_saver.hpp) and the texture-unit helpers.
#include "state_saver.hpp"

#include "../common/error_text.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>

namespace aerial::gl {

std::optional<Error> no_current_context(const Api& api) {
    if (api.GetString != nullptr && api.GetString(GL_VERSION) != nullptr) return std::nullopt;
    // Each public caller re-attributes it to itself (aerial::detail::from).
    return aerial::detail::error("gl::no_current_context", "context",
                                 "no GL context is current on this thread "
                                 "(glGetString(GL_VERSION) is NULL); make the engine's context "
                                 "current before calling the module");
}

std::vector<GLenum> detail::texture_targets(const Caps& caps) {
    std::vector<GLenum> targets{GL_TEXTURE_1D, GL_TEXTURE_2D};
    if (caps.texture_3d) targets.push_back(GL_TEXTURE_3D);
    if (caps.at_least(1, 3) || caps.has_extension("GL_ARB_texture_cube_map") ||
        caps.has_extension("GL_EXT_texture_cube_map")) {
        targets.push_back(GL_TEXTURE_CUBE_MAP);
    }
    return targets;
}

GLenum detail::texture_binding_query(GLenum target) {
    switch (target) {
        case GL_TEXTURE_1D:
            return GL_TEXTURE_BINDING_1D;
        case GL_TEXTURE_3D:
            return GL_TEXTURE_BINDING_3D;
        case GL_TEXTURE_CUBE_MAP:
            return GL_TEXTURE_BINDING_CUBE_MAP;
        default:
            return GL_TEXTURE_BINDING_2D;
    }
}

int detail::saved_texture_units(const Caps& caps) { return std::min(caps.max_texture_units, 8); }

namespace {

const std::initializer_list<GLenum> kBlendFactorList = {GL_ZERO,
                                                        GL_ONE,
                                                        GL_SRC_COLOR,
                                                        GL_ONE_MINUS_SRC_COLOR,
                                                        GL_DST_COLOR,
                                                        GL_ONE_MINUS_DST_COLOR,
                                                        GL_SRC_ALPHA,
                                                        GL_ONE_MINUS_SRC_ALPHA,
                                                        GL_DST_ALPHA,
                                                        GL_ONE_MINUS_DST_ALPHA,
                                                        GL_CONSTANT_COLOR,
                                                        GL_ONE_MINUS_CONSTANT_COLOR,
                                                        GL_CONSTANT_ALPHA,
                                                        GL_ONE_MINUS_CONSTANT_ALPHA,
                                                        GL_SRC_ALPHA_SATURATE};
const StateSaver::EnumState kBlendSource{GL_BLEND_SRC, "GL_BLEND_SRC", GL_ONE, kBlendFactorList};
const StateSaver::EnumState kBlendDestination{GL_BLEND_DST, "GL_BLEND_DST", GL_ZERO,
                                              kBlendFactorList};
const StateSaver::EnumState kBlendEquation{
    GL_BLEND_EQUATION_RGB,
    "GL_BLEND_EQUATION",
    GL_FUNC_ADD,
    {GL_FUNC_ADD, GL_FUNC_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT, GL_MIN, GL_MAX}};
const std::initializer_list<GLenum> kArrayTypeList = {
    GL_BYTE,         GL_UNSIGNED_BYTE, GL_SHORT,  GL_UNSIGNED_SHORT, GL_INT,
    GL_UNSIGNED_INT, GL_FLOAT,         GL_DOUBLE, GL_HALF_FLOAT};
const StateSaver::EnumState kArrayType{0, "array type", GL_FLOAT, kArrayTypeList};

const StateSaver::EnumState kMatrixMode{GL_MATRIX_MODE,
                                        "GL_MATRIX_MODE",
                                        GL_MODELVIEW,
                                        {GL_MODELVIEW, GL_PROJECTION, GL_TEXTURE, GL_COLOR}};
const StateSaver::EnumState kDepthFunc{
    GL_DEPTH_FUNC,
    "GL_DEPTH_FUNC",
    GL_LESS,
    {GL_NEVER, GL_LESS, GL_EQUAL, GL_LEQUAL, GL_GREATER, GL_NOTEQUAL, GL_GEQUAL, GL_ALWAYS}};
const StateSaver::EnumState kCullFaceMode{
    GL_CULL_FACE_MODE, "GL_CULL_FACE_MODE", GL_BACK, {GL_FRONT, GL_BACK, GL_FRONT_AND_BACK}};
const StateSaver::EnumState kColorMaterialFace{GL_COLOR_MATERIAL_FACE,
                                               "GL_COLOR_MATERIAL_FACE",
                                               GL_FRONT_AND_BACK,
                                               {GL_FRONT, GL_BACK, GL_FRONT_AND_BACK}};
const StateSaver::EnumState kColorMaterialParameter{
    GL_COLOR_MATERIAL_PARAMETER,
    "GL_COLOR_MATERIAL_PARAMETER",
    GL_AMBIENT_AND_DIFFUSE,
    {GL_EMISSION, GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR, GL_AMBIENT_AND_DIFFUSE}};

std::string hex(GLint value) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%04X", static_cast<unsigned>(value));
    return text;
}

}  // namespace

GLint StateSaver::read_enum(const EnumState& state) { return read_enum(state, state.query); }

GLint StateSaver::read_enum(const EnumState& state, GLenum query) {
    GLint value = static_cast<GLint>(state.initial);
    api_.GetIntegerv(query, &value);
    return accepted_or_initial(state, value);
}

GLint StateSaver::accepted_or_initial(const EnumState& state, GLint value) {
    for (GLenum accepted : state.accepted) {
        if (static_cast<GLint>(accepted) == value) return value;
    }
    rejected_.push_back(std::string(state.name) + ": the driver reported " + hex(value) +
                        ", which GL does not accept back; restored as its initial value " +
                        hex(static_cast<GLint>(state.initial)));
    return static_cast<GLint>(state.initial);
}

void StateSaver::restore() {
    for (auto it = undo_.rbegin(); it != undo_.rend(); ++it) (*it)();
    undo_.clear();
    if (saved_array_buffer_) api_.BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer_));
    if (saved_client_active_) api_.ClientActiveTexture(static_cast<GLenum>(client_active_));
    if (saved_active_) api_.ActiveTexture(static_cast<GLenum>(active_));
    saved_array_buffer_ = saved_client_active_ = saved_active_ = false;
}

void StateSaver::select_unit(int unit) {
    if (api_.ActiveTexture == nullptr) return;  // no multitexture: unit is 0 (checked by callers)
    if (!saved_active_) {
        api_.GetIntegerv(GL_ACTIVE_TEXTURE, &active_);
        saved_active_ = true;
    }
    api_.ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
}

void StateSaver::select_client_unit(int unit) {
    if (api_.ClientActiveTexture == nullptr) return;
    if (!saved_client_active_) {
        api_.GetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &client_active_);
        saved_client_active_ = true;
    }
    api_.ClientActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
}

void StateSaver::unbind_array_buffer() {
    if (api_.BindBuffer == nullptr) return;
    if (!saved_array_buffer_) {
        api_.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer_);
        saved_array_buffer_ = true;
    }
    api_.BindBuffer(GL_ARRAY_BUFFER, 0);
}

void StateSaver::rebind_engine_array_buffer() {
    if (saved_array_buffer_) api_.BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer_));
}

void StateSaver::enable(GLenum cap, bool on) {
    const bool was = api_.IsEnabled(cap) == GL_TRUE;
    if (was == on) return;
    (on ? api_.Enable : api_.Disable)(cap);
    const Api* api = &api_;
    undo_.push_back([api, cap, was] { (was ? api->Enable : api->Disable)(cap); });
}

void StateSaver::unit_enable(int unit, GLenum cap, bool on) {
    select_unit(unit);
    const bool was = api_.IsEnabled(cap) == GL_TRUE;
    if (was == on) return;
    (on ? api_.Enable : api_.Disable)(cap);
    const Api* api = &api_;
    undo_.push_back([api, unit, cap, was] {
        if (api->ActiveTexture) api->ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        (was ? api->Enable : api->Disable)(cap);
    });
}

void StateSaver::unit_disable_all_targets(int unit) {
    for (GLenum target : detail::texture_targets(api_.caps)) unit_enable(unit, target, false);
}

void StateSaver::blend_func(GLenum source, GLenum destination) {
    const Api* api = &api_;
    if (api_.BlendFuncSeparate) {
        std::array<GLint, 4> was{};
        was[0] = read_enum(kBlendSource, GL_BLEND_SRC_RGB);
        was[1] = read_enum(kBlendDestination, GL_BLEND_DST_RGB);
        was[2] = read_enum(kBlendSource, GL_BLEND_SRC_ALPHA);
        was[3] = read_enum(kBlendDestination, GL_BLEND_DST_ALPHA);
        undo_.push_back([api, was] {
            api->BlendFuncSeparate(static_cast<GLenum>(was[0]), static_cast<GLenum>(was[1]),
                                   static_cast<GLenum>(was[2]), static_cast<GLenum>(was[3]));
        });
    } else {
        std::array<GLint, 2> was{};
        was[0] = read_enum(kBlendSource);
        was[1] = read_enum(kBlendDestination);
        undo_.push_back([api, was] {
            api->BlendFunc(static_cast<GLenum>(was[0]), static_cast<GLenum>(was[1]));
        });
    }
    api_.BlendFunc(source, destination);
    // Blending must add: an engine may have left MIN, MAX or SUBTRACT selected.
    if (api_.BlendEquation) {
        std::array<GLint, 2> equation{GL_FUNC_ADD, GL_FUNC_ADD};
        equation[0] = read_enum(kBlendEquation);
        equation[1] = equation[0];
        if (api_.BlendEquationSeparate) {
            equation[1] = read_enum(kBlendEquation, GL_BLEND_EQUATION_ALPHA);
        }
        undo_.push_back([api, equation] {
            if (api->BlendEquationSeparate) {
                api->BlendEquationSeparate(static_cast<GLenum>(equation[0]),
                                           static_cast<GLenum>(equation[1]));
            } else {
                api->BlendEquation(static_cast<GLenum>(equation[0]));
            }
        });
        api_.BlendEquation(GL_FUNC_ADD);
    }
}

void StateSaver::depth_func(GLenum function) {
    const GLint was = read_enum(kDepthFunc);
    const Api* api = &api_;
    undo_.push_back([api, was] { api->DepthFunc(static_cast<GLenum>(was)); });
    api_.DepthFunc(function);
}

void StateSaver::cull_face(GLenum face) {
    const GLint was = read_enum(kCullFaceMode);
    const Api* api = &api_;
    undo_.push_back([api, was] { api->CullFace(static_cast<GLenum>(was)); });
    api_.CullFace(face);
}

void StateSaver::depth_mask(bool write) {
    GLboolean was = GL_TRUE;
    api_.GetBooleanv(GL_DEPTH_WRITEMASK, &was);
    const Api* api = &api_;
    undo_.push_back([api, was] { api->DepthMask(was); });
    api_.DepthMask(write ? GL_TRUE : GL_FALSE);
}

void StateSaver::mask_alpha() {
    std::array<GLboolean, 4> was{GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
    api_.GetBooleanv(GL_COLOR_WRITEMASK, was.data());
    const Api* api = &api_;
    undo_.push_back([api, was] { api->ColorMask(was[0], was[1], was[2], was[3]); });
    api_.ColorMask(was[0], was[1], was[2], GL_FALSE);
}

void StateSaver::fog_color(const GLfloat colour[4]) {
    std::array<GLfloat, 4> was{};
    api_.GetFloatv(GL_FOG_COLOR, was.data());
    const Api* api = &api_;
    undo_.push_back([api, was] { api->Fogfv(GL_FOG_COLOR, was.data()); });
    api_.Fogfv(GL_FOG_COLOR, colour);
}

void StateSaver::tex_env(int unit, GLenum pname, GLint value) {
    select_unit(unit);
    const Api* api = &api_;
    if (pname == GL_RGB_SCALE || pname == GL_ALPHA_SCALE) {
        GLfloat was = 1.0f;
        api_.GetTexEnvfv(GL_TEXTURE_ENV, pname, &was);
        if (was == static_cast<GLfloat>(value)) return;
        undo_.push_back([api, unit, pname, was] {
            if (api->ActiveTexture) api->ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
            api->TexEnvf(GL_TEXTURE_ENV, pname, was);
        });
        api_.TexEnvf(GL_TEXTURE_ENV, pname, static_cast<GLfloat>(value));
        return;
    }
    GLint was = 0;
    api_.GetTexEnviv(GL_TEXTURE_ENV, pname, &was);
    if (was == value) return;
    undo_.push_back([api, unit, pname, was] {
        if (api->ActiveTexture) api->ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        api->TexEnvi(GL_TEXTURE_ENV, pname, was);
    });
    api_.TexEnvi(GL_TEXTURE_ENV, pname, value);
}

void StateSaver::bind_texture(int unit, GLenum target, GLuint texture) {
    select_unit(unit);
    GLint was = 0;
    api_.GetIntegerv(detail::texture_binding_query(target), &was);
    const Api* api = &api_;
    undo_.push_back([api, unit, target, was] {
        if (api->ActiveTexture) api->ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        api->BindTexture(target, static_cast<GLuint>(was));
    });
    api_.BindTexture(target, texture);
}

void StateSaver::texture_matrix_identity(int unit) {
    select_unit(unit);
    const GLint mode = read_enum(kMatrixMode);
    std::array<GLfloat, 16> was{};
    api_.GetFloatv(GL_TEXTURE_MATRIX, was.data());
    const Api* api = &api_;
    undo_.push_back([api, unit, mode, was] {
        if (api->ActiveTexture) api->ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        api->MatrixMode(GL_TEXTURE);
        api->LoadMatrixf(was.data());
        api->MatrixMode(static_cast<GLenum>(mode));
    });
    api_.MatrixMode(GL_TEXTURE);
    api_.LoadIdentity();
    api_.MatrixMode(static_cast<GLenum>(mode));
}

void StateSaver::bind_program(GLuint program) {
    GLint was = 0;
    api_.GetProgramiv(GL_VERTEX_PROGRAM_ARB, GL_PROGRAM_BINDING_ARB, &was);
    if (static_cast<GLuint>(was) == program) return;
    const Api* api = &api_;
    undo_.push_back(
        [api, was] { api->BindProgram(GL_VERTEX_PROGRAM_ARB, static_cast<GLuint>(was)); });
    api_.BindProgram(GL_VERTEX_PROGRAM_ARB, program);
}

void StateSaver::use_no_glsl_program() {
    if (api_.UseProgram == nullptr) return;
    GLint was = 0;
    api_.GetIntegerv(GL_CURRENT_PROGRAM, &was);
    if (was == 0) return;
    const Api* api = &api_;
    undo_.push_back([api, was] { api->UseProgram(static_cast<GLuint>(was)); });
    api_.UseProgram(0);
}

void StateSaver::color_material() {
    struct Saved {
        bool enabled = false;
        GLint face = GL_FRONT_AND_BACK, mode = GL_AMBIENT_AND_DIFFUSE;
        std::array<std::array<GLfloat, 4>, 4> colours{};  // front/back × ambient/diffuse
    } was;
    was.enabled = api_.IsEnabled(GL_COLOR_MATERIAL) == GL_TRUE;
    was.face = read_enum(kColorMaterialFace);
    was.mode = read_enum(kColorMaterialParameter);
    static constexpr GLenum kFaces[2] = {GL_FRONT, GL_BACK};
    static constexpr GLenum kParams[2] = {GL_AMBIENT, GL_DIFFUSE};
    for (std::size_t f = 0; f < 2; ++f) {
        for (std::size_t p = 0; p < 2; ++p) {
            api_.GetMaterialfv(kFaces[f], kParams[p], was.colours[2 * f + p].data());
        }
    }
    const Api* api = &api_;
    undo_.push_back([api, was] {
        api->Disable(GL_COLOR_MATERIAL);
        for (std::size_t f = 0; f < 2; ++f) {
            for (std::size_t p = 0; p < 2; ++p) {
                api->Materialfv(kFaces[f], kParams[p], was.colours[2 * f + p].data());
            }
        }
        api->ColorMaterial(static_cast<GLenum>(was.face), static_cast<GLenum>(was.mode));
        if (was.enabled) api->Enable(GL_COLOR_MATERIAL);
    });
    api_.ColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    api_.Enable(GL_COLOR_MATERIAL);
}

void StateSaver::save_current_color() {
    std::array<GLfloat, 4> was{};
    api_.GetFloatv(GL_CURRENT_COLOR, was.data());
    const Api* api = &api_;
    undo_.push_back([api, was] { api->Color4f(was[0], was[1], was[2], was[3]); });
}

void StateSaver::save_current_secondary_color() {
    if (api_.SecondaryColor3f == nullptr) return;
    std::array<GLfloat, 4> was{};
    api_.GetFloatv(GL_CURRENT_SECONDARY_COLOR, was.data());
    const Api* api = &api_;
    undo_.push_back([api, was] { api->SecondaryColor3f(was[0], was[1], was[2]); });
}

void StateSaver::save_current_texcoord(int unit) {
    select_unit(unit);
    std::array<GLfloat, 4> was{};
    api_.GetFloatv(GL_CURRENT_TEXTURE_COORDS, was.data());
    const Api* api = &api_;
    if (api_.MultiTexCoord4f) {
        undo_.push_back([api, unit, was] {
            api->MultiTexCoord4f(static_cast<GLenum>(GL_TEXTURE0 + unit), was[0], was[1], was[2],
                                 was[3]);
        });
    } else if (unit == 0) {  // without multitexture there is only unit 0
        undo_.push_back([api, was] { api->TexCoord4f(was[0], was[1], was[2], was[3]); });
    }
}

void StateSaver::load_matrix(GLenum mode, const GLfloat matrix[16]) {
    const GLint was_mode = read_enum(kMatrixMode);
    std::array<GLfloat, 16> was{};
    api_.GetFloatv(mode == GL_PROJECTION ? GL_PROJECTION_MATRIX : GL_MODELVIEW_MATRIX, was.data());
    const Api* api = &api_;
    undo_.push_back([api, mode, was_mode, was] {
        api->MatrixMode(mode);
        api->LoadMatrixf(was.data());
        api->MatrixMode(static_cast<GLenum>(was_mode));
    });
    api_.MatrixMode(mode);
    api_.LoadMatrixf(matrix);
    api_.MatrixMode(static_cast<GLenum>(was_mode));
}

void StateSaver::pixel_store(GLenum pname, GLint value) {
    GLint was = 0;
    api_.GetIntegerv(pname, &was);
    if (was == value) return;
    const Api* api = &api_;
    undo_.push_back([api, pname, was] { api->PixelStorei(pname, was); });
    api_.PixelStorei(pname, value);
}

void StateSaver::unbind_pixel_unpack_buffer() {
    if (!api_.caps.pixel_buffer_object || !api_.BindBuffer) return;
    GLint was = 0;
    api_.GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &was);
    if (was == 0) return;
    const Api* api = &api_;
    undo_.push_back(
        [api, was] { api->BindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(was)); });
    api_.BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
}

namespace {

// One client array's pointer state.
struct ArraySaved {
    bool enabled = false;
    GLint size = 4, type = GL_FLOAT, stride = 0, buffer = 0;
    void* pointer = nullptr;
};

ArraySaved read_array(const Api& api, GLenum array, GLenum size_q, GLenum type_q, GLenum stride_q,
                      GLenum pointer_q, GLenum buffer_q) {
    ArraySaved a;
    a.enabled = api.IsEnabled(array) == GL_TRUE;
    api.GetIntegerv(size_q, &a.size);
    api.GetIntegerv(type_q, &a.type);
    api.GetIntegerv(stride_q, &a.stride);
    api.GetPointerv(pointer_q, &a.pointer);
    if (api.BindBuffer) api.GetIntegerv(buffer_q, &a.buffer);
    return a;
}

}  // namespace

void StateSaver::color_array(GLint size, GLenum type, GLsizei stride, const void* pointer) {
    unbind_array_buffer();
    save_current_color();
    ArraySaved was =
        read_array(api_, GL_COLOR_ARRAY, GL_COLOR_ARRAY_SIZE, GL_COLOR_ARRAY_TYPE,
                   GL_COLOR_ARRAY_STRIDE, GL_COLOR_ARRAY_POINTER, GL_COLOR_ARRAY_BUFFER_BINDING);
    was.type = accepted_or_initial(kArrayType, was.type);
    const Api* api = &api_;
    undo_.push_back([api, was] {
        if (api->BindBuffer) api->BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(was.buffer));
        api->ColorPointer(was.size, static_cast<GLenum>(was.type), was.stride, was.pointer);
        (was.enabled ? api->EnableClientState : api->DisableClientState)(GL_COLOR_ARRAY);
    });
    api_.ColorPointer(size, type, stride, pointer);
    api_.EnableClientState(GL_COLOR_ARRAY);
}

void StateSaver::secondary_color_array(GLint size, GLenum type, GLsizei stride,
                                       const void* pointer) {
    unbind_array_buffer();
    save_current_secondary_color();
    ArraySaved was =
        read_array(api_, GL_SECONDARY_COLOR_ARRAY, GL_SECONDARY_COLOR_ARRAY_SIZE,
                   GL_SECONDARY_COLOR_ARRAY_TYPE, GL_SECONDARY_COLOR_ARRAY_STRIDE,
                   GL_SECONDARY_COLOR_ARRAY_POINTER, GL_SECONDARY_COLOR_ARRAY_BUFFER_BINDING);
    was.type = accepted_or_initial(kArrayType, was.type);
    const Api* api = &api_;
    undo_.push_back([api, was] {
        if (api->BindBuffer) api->BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(was.buffer));
        api->SecondaryColorPointer(was.size, static_cast<GLenum>(was.type), was.stride,
                                   was.pointer);
        (was.enabled ? api->EnableClientState : api->DisableClientState)(GL_SECONDARY_COLOR_ARRAY);
    });
    api_.SecondaryColorPointer(size, type, stride, pointer);
    api_.EnableClientState(GL_SECONDARY_COLOR_ARRAY);
}

void StateSaver::texcoord_array(int unit, GLint size, GLenum type, GLsizei stride,
                                const void* pointer) {
    unbind_array_buffer();
    save_current_texcoord(unit);
    select_client_unit(unit);
    ArraySaved was =
        read_array(api_, GL_TEXTURE_COORD_ARRAY, GL_TEXTURE_COORD_ARRAY_SIZE,
                   GL_TEXTURE_COORD_ARRAY_TYPE, GL_TEXTURE_COORD_ARRAY_STRIDE,
                   GL_TEXTURE_COORD_ARRAY_POINTER, GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING);
    was.type = accepted_or_initial(kArrayType, was.type);
    const Api* api = &api_;
    undo_.push_back([api, unit, was] {
        if (api->ClientActiveTexture) {
            api->ClientActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        }
        if (api->BindBuffer) api->BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(was.buffer));
        api->TexCoordPointer(was.size, static_cast<GLenum>(was.type), was.stride, was.pointer);
        (was.enabled ? api->EnableClientState : api->DisableClientState)(GL_TEXTURE_COORD_ARRAY);
    });
    api_.TexCoordPointer(size, type, stride, pointer);
    api_.EnableClientState(GL_TEXTURE_COORD_ARRAY);
}

}  // namespace aerial::gl
