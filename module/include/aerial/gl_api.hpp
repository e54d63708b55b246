// aerial/gl_api.hpp — the OpenGL entry points the module calls, resolved at run time through
// the engine's own GetProcAddress. The module never links libGL: an application that links
// both libGL and libOSMesa gets NULL from glGetString, so the application chooses where GL comes
// from and hands the module a loader.
//
// How to use this:
//   1. With the engine's context current, once:
//        auto api = aerial::gl::load_api(
//            [](void*, const char* name) { return (void*)OSMesaGetProcAddress(name); }, nullptr);
//      (or eglGetProcAddress, glXGetProcAddressARB, wglGetProcAddress plus GetProcAddress on
//      opengl32.dll for the GL 1.1 functions, SDL_GL_GetProcAddress, ...).
//   2. `api->caps` says what the context offers (version, extensions the module can use);
//      the fixed-function and ARB layers (aerial/gl.hpp) choose their path from it.
//   3. Keep the Api while the context lives; it belongs to that context (function pointers may
//      differ between contexts on some platforms).
//
// This header includes <GL/gl.h> and <GL/glext.h> for the function-pointer types. The rest of
// aerial::gl's interface (aerial/gl.hpp) does not, so an engine using GLEW or its own loader
// includes only that one.
#pragma once

#include <GL/gl.h>
#include <GL/glext.h>

#include <string>
#include <string_view>

#include "aerial/error.hpp"

namespace aerial::gl {

/// Resolves one GL entry point by name ("glEnable", "glProgramStringARB", ...); returns null
/// when it does not know the name. `user` is passed through.
using LoadFunction = void* (*)(void* user, const char* name);

/// What a context offers, read from GL_VERSION and the extension string. A feature counts only
/// when the version or the extension string says so AND its entry points resolved (drivers may
/// return non-null pointers for anything; a name missing from the string is not offered).
struct Caps {
    int version_major = 0;
    int version_minor = 0;
    std::string vendor;      ///< GL_VENDOR
    std::string renderer;    ///< GL_RENDERER ("llvmpipe (LLVM 15.0.6, 256 bits)", ...)
    std::string version;     ///< GL_VERSION
    std::string extensions;  ///< the extension string, space separated

    bool multitexture = false;         ///< GL 1.3 or ARB_multitexture
    bool texture_3d = false;           ///< GL 1.2 or EXT_texture3D
    bool texture_env_combine = false;  ///< GL 1.3, ARB_ or EXT_texture_env_combine
    bool secondary_color = false;      ///< GL 1.4 or EXT_secondary_color (+ COLOR_SUM)
    bool fog_coord = false;            ///< GL 1.4 or EXT_fog_coord
    bool vertex_program = false;       ///< ARB_vertex_program
    bool framebuffer_object = false;   ///< GL 3.0, ARB_ or EXT_framebuffer_object
    /// GL 1.5 or ARB_vertex_buffer_object: arrays may come from buffer objects, so the module
    /// binds buffer 0 while it points arrays at client memory, and restores the binding.
    bool vertex_buffer_object = false;
    bool pixel_buffer_object = false;  ///< GL 2.1 or ARB_pixel_buffer_object (PIXEL_UNPACK_BUFFER)
    bool fragment_program = false;     ///< ARB_fragment_program (disabled while the module draws)
    int max_texture_units = 1;         ///< MAX_TEXTURE_UNITS (1 without multitexture)

