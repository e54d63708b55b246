// Shared by the GL tests that draw: the context each CTest registration asks for
// (AERIAL_TEST_GL_BACKEND=osmesa|egl; GALLIUM_DRIVER and LP_NUM_THREADS come from CTest too), a
// fixture that makes it for every test, and image comparison in 8-bit steps.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "aerial/headless.hpp"

namespace aerial_test {

/// The platform CTest asks for in AERIAL_TEST_GL_BACKEND (osmesa when unset); a name that is
/// neither is an error, never a silent OSMesa.
inline aerial::Result<aerial::headless::Platform> platform_from_environment() {
    const char* name = std::getenv("AERIAL_TEST_GL_BACKEND");
    if (name == nullptr) return aerial::headless::Platform::osmesa;
    auto platform = aerial::headless::parse_platform(name);
    if (!platform) {
        return aerial::Error{"AERIAL_TEST_GL_BACKEND",
                             std::string("AERIAL_TEST_GL_BACKEND: "
                                         "expected osmesa or egl, got '") +
                                 name + "'"};
    }
    return *platform;
}

inline aerial::headless::Platform backend_from_environment() {
    auto platform = platform_from_environment();
    return platform ? *platform : aerial::headless::Platform::osmesa;
}

/// The exit status CTest reads as "not supported" (SKIP_RETURN_CODE of the GL registrations).
constexpr int kNotSupportedExit = 77;

/// Before any test: makes one context of the platform asked for. A platform or driver that
/// cannot give one ends the run as one "not supported" (exit 77, the reason on stderr) instead
/// of every test failing at set-up; a bad AERIAL_TEST_GL_BACKEND, or a renderer that is not the
/// GALLIUM_DRIVER asked for (a MESA_LOADER_DRIVER_OVERRIDE leaking in), fails the run.
class ContextProbe : public ::testing::Environment {
  public:
    void SetUp() override {
        auto platform = platform_from_environment();
        if (!platform) {
            std::fprintf(stderr, "%s\n", platform.error().message.c_str());
            std::exit(1);
        }
        auto ctx = aerial::headless::Context::create({*platform, 8, 8});
        if (!ctx) {
            const bool unsupported = ctx.error().kind == aerial::ErrorKind::not_supported;
            std::fprintf(stderr, "%s: %s: %s\n", unsupported ? "not supported" : "failed",
                         aerial::headless::platform_name(*platform), ctx.error().message.c_str());
            std::exit(unsupported ? kNotSupportedExit : 1);
        }
        const char* driver = std::getenv("GALLIUM_DRIVER");
        const std::string& renderer = ctx->api().caps.renderer;
        if (driver != nullptr && driver[0] != '\0' &&
            aerial::headless::renderer_driver(renderer) != driver) {
            std::fprintf(stderr,
                         "GALLIUM_DRIVER=%s asked for, but GL_RENDERER is '%s' (is "
                         "MESA_LOADER_DRIVER_OVERRIDE or LIBGL_ALWAYS_SOFTWARE set?)\n",
                         driver, renderer.c_str());
            std::exit(1);
        }
    }
};

inline const bool kContextProbeRegistered =
    (::testing::AddGlobalTestEnvironment(new ContextProbe), true);

/// "osmesa llvmpipe (LLVM 15.0.6, 256 bits)": what a figure was measured on.
inline std::string context_label(const aerial::headless::Context& ctx) {
    return std::string(aerial::headless::platform_name(ctx.platform())) + " " +
           ctx.api().caps.renderer;
}

/// The base of the fixtures whose tests draw: SetUp makes a Width x Height context of the backend
/// CTest asks for (the test fails when there is none) and records its renderer as the test's
/// GL_RENDERER property.
template <int Width, int Height>
class DrawingTest : public ::testing::Test {
  protected:
    void SetUp() override {
        auto ctx = aerial::headless::Context::create({backend_from_environment(), Width, Height});
        ASSERT_TRUE(ctx.ok()) << ctx.error().message;
        ctx_.emplace(std::move(ctx).value());
        RecordProperty("GL_RENDERER", ctx_->api().caps.renderer);
    }
    const aerial::gl::Api& gl() const { return ctx_->api(); }

    std::optional<aerial::headless::Context> ctx_;
};

/// The largest difference of any R, G or B channel between two RGBA8 images (alpha ignored),
/// and where it is.
struct ImageDifference {
    int max_lsb = 0;
    std::size_t pixel = 0;
    std::size_t over1 = 0;   ///< pixels off by more than 1 step
    std::size_t differ = 0;  ///< pixels that differ at all
};

inline ImageDifference compare_rgb(const std::vector<std::uint8_t>& a,
                                   const std::vector<std::uint8_t>& b) {
    ImageDifference d;
    const std::size_t n = std::min(a.size(), b.size()) / 4;
    for (std::size_t p = 0; p < n; ++p) {
        int worst = 0;
        for (std::size_t c = 0; c < 3; ++c) {
            worst = std::max(worst, std::abs(int(a[4 * p + c]) - int(b[4 * p + c])));
        }
        if (worst > 1) ++d.over1;
        if (worst > 0) ++d.differ;
        if (worst > d.max_lsb) {
            d.max_lsb = worst;
            d.pixel = p;
        }
    }
    return d;
}

inline std::string pixel_text(const std::vector<std::uint8_t>& image, std::size_t p) {
    char text[48];
    std::snprintf(text, sizeof text, "(%d, %d, %d)", image[4 * p], image[4 * p + 1],
                  image[4 * p + 2]);
    return text;
}

}  // namespace aerial_test
