// Off-screen contexts (aerial/headless.hpp): OSMesa and EGL surfaceless, both opened with dlopen.
#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "aerial/headless.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>
#include <dlfcn.h>
#include <link.h>

#include <cctype>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace aerial::headless {

constexpr aerial::detail::NameTable<Platform, 2> kPlatformNames{
    {{Platform::osmesa, "osmesa"}, {Platform::egl, "egl"}}};

const char* platform_name(Platform platform) {
    return aerial::detail::name_in(kPlatformNames, platform);
}

std::optional<Platform> parse_platform(std::string_view name) {
    return aerial::detail::find_in(kPlatformNames, name);
}

namespace {

constexpr int kMaxSize = 8192;
constexpr const char* kCreate = "headless::Context::create";

// The Gallium drivers Mesa's OSMesa renders with: its software winsys creates only these, and
// OSMesaCreateContextAttribs dereferences a null screen for any other GALLIUM_DRIVER (zink, a
// typo), killing the process. Refused here instead, as "not supported".
constexpr const char* kOsmesaDrivers[] = {"llvmpipe", "softpipe"};

std::optional<Error> osmesa_driver_unsupported() {
    const char* driver = std::getenv("GALLIUM_DRIVER");
    if (driver == nullptr || driver[0] == '\0') return std::nullopt;
    for (const char* known : kOsmesaDrivers) {
        if (std::strcmp(driver, known) == 0) return std::nullopt;
    }
    return aerial::detail::unsupported(kCreate, "GALLIUM_DRIVER",
                                       std::string("OSMesa renders with llvmpipe or softpipe, "
                                                   "got '") +
                                           driver + "' (use the egl platform for other drivers)");
}

/// Keeps the Mesa drivers that eglInitialize loaded (the DRI driver under .../dri/ and the gallium
/// library) mapped after eglTerminate, as OSMesa is (RTLD_NODELETE): Mesa's drivers are not built
/// to be unloaded, and an unloaded library's allocations lose their stack frames, so that
/// LeakSanitizer could no longer tell Mesa's own leaks (suppressed) from the module's.
void keep_mesa_drivers_loaded() {
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void*) {
            const char* path = info->dlpi_name;
            if (path != nullptr &&
                (std::strstr(path, "/dri/") || std::strstr(path, "libgallium"))) {
                // Already loaded: RTLD_NOLOAD only marks it; the handle is released at once and
                // the library stays.
                if (void* handle = dlopen(path, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE)) {
                    dlclose(handle);
                }
            }
            return 0;
        },
        nullptr);
}

// The OSMesa entry points the context uses (libOSMesa.so.8).
struct OsmesaLibrary {
    void* handle = nullptr;
    OSMesaContext (*CreateContextAttribs)(const int*, OSMesaContext) = nullptr;
    GLboolean (*MakeCurrent)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
    void (*DestroyContext)(OSMesaContext) = nullptr;
    OSMESAproc (*GetProcAddress)(const char*) = nullptr;
};

// The EGL entry points the context uses (libEGL.so.1).
struct EglLibrary {
    void* handle = nullptr;
    PFNEGLGETPROCADDRESSPROC GetProcAddress = nullptr;
    PFNEGLQUERYSTRINGPROC QueryString = nullptr;
    PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplay = nullptr;
    PFNEGLINITIALIZEPROC Initialize = nullptr;
    PFNEGLTERMINATEPROC Terminate = nullptr;
    PFNEGLBINDAPIPROC BindAPI = nullptr;
    PFNEGLCHOOSECONFIGPROC ChooseConfig = nullptr;
    PFNEGLCREATECONTEXTPROC CreateContext = nullptr;
    PFNEGLDESTROYCONTEXTPROC DestroyContext = nullptr;
    PFNEGLMAKECURRENTPROC MakeCurrent = nullptr;
    PFNEGLGETERRORPROC GetError = nullptr;
};

template <class F>
bool load_symbol(void* handle, const char* name, F& out) {
    out = reinterpret_cast<F>(dlsym(handle, name));
    return out != nullptr;
}

