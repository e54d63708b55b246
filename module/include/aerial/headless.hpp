// aerial/headless.hpp — an off-screen OpenGL context for tools, tests and users' regression
// suites: OSMesa, or EGL surfaceless rendering into a framebuffer object. Target
// `aerial::headless`, separate from the module proper: an engine never needs it (the module
// never creates or owns the engine's context).
//
// How to use this:
//   1. `auto ctx = aerial::headless::Context::create({aerial::headless::Platform::osmesa, 640,
//      480});` — on failure the error says what is missing (library, extension, config).
//   2. The context is current on the calling thread after create(); `ctx->api()` holds the GL
//      entry points (resolved through OSMesaGetProcAddress or eglGetProcAddress, never by
//      linking libGL: an OSMesa binary linked with libGL gets NULL from glGetString).
//   3. Render with the default framebuffer bound (OSMesa's buffer, or the FBO under EGL), then
//      `ctx->read_rgba8()` gives the image, top row first.
//
// libOSMesa and libEGL are opened at run time (dlopen), so a binary that uses only one of them
// runs where the other is not installed, and a missing one is a clear error, not a link failure.
// Pin LP_NUM_THREADS and choose llvmpipe or softpipe with GALLIUM_DRIVER as usual with Mesa.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "aerial/error.hpp"
#include "aerial/gl_api.hpp"

namespace aerial::headless {

/// Where the context comes from.
enum class Platform {
    osmesa,  ///< Mesa's off-screen renderer (libOSMesa.so.8), renders into memory
    egl,     ///< EGL on Mesa's surfaceless platform (EGL_MESA_platform_surfaceless) into an FBO
};

/// "osmesa" or "egl".
const char* platform_name(Platform platform);
/// Parses "osmesa" or "egl"; nullopt for anything else.
std::optional<Platform> parse_platform(std::string_view name);

/// The driver a GL_RENDERER string names: its first word ("llvmpipe" for "llvmpipe (LLVM 15.0.6,
/// 256 bits)", "zink" for "zink (llvmpipe (LLVM 15.0.6, 256 bits))", "softpipe"), lower case.
std::string renderer_driver(std::string_view renderer);

struct ContextOptions {
    Platform platform = Platform::osmesa;
    int width = 256;   ///< pixels, 1 .. 8192
    int height = 256;  ///< pixels, 1 .. 8192
};

/// An off-screen compatibility-profile context with a colour (RGBA8) and depth (24 bit) buffer
/// of the requested size. Move-only; destroying it destroys the context.
class Context {
  public:
    /// Creates the context and makes it current. Errors name the field ("width", "height") or
    /// the step that failed ("libOSMesa", "libEGL", "eglInitialize", "framebuffer", ...).
    static Result<Context> create(const ContextOptions& options);

    Context(Context&&) noexcept;
    Context& operator=(Context&&) noexcept;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    ~Context();

    /// Makes this context current on the calling thread (create() already did).
    std::optional<Error> make_current();

    const gl::Api& api() const;
    /// The loader this context resolves GL entry points with (for an engine's own loader).
    gl::LoadFunction loader() const;
    void* loader_user() const;

    Platform platform() const;
    int width() const;
    int height() const;

    /// The colour buffer as RGBA8, width × height × 4 bytes, top row first.
    std::vector<std::uint8_t> read_rgba8() const;

  private:
    struct Impl;
    explicit Context(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace aerial::headless
