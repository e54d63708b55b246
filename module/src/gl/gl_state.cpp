// A snapshot of the GL state the module may touch (aerial/gl_state.hpp).
#include "aerial/gl_state.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

#include "aerial/gl_api.hpp"
#include "state_saver.hpp"

namespace aerial::gl {

const std::string* StateSnapshot::find(std::string_view name) const {
    for (const StateEntry& e : entries) {
        if (e.name == name) return &e.value;
    }
    return nullptr;
}

namespace {

// The enum values the captured state takes, by name; others print as hex.
std::string enum_text(GLint value) {
    // clang-format off
    static const std::map<GLint, const char*> kNames{
        {GL_ZERO, "GL_ZERO"},
        {GL_ONE, "GL_ONE"},
        {GL_SRC_COLOR, "GL_SRC_COLOR"},
        {GL_ONE_MINUS_SRC_COLOR, "GL_ONE_MINUS_SRC_COLOR"},
        {GL_SRC_ALPHA, "GL_SRC_ALPHA"},
        {GL_ONE_MINUS_SRC_ALPHA, "GL_ONE_MINUS_SRC_ALPHA"},
        {GL_DST_ALPHA, "GL_DST_ALPHA"},
        {GL_ONE_MINUS_DST_ALPHA, "GL_ONE_MINUS_DST_ALPHA"},
        {GL_DST_COLOR, "GL_DST_COLOR"},
        {GL_ONE_MINUS_DST_COLOR, "GL_ONE_MINUS_DST_COLOR"},
        {GL_NEVER, "GL_NEVER"},
        {GL_LESS, "GL_LESS"},
        {GL_EQUAL, "GL_EQUAL"},
        {GL_LEQUAL, "GL_LEQUAL"},
        {GL_GREATER, "GL_GREATER"},
        {GL_NOTEQUAL, "GL_NOTEQUAL"},
        {GL_GEQUAL, "GL_GEQUAL"},
        {GL_ALWAYS, "GL_ALWAYS"},
        {GL_MODULATE, "GL_MODULATE"},
        {GL_DECAL, "GL_DECAL"},
        {GL_BLEND, "GL_BLEND"},
        {GL_REPLACE, "GL_REPLACE"},
        {GL_ADD, "GL_ADD"},
        {GL_COMBINE, "GL_COMBINE"},
        {GL_ADD_SIGNED, "GL_ADD_SIGNED"},
        {GL_INTERPOLATE, "GL_INTERPOLATE"},
        {GL_SUBTRACT, "GL_SUBTRACT"},
        {GL_DOT3_RGB, "GL_DOT3_RGB"},
        {GL_DOT3_RGBA, "GL_DOT3_RGBA"},
        {GL_TEXTURE, "GL_TEXTURE"},
        {GL_CONSTANT, "GL_CONSTANT"},
        {GL_PRIMARY_COLOR, "GL_PRIMARY_COLOR"},
        {GL_PREVIOUS, "GL_PREVIOUS"},
        {GL_FLAT, "GL_FLAT"},
        {GL_SMOOTH, "GL_SMOOTH"},
        {GL_MODELVIEW, "GL_MODELVIEW"},
        {GL_PROJECTION, "GL_PROJECTION"},
        {GL_FLOAT, "GL_FLOAT"},
        {GL_DOUBLE, "GL_DOUBLE"},
        {GL_BYTE, "GL_BYTE"},
        {GL_UNSIGNED_BYTE, "GL_UNSIGNED_BYTE"},
        {GL_SHORT, "GL_SHORT"},
        {GL_INT, "GL_INT"},
        {GL_FUNC_ADD, "GL_FUNC_ADD"},
        {GL_MIN, "GL_MIN"},
        {GL_MAX, "GL_MAX"},
        {GL_FUNC_SUBTRACT, "GL_FUNC_SUBTRACT"},
        {GL_FUNC_REVERSE_SUBTRACT, "GL_FUNC_REVERSE_SUBTRACT"},
        {GL_FRONT, "GL_FRONT"},
        {GL_BACK, "GL_BACK"},
        {GL_FRONT_AND_BACK, "GL_FRONT_AND_BACK"},
        {GL_AMBIENT, "GL_AMBIENT"},
        {GL_DIFFUSE, "GL_DIFFUSE"},
        {GL_SPECULAR, "GL_SPECULAR"},
        {GL_EMISSION, "GL_EMISSION"},
        {GL_AMBIENT_AND_DIFFUSE, "GL_AMBIENT_AND_DIFFUSE"},
        {GL_FOG_COORD, "GL_FOG_COORD"},
        {GL_FRAGMENT_DEPTH, "GL_FRAGMENT_DEPTH"},
        {GL_CW, "GL_CW"},
        {GL_CCW, "GL_CCW"},
        {GL_POINT, "GL_POINT"},
        {GL_LINE, "GL_LINE"},
        {GL_FILL, "GL_FILL"},
        {GL_EXP, "GL_EXP"},
        {GL_EXP2, "GL_EXP2"},
        {GL_LINEAR, "GL_LINEAR"},
    };
    // clang-format on
    const auto it = kNames.find(value);
    if (it != kNames.end()) return it->second;
    if (value >= GL_TEXTURE0 && value < GL_TEXTURE0 + 32) {
        return "GL_TEXTURE" + std::to_string(value - GL_TEXTURE0);
    }
    char text[16];
    std::snprintf(text, sizeof text, "0x%04X", static_cast<unsigned>(value));
    return text;
}

// ARB_vertex_program guarantees at least 96 env and 96 local parameters.
constexpr GLuint kProgramParameters = 96;

std::string float_text(const GLfloat* v, int n) {
    std::string s;
    for (int i = 0; i < n; ++i) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v[i]));
        if (i) s += ' ';
        s += text;
    }
    return s;
}