void* osmesa_loader(void* user, const char* name) {
    auto* lib = static_cast<OsmesaLibrary*>(user);
    return reinterpret_cast<void*>(lib->GetProcAddress(name));
}

void* egl_loader(void* user, const char* name) {
    auto* lib = static_cast<EglLibrary*>(user);
    return reinterpret_cast<void*>(lib->GetProcAddress(name));
}

std::string egl_error_text(EGLint code) {
    char text[32];
    std::snprintf(text, sizeof text, "EGL error 0x%04X", static_cast<unsigned>(code));
    return text;
}

}  // namespace

struct Context::Impl {
    Platform platform = Platform::osmesa;
    int width = 0;
    int height = 0;
    gl::Api api;

    // OSMesa
    OsmesaLibrary osmesa;
    OSMesaContext osmesa_context = nullptr;
    std::vector<std::uint8_t> osmesa_buffer;

    // EGL
    EglLibrary egl;
    EGLDisplay egl_display = EGL_NO_DISPLAY;
    EGLContext egl_context = EGL_NO_CONTEXT;
    GLuint framebuffer = 0;
    GLuint renderbuffers[2] = {0, 0};

    ~Impl() {
        if (platform == Platform::osmesa) {
            if (osmesa_context) osmesa.DestroyContext(osmesa_context);
            if (osmesa.handle) dlclose(osmesa.handle);
            return;
        }
        if (egl_context != EGL_NO_CONTEXT) {
            if (egl.MakeCurrent(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context) &&
                framebuffer != 0) {
                api.BindFramebuffer(GL_FRAMEBUFFER, 0);
                api.DeleteFramebuffers(1, &framebuffer);
                api.DeleteRenderbuffers(2, renderbuffers);
            }
            egl.MakeCurrent(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            egl.DestroyContext(egl_display, egl_context);
        }
        if (egl_display != EGL_NO_DISPLAY) egl.Terminate(egl_display);
        // libEGL is left loaded: Mesa's EGL driver registers thread-exit handlers that must
        // outlive the context, and unloading it is not safe while other contexts may exist.
    }

    std::optional<Error> make_current() {
        if (platform == Platform::osmesa) {
            if (!osmesa.MakeCurrent(osmesa_context, osmesa_buffer.data(), GL_UNSIGNED_BYTE, width,
                                    height)) {
                return aerial::detail::unsupported(kCreate, "OSMesaMakeCurrent", "failed");
            }
            return std::nullopt;
        }
        if (!egl.MakeCurrent(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context)) {
            return aerial::detail::unsupported(kCreate, "eglMakeCurrent",
                                               "failed (" + egl_error_text(egl.GetError()) + ")");
        }
        if (framebuffer != 0) api.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        return std::nullopt;
    }

    std::optional<Error> create_osmesa() {
        if (auto e = osmesa_driver_unsupported()) return e;
        // RTLD_NODELETE: dlclose leaves Mesa mapped. Mesa's drivers are not built to be
        // unloaded, and an unloaded library's allocations lose their stack frames, so that
        // LeakSanitizer could no longer tell Mesa's own leaks (suppressed) from the module's.
        constexpr int kFlags = RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE;
        osmesa.handle = dlopen("libOSMesa.so.8", kFlags);
        if (!osmesa.handle) osmesa.handle = dlopen("libOSMesa.so", kFlags);
        if (!osmesa.handle) {
            return aerial::detail::unsupported(
                kCreate, "libOSMesa", "cannot open libOSMesa.so.8 (install Debian's libosmesa6)");
        }
        if (!load_symbol(osmesa.handle, "OSMesaCreateContextAttribs",
                         osmesa.CreateContextAttribs) ||
            !load_symbol(osmesa.handle, "OSMesaMakeCurrent", osmesa.MakeCurrent) ||
            !load_symbol(osmesa.handle, "OSMesaDestroyContext", osmesa.DestroyContext) ||
            !load_symbol(osmesa.handle, "OSMesaGetProcAddress", osmesa.GetProcAddress)) {
            return aerial::detail::unsupported(kCreate, "libOSMesa",
                                               "missing OSMesa 11.2 entry points");
        }
        const int attributes[] = {OSMESA_FORMAT,
                                  OSMESA_RGBA,
                                  OSMESA_DEPTH_BITS,
                                  24,
                                  OSMESA_STENCIL_BITS,
                                  8,
                                  OSMESA_PROFILE,
                                  OSMESA_COMPAT_PROFILE,
                                  0};
        osmesa_context = osmesa.CreateContextAttribs(attributes, nullptr);
        if (!osmesa_context) {
            return aerial::detail::unsupported(kCreate, "OSMesaCreateContextAttribs",
                                               "no RGBA compatibility context");
        }
        osmesa_buffer.assign(static_cast<std::size_t>(width) * height * 4, 0);
        if (auto e = make_current()) return aerial::detail::from(kCreate, *e);
        auto loaded = gl::load_api(osmesa_loader, &osmesa);
        if (!loaded) return loaded.error();
        api = std::move(loaded.value());
        return std::nullopt;
    }

    std::optional<Error> create_egl() {
        egl.handle = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
        if (!egl.handle) {
            return aerial::detail::unsupported(kCreate, "libEGL",
                                               "cannot open libEGL.so.1 (install Debian's libegl1 "
                                               "and libegl-mesa0)");
        }
        if (!load_symbol(egl.handle, "eglGetProcAddress", egl.GetProcAddress) ||
            !load_symbol(egl.handle, "eglQueryString", egl.QueryString) ||
            !load_symbol(egl.handle, "eglInitialize", egl.Initialize) ||
            !load_symbol(egl.handle, "eglTerminate", egl.Terminate) ||
            !load_symbol(egl.handle, "eglBindAPI", egl.BindAPI) ||
            !load_symbol(egl.handle, "eglChooseConfig", egl.ChooseConfig) ||
            !load_symbol(egl.handle, "eglCreateContext", egl.CreateContext) ||
            !load_symbol(egl.handle, "eglDestroyContext", egl.DestroyContext) ||
            !load_symbol(egl.handle, "eglMakeCurrent", egl.MakeCurrent) ||
            !load_symbol(egl.handle, "eglGetError", egl.GetError)) {
            return aerial::detail::unsupported(kCreate, "libEGL", "missing EGL 1.4 entry points");
        }
        const char* client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (!client || !std::strstr(client, "EGL_MESA_platform_surfaceless")) {
            return aerial::detail::unsupported(kCreate, "EGL_MESA_platform_surfaceless",
                                               "not offered by libEGL (install "
                                               "Debian's libegl-mesa0)");
        }
        egl.GetPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
            egl.GetProcAddress("eglGetPlatformDisplayEXT"));
        if (!egl.GetPlatformDisplay) {
            return aerial::detail::unsupported(kCreate, "eglGetPlatformDisplayEXT", "not found");
        }
        egl_display =
            egl.GetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        EGLint major = 0, minor = 0;
        if (egl_display == EGL_NO_DISPLAY || !egl.Initialize(egl_display, &major, &minor)) {
            egl_display = EGL_NO_DISPLAY;
            return aerial::detail::unsupported(
                kCreate, "eglInitialize",
                "the surfaceless display failed (" + egl_error_text(egl.GetError()) + ")");
        }
        keep_mesa_drivers_loaded();
        const char* display_extensions = egl.QueryString(egl_display, EGL_EXTENSIONS);
        if (!display_extensions ||
            !std::strstr(display_extensions, "EGL_KHR_surfaceless_context")) {
            return aerial::detail::unsupported(kCreate, "EGL_KHR_surfaceless_context",
                                               "not offered by the display");
        }
        if (!egl.BindAPI(EGL_OPENGL_API)) {
            return aerial::detail::unsupported(kCreate, "eglBindAPI",
                                               "desktop OpenGL is not available");
        }
        const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                            0, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        if (!egl.ChooseConfig(egl_display, config_attributes, &config, 1, &count) || count < 1) {
            return aerial::detail::unsupported(kCreate, "eglChooseConfig",
                                               "no desktop OpenGL config");
        }
        // No attributes: a compatibility-profile context, which keeps the fixed pipeline.
        egl_context = egl.CreateContext(egl_display, config, EGL_NO_CONTEXT, nullptr);
        if (egl_context == EGL_NO_CONTEXT) {
            return aerial::detail::unsupported(kCreate, "eglCreateContext",
                                               "failed (" + egl_error_text(egl.GetError()) + ")");
        }
        if (auto e = make_current()) return aerial::detail::from(kCreate, *e);
        auto loaded = gl::load_api(egl_loader, &egl);
        if (!loaded) return loaded.error();
        api = std::move(loaded.value());
        if (!api.caps.framebuffer_object) {
            return aerial::detail::unsupported(kCreate, "framebuffer",
                                               "the EGL context has no framebuffer objects");
        }
        api.GenRenderbuffers(2, renderbuffers);
        api.BindRenderbuffer(GL_RENDERBUFFER, renderbuffers[0]);
        api.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
        api.BindRenderbuffer(GL_RENDERBUFFER, renderbuffers[1]);
        api.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
        api.BindRenderbuffer(GL_RENDERBUFFER, 0);
        api.GenFramebuffers(1, &framebuffer);
        api.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        api.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                    renderbuffers[0]);
        api.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                    renderbuffers[1]);
        api.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                    renderbuffers[1]);
        const GLenum status = api.CheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
            char text[96];
            std::snprintf(text, sizeof text, "incomplete (status 0x%04X)",
                          static_cast<unsigned>(status));
            return aerial::detail::unsupported(kCreate, "framebuffer", text);
        }
        api.Viewport(0, 0, width, height);
        return std::nullopt;
    }
};

