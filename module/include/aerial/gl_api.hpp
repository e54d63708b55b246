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
// The first block is GL 1.1 (required); the second is optional and null when not offered.
#define AERIAL_GL_REQUIRED_FUNCTIONS(X)                                                  \
    X(decltype(&::glGetString), GetString, "glGetString", "")                            \
    X(decltype(&::glGetError), GetError, "glGetError", "")                               \
    X(decltype(&::glGetIntegerv), GetIntegerv, "glGetIntegerv", "")                      \
    X(decltype(&::glGetFloatv), GetFloatv, "glGetFloatv", "")                            \
    X(decltype(&::glGetBooleanv), GetBooleanv, "glGetBooleanv", "")                      \
    X(decltype(&::glGetPointerv), GetPointerv, "glGetPointerv", "")                      \
    X(decltype(&::glIsEnabled), IsEnabled, "glIsEnabled", "")                            \
    X(decltype(&::glEnable), Enable, "glEnable", "")                                     \
    X(decltype(&::glDisable), Disable, "glDisable", "")                                  \
    X(decltype(&::glEnableClientState), EnableClientState, "glEnableClientState", "")    \
    X(decltype(&::glDisableClientState), DisableClientState, "glDisableClientState", "") \
    X(decltype(&::glVertexPointer), VertexPointer, "glVertexPointer", "")                \
    X(decltype(&::glNormalPointer), NormalPointer, "glNormalPointer", "")                \
    X(decltype(&::glColorPointer), ColorPointer, "glColorPointer", "")                   \
    X(decltype(&::glTexCoordPointer), TexCoordPointer, "glTexCoordPointer", "")          \
    X(decltype(&::glDrawArrays), DrawArrays, "glDrawArrays", "")                         \
    X(decltype(&::glDrawElements), DrawElements, "glDrawElements", "")                   \
    X(decltype(&::glBlendFunc), BlendFunc, "glBlendFunc", "")                            \
    X(decltype(&::glDepthFunc), DepthFunc, "glDepthFunc", "")                            \
    X(decltype(&::glDepthMask), DepthMask, "glDepthMask", "")                            \
    X(decltype(&::glColorMask), ColorMask, "glColorMask", "")                            \
    X(decltype(&::glShadeModel), ShadeModel, "glShadeModel", "")                         \
    X(decltype(&::glColorMaterial), ColorMaterial, "glColorMaterial", "")                \
    X(decltype(&::glMaterialfv), Materialfv, "glMaterialfv", "")                         \
    X(decltype(&::glGetMaterialfv), GetMaterialfv, "glGetMaterialfv", "")                \
    X(decltype(&::glFogf), Fogf, "glFogf", "")                                           \
    X(decltype(&::glFogi), Fogi, "glFogi", "")                                           \
    X(decltype(&::glFogfv), Fogfv, "glFogfv", "")                                        \
    X(decltype(&::glTexEnvi), TexEnvi, "glTexEnvi", "")                                  \
    X(decltype(&::glTexEnvf), TexEnvf, "glTexEnvf", "")                                  \
    X(decltype(&::glTexEnvfv), TexEnvfv, "glTexEnvfv", "")                               \
    X(decltype(&::glGetTexEnviv), GetTexEnviv, "glGetTexEnviv", "")                      \
    X(decltype(&::glGetTexEnvfv), GetTexEnvfv, "glGetTexEnvfv", "")                      \
    X(decltype(&::glGenTextures), GenTextures, "glGenTextures", "")                      \
    X(decltype(&::glDeleteTextures), DeleteTextures, "glDeleteTextures", "")             \
    X(decltype(&::glBindTexture), BindTexture, "glBindTexture", "")                      \
    X(decltype(&::glTexImage1D), TexImage1D, "glTexImage1D", "")                         \
    X(decltype(&::glTexImage2D), TexImage2D, "glTexImage2D", "")                         \
    X(decltype(&::glTexParameteri), TexParameteri, "glTexParameteri", "")                \
    X(decltype(&::glPixelStorei), PixelStorei, "glPixelStorei", "")                      \
    X(decltype(&::glReadPixels), ReadPixels, "glReadPixels", "")                         \
    X(decltype(&::glViewport), Viewport, "glViewport", "")                               \
    X(decltype(&::glScissor), Scissor, "glScissor", "")                                  \
    X(decltype(&::glClear), Clear, "glClear", "")                                        \
    X(decltype(&::glClearColor), ClearColor, "glClearColor", "")                         \
    X(decltype(&::glMatrixMode), MatrixMode, "glMatrixMode", "")                         \
    X(decltype(&::glLoadMatrixf), LoadMatrixf, "glLoadMatrixf", "")                      \
    X(decltype(&::glLoadIdentity), LoadIdentity, "glLoadIdentity", "")                   \
    X(decltype(&::glPushMatrix), PushMatrix, "glPushMatrix", "")                         \
    X(decltype(&::glPopMatrix), PopMatrix, "glPopMatrix", "")                            \
    X(decltype(&::glColor4f), Color4f, "glColor4f", "")                                  \
    X(decltype(&::glBegin), Begin, "glBegin", "")                                        \
    X(decltype(&::glEnd), End, "glEnd", "")                                              \
    X(decltype(&::glVertex3f), Vertex3f, "glVertex3f", "")                               \
    X(decltype(&::glTexCoord2f), TexCoord2f, "glTexCoord2f", "")                         \
    X(decltype(&::glTexCoord3f), TexCoord3f, "glTexCoord3f", "")                         \
    X(decltype(&::glTexCoord4f), TexCoord4f, "glTexCoord4f", "")                         \
    X(decltype(&::glTexParameterf), TexParameterf, "glTexParameterf", "")                \
    X(decltype(&::glFinish), Finish, "glFinish", "")