    /// True when `name` is a whole word of the extension string.
    bool has_extension(std::string_view name) const;
    /// True when the context is at least version major.minor.
    bool at_least(int major, int minor) const;
};

// X(type, member, "name", "alternative name or empty") — every entry point the module calls.
// The member is the name without its "gl" prefix; the shorthands below spell each name once:
//   AERIAL_GL_11(X, Member)                    GL 1.1: "glMember", its type from <GL/gl.h>
//   AERIAL_GL_OR_EXT(X, TYPE, Member, SUFFIX)  "glMember", else the extension's "glMemberSUFFIX"
//   AERIAL_GL_EXT(X, TYPE, Member, SUFFIX)     only the extension's "glMemberSUFFIX"
// The first list is GL 1.1 (required); the second is optional and null when not offered.
#define AERIAL_GL_11(X, member) X(decltype(&::gl##member), member, "gl" #member, "")
#define AERIAL_GL_OR_EXT(X, type, member, suffix) \
    X(type, member, "gl" #member, "gl" #member #suffix)
#define AERIAL_GL_EXT(X, type, member, suffix) X(type, member, "gl" #member #suffix, "")

#define AERIAL_GL_REQUIRED_FUNCTIONS(X) \
    AERIAL_GL_11(X, GetString)          \
    AERIAL_GL_11(X, GetError)           \
    AERIAL_GL_11(X, GetIntegerv)        \
    AERIAL_GL_11(X, GetFloatv)          \
    AERIAL_GL_11(X, GetBooleanv)        \
    AERIAL_GL_11(X, GetPointerv)        \
    AERIAL_GL_11(X, IsEnabled)          \
    AERIAL_GL_11(X, Enable)             \
    AERIAL_GL_11(X, Disable)            \
    AERIAL_GL_11(X, EnableClientState)  \
    AERIAL_GL_11(X, DisableClientState) \
    AERIAL_GL_11(X, VertexPointer)      \
    AERIAL_GL_11(X, NormalPointer)      \
    AERIAL_GL_11(X, ColorPointer)       \
    AERIAL_GL_11(X, TexCoordPointer)    \
    AERIAL_GL_11(X, DrawArrays)         \
    AERIAL_GL_11(X, DrawElements)       \
    AERIAL_GL_11(X, BlendFunc)          \
    AERIAL_GL_11(X, DepthFunc)          \
    AERIAL_GL_11(X, DepthMask)          \
    AERIAL_GL_11(X, CullFace)           \
    AERIAL_GL_11(X, ColorMask)          \
    AERIAL_GL_11(X, ShadeModel)         \
    AERIAL_GL_11(X, ColorMaterial)      \
    AERIAL_GL_11(X, Materialfv)         \
    AERIAL_GL_11(X, GetMaterialfv)      \
    AERIAL_GL_11(X, Fogf)               \
    AERIAL_GL_11(X, Fogi)               \
    AERIAL_GL_11(X, Fogfv)              \
    AERIAL_GL_11(X, TexEnvi)            \
    AERIAL_GL_11(X, TexEnvf)            \
    AERIAL_GL_11(X, TexEnvfv)           \
    AERIAL_GL_11(X, GetTexEnviv)        \
    AERIAL_GL_11(X, GetTexEnvfv)        \
    AERIAL_GL_11(X, GenTextures)        \
    AERIAL_GL_11(X, DeleteTextures)     \
    AERIAL_GL_11(X, BindTexture)        \
    AERIAL_GL_11(X, TexImage1D)         \
    AERIAL_GL_11(X, TexImage2D)         \
    AERIAL_GL_11(X, TexParameteri)      \
    AERIAL_GL_11(X, PixelStorei)        \
    AERIAL_GL_11(X, ReadPixels)         \
    AERIAL_GL_11(X, Viewport)           \
    AERIAL_GL_11(X, Scissor)            \
    AERIAL_GL_11(X, Clear)              \
    AERIAL_GL_11(X, ClearColor)         \
    AERIAL_GL_11(X, MatrixMode)         \
    AERIAL_GL_11(X, LoadMatrixf)        \
    AERIAL_GL_11(X, LoadIdentity)       \
    AERIAL_GL_11(X, PushMatrix)         \
    AERIAL_GL_11(X, PopMatrix)          \
    AERIAL_GL_11(X, Color4f)            \
    AERIAL_GL_11(X, Begin)              \
    AERIAL_GL_11(X, End)                \
    AERIAL_GL_11(X, Vertex3f)           \
    AERIAL_GL_11(X, TexCoord2f)         \
    AERIAL_GL_11(X, TexCoord3f)         \
    AERIAL_GL_11(X, TexCoord4f)         \
    AERIAL_GL_11(X, TexParameterf)      \
    AERIAL_GL_11(X, Finish)

#define AERIAL_GL_OPTIONAL_FUNCTIONS(X)                                                       \
    AERIAL_GL_OR_EXT(X, PFNGLACTIVETEXTUREPROC, ActiveTexture, ARB)                           \
    AERIAL_GL_OR_EXT(X, PFNGLCLIENTACTIVETEXTUREARBPROC, ClientActiveTexture, ARB)            \
    AERIAL_GL_OR_EXT(X, PFNGLTEXIMAGE3DPROC, TexImage3D, EXT)                                 \
    AERIAL_GL_OR_EXT(X, PFNGLSECONDARYCOLORPOINTEREXTPROC, SecondaryColorPointer, EXT)        \
    AERIAL_GL_OR_EXT(X, PFNGLFOGCOORDPOINTEREXTPROC, FogCoordPointer, EXT)                    \
    AERIAL_GL_OR_EXT(X, PFNGLSECONDARYCOLOR3FEXTPROC, SecondaryColor3f, EXT)                  \
    AERIAL_GL_OR_EXT(X, PFNGLMULTITEXCOORD4FARBPROC, MultiTexCoord4f, ARB)                    \
    AERIAL_GL_OR_EXT(X, PFNGLBINDBUFFERARBPROC, BindBuffer, ARB)                              \
    AERIAL_GL_OR_EXT(X, PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate, EXT)                   \
    AERIAL_GL_OR_EXT(X, PFNGLBLENDEQUATIONPROC, BlendEquation, EXT)                           \
    AERIAL_GL_OR_EXT(X, PFNGLBLENDEQUATIONSEPARATEPROC, BlendEquationSeparate, EXT)           \
    X(PFNGLUSEPROGRAMPROC, UseProgram, "glUseProgram", "")                                    \
    AERIAL_GL_EXT(X, PFNGLGENPROGRAMSARBPROC, GenPrograms, ARB)                               \
    AERIAL_GL_EXT(X, PFNGLDELETEPROGRAMSARBPROC, DeletePrograms, ARB)                         \
    AERIAL_GL_EXT(X, PFNGLBINDPROGRAMARBPROC, BindProgram, ARB)                               \
    AERIAL_GL_EXT(X, PFNGLPROGRAMSTRINGARBPROC, ProgramString, ARB)                           \
    AERIAL_GL_EXT(X, PFNGLGETPROGRAMIVARBPROC, GetProgramiv, ARB)                             \
    AERIAL_GL_EXT(X, PFNGLPROGRAMLOCALPARAMETER4FVARBPROC, ProgramLocalParameter4fv, ARB)     \
    AERIAL_GL_EXT(X, PFNGLPROGRAMENVPARAMETER4FVARBPROC, ProgramEnvParameter4fv, ARB)         \
    AERIAL_GL_EXT(X, PFNGLGETPROGRAMLOCALPARAMETERFVARBPROC, GetProgramLocalParameterfv, ARB) \
    AERIAL_GL_EXT(X, PFNGLGETPROGRAMENVPARAMETERFVARBPROC, GetProgramEnvParameterfv, ARB)     \
    AERIAL_GL_OR_EXT(X, PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers, EXT)                       \
    AERIAL_GL_OR_EXT(X, PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers, EXT)                 \
    AERIAL_GL_OR_EXT(X, PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer, EXT)                       \
    AERIAL_GL_OR_EXT(X, PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers, EXT)                     \
    AERIAL_GL_OR_EXT(X, PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers, EXT)               \
    AERIAL_GL_OR_EXT(X, PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer, EXT)                     \
    AERIAL_GL_OR_EXT(X, PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage, EXT)               \
    AERIAL_GL_OR_EXT(X, PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer, EXT)       \
    AERIAL_GL_OR_EXT(X, PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus, EXT)

/// The resolved entry points of one context, named without the `gl` prefix
/// (`api.Enable(GL_FOG)`), and what the context offers.
struct Api {
#define AERIAL_GL_MEMBER(type, member, name, alternative) type member = nullptr;
    AERIAL_GL_REQUIRED_FUNCTIONS(AERIAL_GL_MEMBER)
    AERIAL_GL_OPTIONAL_FUNCTIONS(AERIAL_GL_MEMBER)
#undef AERIAL_GL_MEMBER
    Caps caps;
};

/// Resolves every entry point and reads the capabilities. Needs a current context. Errors:
/// field "load" when `load` is null; "glGetString" when GL_VERSION is NULL (no current context,
/// or libGL's dispatch used with an OSMesa context); the name of a missing GL 1.1 function.
Result<Api> load_api(LoadFunction load, void* user = nullptr);

/// The text of a GL error code ("GL_INVALID_OPERATION", ...; "0x…" for others).
std::string gl_error_name(GLenum error);

}  // namespace aerial::gl