std::string renderer_driver(std::string_view renderer) {
    std::string driver;
    for (char c : renderer) {
        if (c == ' ' || c == '(') break;
        driver += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return driver;
}

Context::Context(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;
Context::~Context() = default;

Result<Context> Context::create(const ContextOptions& options) {
    if (options.width < 1 || options.width > kMaxSize) {
        return aerial::detail::invalid(kCreate, "width", "1 .. 8192 pixels",
                                       aerial::detail::number(options.width));
    }
    if (options.height < 1 || options.height > kMaxSize) {
        return aerial::detail::invalid(kCreate, "height", "1 .. 8192 pixels",
                                       aerial::detail::number(options.height));
    }
    auto impl = std::make_unique<Impl>();
    impl->platform = options.platform;
    impl->width = options.width;
    impl->height = options.height;
    std::optional<Error> error =
        options.platform == Platform::osmesa ? impl->create_osmesa() : impl->create_egl();
    if (error) return *error;
    return Context(std::move(impl));
}

std::optional<Error> Context::make_current() {
    if (auto e = impl_->make_current()) {
        return aerial::detail::from("headless::Context::make_current", *e);
    }
    return std::nullopt;
}
const gl::Api& Context::api() const { return impl_->api; }
gl::LoadFunction Context::loader() const {
    return impl_->platform == Platform::osmesa ? osmesa_loader : egl_loader;
}
void* Context::loader_user() const {
    return impl_->platform == Platform::osmesa ? static_cast<void*>(&impl_->osmesa)
                                               : static_cast<void*>(&impl_->egl);
}
Platform Context::platform() const { return impl_->platform; }
int Context::width() const { return impl_->width; }
int Context::height() const { return impl_->height; }

std::vector<std::uint8_t> Context::read_rgba8() const {
    const gl::Api& gl = impl_->api;
    const std::size_t row = static_cast<std::size_t>(impl_->width) * 4;
    std::vector<std::uint8_t> bottom_up(row * impl_->height);
    GLint alignment = 4;
    gl.GetIntegerv(GL_PACK_ALIGNMENT, &alignment);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.Finish();
    gl.ReadPixels(0, 0, impl_->width, impl_->height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    gl.PixelStorei(GL_PACK_ALIGNMENT, alignment);
    std::vector<std::uint8_t> top_down(bottom_up.size());
    for (int y = 0; y < impl_->height; ++y) {
        std::memcpy(top_down.data() + row * y, bottom_up.data() + row * (impl_->height - 1 - y),
                    row);
    }
    return top_down;
}

}  // namespace aerial::headless