#define AERIAL_GL_OPTIONAL_FUNCTIONS(X)                                                           \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture, "glActiveTexture", "glActiveTextureARB")             \
    X(PFNGLCLIENTACTIVETEXTUREARBPROC, ClientActiveTexture, "glClientActiveTexture",              \
      "glClientActiveTextureARB")                                                                 \
    X(PFNGLTEXIMAGE3DPROC, TexImage3D, "glTexImage3D", "glTexImage3DEXT")                         \
    X(PFNGLSECONDARYCOLORPOINTEREXTPROC, SecondaryColorPointer, "glSecondaryColorPointer",        \
      "glSecondaryColorPointerEXT")                                                               \
    X(PFNGLFOGCOORDPOINTEREXTPROC, FogCoordPointer, "glFogCoordPointer", "glFogCoordPointerEXT")  \
    X(PFNGLSECONDARYCOLOR3FEXTPROC, SecondaryColor3f, "glSecondaryColor3f",                       \
      "glSecondaryColor3fEXT")                                                                    \
    X(PFNGLMULTITEXCOORD4FARBPROC, MultiTexCoord4f, "glMultiTexCoord4f", "glMultiTexCoord4fARB")  \
    X(PFNGLBINDBUFFERARBPROC, BindBuffer, "glBindBuffer", "glBindBufferARB")                      \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate, "glBlendFuncSeparate",                       \
      "glBlendFuncSeparateEXT")                                                                   \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation, "glBlendEquation", "glBlendEquationEXT")             \
    X(PFNGLBLENDEQUATIONSEPARATEPROC, BlendEquationSeparate, "glBlendEquationSeparate",           \
      "glBlendEquationSeparateEXT")                                                               \
    X(PFNGLUSEPROGRAMPROC, UseProgram, "glUseProgram", "")                                        \
    X(PFNGLGENPROGRAMSARBPROC, GenPrograms, "glGenProgramsARB", "")                               \
    X(PFNGLDELETEPROGRAMSARBPROC, DeletePrograms, "glDeleteProgramsARB", "")                      \
    X(PFNGLBINDPROGRAMARBPROC, BindProgram, "glBindProgramARB", "")                               \
    X(PFNGLPROGRAMSTRINGARBPROC, ProgramString, "glProgramStringARB", "")                         \
    X(PFNGLGETPROGRAMIVARBPROC, GetProgramiv, "glGetProgramivARB", "")                            \
    X(PFNGLPROGRAMLOCALPARAMETER4FVARBPROC, ProgramLocalParameter4fv,                             \
      "glProgramLocalParameter4fvARB", "")                                                        \
    X(PFNGLPROGRAMENVPARAMETER4FVARBPROC, ProgramEnvParameter4fv, "glProgramEnvParameter4fvARB",  \
      "")                                                                                         \
    X(PFNGLGETPROGRAMLOCALPARAMETERFVARBPROC, GetProgramLocalParameterfv,                         \
      "glGetProgramLocalParameterfvARB", "")                                                      \
    X(PFNGLGETPROGRAMENVPARAMETERFVARBPROC, GetProgramEnvParameterfv,                             \
      "glGetProgramEnvParameterfvARB", "")                                                        \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers, "glGenFramebuffers", "glGenFramebuffersEXT")     \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers, "glDeleteFramebuffers",                    \
      "glDeleteFramebuffersEXT")                                                                  \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer, "glBindFramebuffer", "glBindFramebufferEXT")     \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers, "glGenRenderbuffers", "glGenRenderbuffersEXT") \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers, "glDeleteRenderbuffers",                 \
      "glDeleteRenderbuffersEXT")                                                                 \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer, "glBindRenderbuffer", "glBindRenderbufferEXT") \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage, "glRenderbufferStorage",                 \
      "glRenderbufferStorageEXT")                                                                 \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer, "glFramebufferRenderbuffer",     \
      "glFramebufferRenderbufferEXT")                                                             \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus, "glCheckFramebufferStatus",        \
      "glCheckFramebufferStatusEXT")

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
