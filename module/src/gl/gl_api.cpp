// Run-time resolution of the GL entry points (aerial/gl_api.hpp).
#include "aerial/gl_api.hpp"

#include "../common/error_text.hpp"

#include <cstdio>
#include <cstring>

namespace aerial::gl {

bool Caps::has_extension(std::string_view name) const {
    if (name.empty()) return false;
    std::string_view all = extensions;
    std::size_t from = 0;
    while (from < all.size()) {
        std::size_t end = all.find(' ', from);
        if (end == std::string_view::npos) end = all.size();
        if (all.substr(from, end - from) == name) return true;
        from = end + 1;
    }
    return false;
}

bool Caps::at_least(int major, int minor) const {
    return version_major > major || (version_major == major && version_minor >= minor);
}

namespace {

void* resolve(LoadFunction load, void* user, const char* name, const char* alternative) {
    void* p = load(user, name);
    if (p == nullptr && alternative[0] != '\0') p = load(user, alternative);
    return p;
}

// "2.1 Mesa 22.3.6" -> 2, 1. OpenGL ES strings ("OpenGL ES 2.0 ...") are not what the module
// drives; they parse as 0.0 and offer nothing.
void parse_version(const char* text, int& major, int& minor) {
    major = 0;
    minor = 0;
    if (text == nullptr) return;
    if (std::sscanf(text, "%d.%d", &major, &minor) != 2) {
        major = 0;
        minor = 0;
    }
}

std::string read_extensions(const Api& api) {
    // Compatibility contexts keep the single extension string (GL_EXTENSIONS); the module only
    // drives compatibility contexts, because a core profile has no fixed-function pipeline.
    const GLubyte* e = api.GetString(GL_EXTENSIONS);
    return e ? std::string(reinterpret_cast<const char*>(e)) : std::string();
}

constexpr const char* kLoad = "gl::load_api";

// GL_CONTEXT_PROFILE_MASK (GL 3.2) and GL_CONTEXT_FLAGS (GL 3.0), from glext.h.
constexpr GLenum kContextProfileMask = 0x9126;
constexpr GLint kContextCoreProfileBit = 0x1;
constexpr GLenum kContextFlags = 0x821E;
constexpr GLint kContextForwardCompatibleBit = 0x1;

// "core profile" or "forward-compatible" when the context has no fixed-function pipeline, empty
// otherwise. Asked before anything else: a core profile rejects GL_EXTENSIONS and every
// fixed-function query with GL_INVALID_ENUM.
std::string missing_fixed_function(const Api& api, const Caps& caps) {
    GLint value = 0;
    if (caps.at_least(3, 2)) {
        api.GetIntegerv(kContextProfileMask, &value);
        if ((value & kContextCoreProfileBit) != 0) return "core profile";
    }
    if (caps.at_least(3, 0)) {
        value = 0;
        api.GetIntegerv(kContextFlags, &value);
        if ((value & kContextForwardCompatibleBit) != 0) return "forward-compatible";
    }
    return {};
}

}  // namespace

Result<Api> load_api(LoadFunction load, void* user) {
    if (load == nullptr) {
        return aerial::detail::error(kLoad, "load", "the GetProcAddress function is null");
    }
    Api api;
#define AERIAL_GL_REQUIRED(type, member, name, alternative)                                   \
    api.member = reinterpret_cast<type>(resolve(load, user, name, alternative));              \
    if (api.member == nullptr) {                                                              \
        return aerial::detail::error(kLoad, name,                                             \
                                     "not found by the loader (is a GL context current, and " \
                                     "does the loader resolve GL 1.1 functions?)");           \
    }
    AERIAL_GL_REQUIRED_FUNCTIONS(AERIAL_GL_REQUIRED)
#undef AERIAL_GL_REQUIRED
#define AERIAL_GL_OPTIONAL(type, member, name, alternative) \
    api.member = reinterpret_cast<type>(resolve(load, user, name, alternative));
    AERIAL_GL_OPTIONAL_FUNCTIONS(AERIAL_GL_OPTIONAL)
#undef AERIAL_GL_OPTIONAL

    const GLubyte* version = api.GetString(GL_VERSION);
    if (version == nullptr) {
        return aerial::detail::error(kLoad, "glGetString",
                                     "GL_VERSION is NULL (no current context, or the loader "
                                     "resolves to libGL while the context is OSMesa's)");
    }
    Caps& caps = api.caps;
    caps.version = reinterpret_cast<const char*>(version);
    parse_version(caps.version.c_str(), caps.version_major, caps.version_minor);
    if (const GLubyte* s = api.GetString(GL_VENDOR)) caps.vendor = reinterpret_cast<const char*>(s);
    if (const GLubyte* s = api.GetString(GL_RENDERER)) {
        caps.renderer = reinterpret_cast<const char*>(s);
    }
    const std::string missing = missing_fixed_function(api, caps);
    if (!missing.empty()) {
        return aerial::detail::unsupported(kLoad, "profile",
                                           "the context (GL " + caps.version + ", " +
                                               caps.renderer + ") is a " + missing +
                                               " context: no fixed-function pipeline; the "
                                               "module needs a compatibility profile");
    }
    caps.extensions = read_extensions(api);

    // A feature is offered when the version or the extension string says so and its entry
    // points resolved; otherwise its pointers are cleared so that nothing calls them by mistake.
    caps.multitexture = (caps.at_least(1, 3) || caps.has_extension("GL_ARB_multitexture")) &&
                        api.ActiveTexture && api.ClientActiveTexture;
    if (!caps.multitexture) {
        api.ActiveTexture = nullptr;
        api.ClientActiveTexture = nullptr;
    }
    caps.texture_3d =
        (caps.at_least(1, 2) || caps.has_extension("GL_EXT_texture3D")) && api.TexImage3D;
    if (!caps.texture_3d) api.TexImage3D = nullptr;
    caps.texture_env_combine =
        caps.multitexture &&
        (caps.at_least(1, 3) || caps.has_extension("GL_ARB_texture_env_combine") ||
         caps.has_extension("GL_EXT_texture_env_combine"));
    caps.secondary_color = (caps.at_least(1, 4) || caps.has_extension("GL_EXT_secondary_color")) &&
                           api.SecondaryColorPointer;
    if (!caps.secondary_color) api.SecondaryColorPointer = nullptr;
    if (!caps.secondary_color) api.SecondaryColor3f = nullptr;
    if (!caps.multitexture) api.MultiTexCoord4f = nullptr;
    caps.vertex_buffer_object =
        (caps.at_least(1, 5) || caps.has_extension("GL_ARB_vertex_buffer_object")) &&
        api.BindBuffer;
    if (!caps.vertex_buffer_object) api.BindBuffer = nullptr;
    caps.pixel_buffer_object =
        caps.vertex_buffer_object &&
        (caps.at_least(2, 1) || caps.has_extension("GL_ARB_pixel_buffer_object") ||
         caps.has_extension("GL_EXT_pixel_buffer_object"));
    caps.fragment_program = caps.has_extension("GL_ARB_fragment_program");
    // Blend state the two-pass path sets and restores; GLSL programs it unbinds while it draws.
    if (!(caps.at_least(1, 4) || caps.has_extension("GL_EXT_blend_func_separate"))) {
        api.BlendFuncSeparate = nullptr;
    }
    if (!(caps.at_least(1, 4) || caps.has_extension("GL_EXT_blend_minmax") ||
          caps.has_extension("GL_ARB_imaging"))) {
        api.BlendEquation = nullptr;
    }
    if (!(caps.at_least(2, 0) || caps.has_extension("GL_EXT_blend_equation_separate"))) {
        api.BlendEquationSeparate = nullptr;
    }
    if (!caps.at_least(2, 0)) api.UseProgram = nullptr;
    caps.fog_coord =
        (caps.at_least(1, 4) || caps.has_extension("GL_EXT_fog_coord")) && api.FogCoordPointer;
    if (!caps.fog_coord) api.FogCoordPointer = nullptr;
    caps.vertex_program = caps.has_extension("GL_ARB_vertex_program") && api.GenPrograms &&
                          api.DeletePrograms && api.BindProgram && api.ProgramString &&
                          api.GetProgramiv && api.ProgramLocalParameter4fv &&
                          api.ProgramEnvParameter4fv;
    if (!caps.vertex_program) {
        api.GenPrograms = nullptr;
        api.DeletePrograms = nullptr;
        api.BindProgram = nullptr;
        api.ProgramString = nullptr;
        api.GetProgramiv = nullptr;
        api.ProgramLocalParameter4fv = nullptr;
        api.ProgramEnvParameter4fv = nullptr;
        api.GetProgramLocalParameterfv = nullptr;
        api.GetProgramEnvParameterfv = nullptr;
    }
    caps.framebuffer_object =
        (caps.at_least(3, 0) || caps.has_extension("GL_ARB_framebuffer_object") ||
         caps.has_extension("GL_EXT_framebuffer_object")) &&
        api.GenFramebuffers && api.DeleteFramebuffers && api.BindFramebuffer &&
        api.GenRenderbuffers && api.DeleteRenderbuffers && api.BindRenderbuffer &&
        api.RenderbufferStorage && api.FramebufferRenderbuffer && api.CheckFramebufferStatus;
    caps.max_texture_units = 1;
    if (caps.multitexture) {
        GLint units = 1;
        api.GetIntegerv(GL_MAX_TEXTURE_UNITS, &units);
        caps.max_texture_units = units > 0 ? units : 1;
    }
    return api;
}

std::string gl_error_name(GLenum error) {
    switch (error) {
        case GL_NO_ERROR:
            return "GL_NO_ERROR";
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_STACK_OVERFLOW:
            return "GL_STACK_OVERFLOW";
        case GL_STACK_UNDERFLOW:
            return "GL_STACK_UNDERFLOW";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        default:
            break;
    }
    char text[16];
    std::snprintf(text, sizeof text, "0x%04X", static_cast<unsigned>(error));
    return text;
}

}  // namespace aerial::gl