class Reader {
  public:
    explicit Reader(const Api& api) : api_(api) {}
    StateSnapshot take() { return std::move(snapshot_); }

    void prefix(std::string p) { prefix_ = std::move(p); }
    void add(const char* name, std::string value) {
        snapshot_.entries.push_back({prefix_ + name, std::move(value)});
    }
    void enabled(const char* name, GLenum cap) {
        add(name, api_.IsEnabled(cap) == GL_TRUE ? "GL_TRUE" : "GL_FALSE");
    }
    void integer(const char* name, GLenum pname) {
        GLint v = 0;
        api_.GetIntegerv(pname, &v);
        add(name, std::to_string(v));
    }
    void enumeration(const char* name, GLenum pname) {
        GLint v = 0;
        api_.GetIntegerv(pname, &v);
        add(name, enum_text(v));
    }
    void booleans(const char* name, GLenum pname, int n) {
        std::array<GLboolean, 4> v{};
        api_.GetBooleanv(pname, v.data());
        std::string s;
        for (int i = 0; i < n; ++i) {
            if (i) s += ' ';
            s += v[static_cast<std::size_t>(i)] ? "GL_TRUE" : "GL_FALSE";
        }
        add(name, s);
    }
    void floats(const char* name, GLenum pname, int n) {
        std::array<GLfloat, 16> v{};
        api_.GetFloatv(pname, v.data());
        add(name, float_text(v.data(), n));
    }
    void pointer(const char* name, GLenum pname) {
        void* p = nullptr;
        api_.GetPointerv(pname, &p);
        char text[32];
        std::snprintf(text, sizeof text, "%p", p);
        add(name, text);
    }
    void tex_env_enum(const char* name, GLenum pname) {
        GLint v = 0;
        api_.GetTexEnviv(GL_TEXTURE_ENV, pname, &v);
        add(name, enum_text(v));
    }
    void tex_env_floats(const char* name, GLenum pname, int n) {
        std::array<GLfloat, 4> v{};
        api_.GetTexEnvfv(GL_TEXTURE_ENV, pname, v.data());
        add(name, float_text(v.data(), n));
    }
    // One client array: enabled, size, type, stride, pointer, buffer.
    void array(const char* name, GLenum array, GLenum size_q, GLenum type_q, GLenum stride_q,
               GLenum pointer_q, GLenum buffer_q) {
        const std::string n = name;
        enabled(n.c_str(), array);
        if (size_q) integer((n + "_SIZE").c_str(), size_q);
        enumeration((n + "_TYPE").c_str(), type_q);
        integer((n + "_STRIDE").c_str(), stride_q);
        pointer((n + "_POINTER").c_str(), pointer_q);
        if (api_.BindBuffer) integer((n + "_BUFFER_BINDING").c_str(), buffer_q);
    }

  private:
    const Api& api_;
    StateSnapshot snapshot_;
    std::string prefix_;
};

// Each group below adds its entries in the order capture_state lists them.
#define AERIAL_ENABLED(cap) r.enabled(#cap, cap)

// Enables, blending, depth and colour masks.
void enables_and_blending(Reader& r, const Api& api) {
    const Caps& caps = api.caps;
    if (caps.secondary_color || caps.vertex_program) AERIAL_ENABLED(GL_COLOR_SUM);
    AERIAL_ENABLED(GL_BLEND);
    AERIAL_ENABLED(GL_FOG);
    AERIAL_ENABLED(GL_LIGHTING);
    AERIAL_ENABLED(GL_COLOR_MATERIAL);
    AERIAL_ENABLED(GL_DEPTH_TEST);
    AERIAL_ENABLED(GL_ALPHA_TEST);
    AERIAL_ENABLED(GL_CULL_FACE);
    if (caps.vertex_program) AERIAL_ENABLED(GL_VERTEX_PROGRAM_ARB);
    if (caps.fragment_program) AERIAL_ENABLED(GL_FRAGMENT_PROGRAM_ARB);
    if (api.BlendFuncSeparate) {
        r.enumeration("GL_BLEND_SRC_RGB", GL_BLEND_SRC_RGB);
        r.enumeration("GL_BLEND_DST_RGB", GL_BLEND_DST_RGB);
        r.enumeration("GL_BLEND_SRC_ALPHA", GL_BLEND_SRC_ALPHA);
        r.enumeration("GL_BLEND_DST_ALPHA", GL_BLEND_DST_ALPHA);
    } else {
        r.enumeration("GL_BLEND_SRC", GL_BLEND_SRC);
        r.enumeration("GL_BLEND_DST", GL_BLEND_DST);
    }
    if (api.BlendEquation) r.enumeration("GL_BLEND_EQUATION_RGB", GL_BLEND_EQUATION_RGB);
    if (api.BlendEquationSeparate) {
        r.enumeration("GL_BLEND_EQUATION_ALPHA", GL_BLEND_EQUATION_ALPHA);
    }
    r.enumeration("GL_DEPTH_FUNC", GL_DEPTH_FUNC);
    r.booleans("GL_DEPTH_WRITEMASK", GL_DEPTH_WRITEMASK, 1);
    r.booleans("GL_COLOR_WRITEMASK", GL_COLOR_WRITEMASK, 4);
}

// Fog, colour material, shading, rasterisation (polygon, viewport, culling) and the alpha test.
void fog_material_and_raster(Reader& r, const Api& api) {
    const Caps& caps = api.caps;
    r.floats("GL_FOG_COLOR", GL_FOG_COLOR, 4);
    if (caps.fog_coord) r.enumeration("GL_FOG_COORD_SRC", GL_FOG_COORD_SRC);
    r.enumeration("GL_COLOR_MATERIAL_FACE", GL_COLOR_MATERIAL_FACE);
    r.enumeration("GL_COLOR_MATERIAL_PARAMETER", GL_COLOR_MATERIAL_PARAMETER);
    for (GLenum face : {GL_FRONT, GL_BACK}) {
        for (GLenum param : {GL_AMBIENT, GL_DIFFUSE}) {
            std::array<GLfloat, 4> v{};
            api.GetMaterialfv(face, param, v.data());
            r.add((std::string(face == GL_FRONT ? "GL_FRONT" : "GL_BACK") +
                   (param == GL_AMBIENT ? " GL_AMBIENT" : " GL_DIFFUSE"))
                      .c_str(),
                  float_text(v.data(), 4));
        }
    }
    r.enumeration("GL_SHADE_MODEL", GL_SHADE_MODEL);
    AERIAL_ENABLED(GL_NORMALIZE);
    AERIAL_ENABLED(GL_SCISSOR_TEST);
    AERIAL_ENABLED(GL_STENCIL_TEST);
    AERIAL_ENABLED(GL_POLYGON_OFFSET_FILL);
    r.floats("GL_POLYGON_OFFSET_FACTOR", GL_POLYGON_OFFSET_FACTOR, 1);
    r.floats("GL_POLYGON_OFFSET_UNITS", GL_POLYGON_OFFSET_UNITS, 1);
    {
        std::array<GLint, 2> modes{};
        api.GetIntegerv(GL_POLYGON_MODE, modes.data());
        r.add("GL_POLYGON_MODE", enum_text(modes[0]) + " " + enum_text(modes[1]));
        std::array<GLint, 4> box{};
        api.GetIntegerv(GL_VIEWPORT, box.data());
        r.add("GL_VIEWPORT", std::to_string(box[0]) + " " + std::to_string(box[1]) + " " +
                                 std::to_string(box[2]) + " " + std::to_string(box[3]));
    }
    r.enumeration("GL_CULL_FACE_MODE", GL_CULL_FACE_MODE);
    r.enumeration("GL_FRONT_FACE", GL_FRONT_FACE);
    r.enumeration("GL_ALPHA_TEST_FUNC", GL_ALPHA_TEST_FUNC);
    r.floats("GL_ALPHA_TEST_REF", GL_ALPHA_TEST_REF, 1);
    r.enumeration("GL_FOG_MODE", GL_FOG_MODE);
    r.floats("GL_FOG_DENSITY", GL_FOG_DENSITY, 1);
    r.floats("GL_FOG_START", GL_FOG_START, 1);
    r.floats("GL_FOG_END", GL_FOG_END, 1);
    r.floats("GL_CURRENT_NORMAL", GL_CURRENT_NORMAL, 3);
}

// Matrix stacks, the framebuffer binding and the pixel unpack state.
void matrices_and_unpack(Reader& r, const Api& api) {
    const Caps& caps = api.caps;
    r.enumeration("GL_MATRIX_MODE", GL_MATRIX_MODE);
    r.integer("GL_MODELVIEW_STACK_DEPTH", GL_MODELVIEW_STACK_DEPTH);
    r.integer("GL_PROJECTION_STACK_DEPTH", GL_PROJECTION_STACK_DEPTH);
    if (api.BindFramebuffer) r.integer("GL_FRAMEBUFFER_BINDING", GL_FRAMEBUFFER_BINDING);
    r.floats("GL_MODELVIEW_MATRIX", GL_MODELVIEW_MATRIX, 16);
    r.floats("GL_PROJECTION_MATRIX", GL_PROJECTION_MATRIX, 16);
    r.integer("GL_UNPACK_ALIGNMENT", GL_UNPACK_ALIGNMENT);
    r.integer("GL_UNPACK_ROW_LENGTH", GL_UNPACK_ROW_LENGTH);
    r.integer("GL_UNPACK_SKIP_ROWS", GL_UNPACK_SKIP_ROWS);
    r.integer("GL_UNPACK_SKIP_PIXELS", GL_UNPACK_SKIP_PIXELS);
    r.booleans("GL_UNPACK_SWAP_BYTES", GL_UNPACK_SWAP_BYTES, 1);
    r.booleans("GL_UNPACK_LSB_FIRST", GL_UNPACK_LSB_FIRST, 1);
    if (caps.pixel_buffer_object && api.BindBuffer) {
        r.integer("GL_PIXEL_UNPACK_BUFFER_BINDING", GL_PIXEL_UNPACK_BUFFER_BINDING);
    }
}

// The first kProgramParameters vertex program parameters of one kind (env or local).
void parameters(Reader& r, const char* name, PFNGLGETPROGRAMENVPARAMETERFVARBPROC get) {
    for (GLuint i = 0; i < kProgramParameters; ++i) {
        std::array<GLfloat, 4> v{};
        get(GL_VERTEX_PROGRAM_ARB, i, v.data());
        r.add((std::string(name) + "[" + std::to_string(i) + "]").c_str(), float_text(v.data(), 4));
    }
}

// The bound ARB vertex program and its parameters, and the bound GLSL program.
void programs(Reader& r, const Api& api) {
    const Caps& caps = api.caps;
    if (caps.vertex_program) {
        GLint bound = 0;
        api.GetProgramiv(GL_VERTEX_PROGRAM_ARB, GL_PROGRAM_BINDING_ARB, &bound);
        r.add("GL_VERTEX_PROGRAM_ARB GL_PROGRAM_BINDING_ARB", std::to_string(bound));
        // The vertex program parameters an engine's programs read: program.env, and
        // program.local of the engine's bound program (the first kProgramParameters of each,
        // the minimum every implementation has).
        parameters(r, "program.env", api.GetProgramEnvParameterfv);
        if (bound != 0) parameters(r, "program.local", api.GetProgramLocalParameterfv);
    }
    if (api.UseProgram) r.integer("GL_CURRENT_PROGRAM", GL_CURRENT_PROGRAM);
}

// The active units, the current colours and the client arrays that are not per unit.
void client_arrays(Reader& r, const Api& api) {
    const Caps& caps = api.caps;
    if (caps.multitexture) {
        r.enumeration("GL_ACTIVE_TEXTURE", GL_ACTIVE_TEXTURE);
        r.enumeration("GL_CLIENT_ACTIVE_TEXTURE", GL_CLIENT_ACTIVE_TEXTURE);
    }
    r.floats("GL_CURRENT_COLOR", GL_CURRENT_COLOR, 4);
    if (caps.secondary_color) r.floats("GL_CURRENT_SECONDARY_COLOR", GL_CURRENT_SECONDARY_COLOR, 3);
    if (api.BindBuffer) r.integer("GL_ARRAY_BUFFER_BINDING", GL_ARRAY_BUFFER_BINDING);
    r.array("GL_VERTEX_ARRAY", GL_VERTEX_ARRAY, GL_VERTEX_ARRAY_SIZE, GL_VERTEX_ARRAY_TYPE,
            GL_VERTEX_ARRAY_STRIDE, GL_VERTEX_ARRAY_POINTER, GL_VERTEX_ARRAY_BUFFER_BINDING);
    r.array("GL_NORMAL_ARRAY", GL_NORMAL_ARRAY, 0, GL_NORMAL_ARRAY_TYPE, GL_NORMAL_ARRAY_STRIDE,
            GL_NORMAL_ARRAY_POINTER, GL_NORMAL_ARRAY_BUFFER_BINDING);
    r.array("GL_COLOR_ARRAY", GL_COLOR_ARRAY, GL_COLOR_ARRAY_SIZE, GL_COLOR_ARRAY_TYPE,
            GL_COLOR_ARRAY_STRIDE, GL_COLOR_ARRAY_POINTER, GL_COLOR_ARRAY_BUFFER_BINDING);
    if (caps.secondary_color) {
        r.array("GL_SECONDARY_COLOR_ARRAY", GL_SECONDARY_COLOR_ARRAY, GL_SECONDARY_COLOR_ARRAY_SIZE,
                GL_SECONDARY_COLOR_ARRAY_TYPE, GL_SECONDARY_COLOR_ARRAY_STRIDE,
                GL_SECONDARY_COLOR_ARRAY_POINTER, GL_SECONDARY_COLOR_ARRAY_BUFFER_BINDING);
    }
    if (caps.fog_coord) {
        r.array("GL_FOG_COORD_ARRAY", GL_FOG_COORD_ARRAY, 0, GL_FOG_COORD_ARRAY_TYPE,
                GL_FOG_COORD_ARRAY_STRIDE, GL_FOG_COORD_ARRAY_POINTER,
                GL_FOG_COORD_ARRAY_BUFFER_BINDING);
    }
}

// The state of the texture unit that is active (and client-active), prefixed "unit N ".
void texture_unit(Reader& r, const Api& api, const std::vector<GLenum>& targets) {
    const Caps& caps = api.caps;
    AERIAL_ENABLED(GL_TEXTURE_1D);
    AERIAL_ENABLED(GL_TEXTURE_2D);
    if (caps.texture_3d) AERIAL_ENABLED(GL_TEXTURE_3D);
    if (targets.back() == GL_TEXTURE_CUBE_MAP) AERIAL_ENABLED(GL_TEXTURE_CUBE_MAP);
    AERIAL_ENABLED(GL_TEXTURE_GEN_S);
    AERIAL_ENABLED(GL_TEXTURE_GEN_T);
    AERIAL_ENABLED(GL_TEXTURE_GEN_R);
    AERIAL_ENABLED(GL_TEXTURE_GEN_Q);
    for (GLenum target : targets) {
        const GLenum q = detail::texture_binding_query(target);
        const char* name = q == GL_TEXTURE_BINDING_1D   ? "GL_TEXTURE_BINDING_1D"
                           : q == GL_TEXTURE_BINDING_2D ? "GL_TEXTURE_BINDING_2D"
                           : q == GL_TEXTURE_BINDING_3D ? "GL_TEXTURE_BINDING_3D"
                                                        : "GL_TEXTURE_BINDING_CUBE_MAP";
        r.integer(name, q);
    }
    r.tex_env_enum("GL_TEXTURE_ENV_MODE", GL_TEXTURE_ENV_MODE);
    r.tex_env_floats("GL_TEXTURE_ENV_COLOR", GL_TEXTURE_ENV_COLOR, 4);
    if (caps.texture_env_combine) {
#define AERIAL_ENV(e) r.tex_env_enum(#e, e)
        AERIAL_ENV(GL_COMBINE_RGB);
        AERIAL_ENV(GL_COMBINE_ALPHA);
        AERIAL_ENV(GL_SOURCE0_RGB);
        AERIAL_ENV(GL_SOURCE1_RGB);
        AERIAL_ENV(GL_SOURCE2_RGB);
        AERIAL_ENV(GL_SOURCE0_ALPHA);
        AERIAL_ENV(GL_SOURCE1_ALPHA);
        AERIAL_ENV(GL_SOURCE2_ALPHA);
        AERIAL_ENV(GL_OPERAND0_RGB);
        AERIAL_ENV(GL_OPERAND1_RGB);
        AERIAL_ENV(GL_OPERAND2_RGB);
        AERIAL_ENV(GL_OPERAND0_ALPHA);
        AERIAL_ENV(GL_OPERAND1_ALPHA);
        AERIAL_ENV(GL_OPERAND2_ALPHA);
#undef AERIAL_ENV
        r.tex_env_floats("GL_RGB_SCALE", GL_RGB_SCALE, 1);
        r.tex_env_floats("GL_ALPHA_SCALE", GL_ALPHA_SCALE, 1);
    }
    r.floats("GL_TEXTURE_MATRIX", GL_TEXTURE_MATRIX, 16);
    r.integer("GL_TEXTURE_STACK_DEPTH", GL_TEXTURE_STACK_DEPTH);
    r.floats("GL_CURRENT_TEXTURE_COORDS", GL_CURRENT_TEXTURE_COORDS, 4);
    r.array("GL_TEXTURE_COORD_ARRAY", GL_TEXTURE_COORD_ARRAY, GL_TEXTURE_COORD_ARRAY_SIZE,
            GL_TEXTURE_COORD_ARRAY_TYPE, GL_TEXTURE_COORD_ARRAY_STRIDE,
            GL_TEXTURE_COORD_ARRAY_POINTER, GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING);
}

// Every unit the module saves. Selecting units changes the active units: client_arrays records
// them before, and they are restored after.
void texture_units(Reader& r, const Api& api) {
    const Caps& caps = api.caps;
    GLint active = GL_TEXTURE0, client_active = GL_TEXTURE0;
    if (caps.multitexture) {
        api.GetIntegerv(GL_ACTIVE_TEXTURE, &active);
        api.GetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &client_active);
    }
    const std::vector<GLenum> targets = detail::texture_targets(caps);
    for (int unit = 0; unit < detail::saved_texture_units(caps); ++unit) {
        if (caps.multitexture) {
            api.ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
            api.ClientActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        }
        r.prefix("unit " + std::to_string(unit) + " ");
        texture_unit(r, api, targets);
    }
    if (caps.multitexture) {
        api.ActiveTexture(static_cast<GLenum>(active));
        api.ClientActiveTexture(static_cast<GLenum>(client_active));
    }
}

#undef AERIAL_ENABLED

}  // namespace

StateSnapshot capture_state(const Api& api) {
    Reader r(api);
    enables_and_blending(r, api);
    fog_material_and_raster(r, api);
    matrices_and_unpack(r, api);
    programs(r, api);
    client_arrays(r, api);
    texture_units(r, api);
    return r.take();
}

std::vector<std::string> state_differences(const StateSnapshot& before,
                                           const StateSnapshot& after) {
    std::vector<std::string> out;
    for (const StateEntry& e : before.entries) {
        const std::string* other = after.find(e.name);
        if (other == nullptr) {
            out.push_back(e.name + ": missing after");
        } else if (*other != e.value) {
            out.push_back(e.name + ": " + e.value + " -> " + *other);
        }
    }
    for (const StateEntry& e : after.entries) {
        if (before.find(e.name) == nullptr) out.push_back(e.name + ": missing before");
    }
    return out;
}

}  // namespace aerial::gl
