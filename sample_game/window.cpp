// The interactive flight in a GLFW window (built when GLFW is found).
#include "aerial/gl_api.hpp"  // GL/gl.h and GL/glext.h first; GLFW includes no GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <iterator>

#include "game.hpp"
#include "support/png.hpp"

namespace sample {
namespace {

void* load_gl(void*, const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

const char* const kPresets[] = {"earth", "hazy", "foggy", "hp2002", "mars"};
/// T and G move the clock by an hour a second held.
constexpr double kHourKeyMinutesPerSecond = 60.0;

}  // namespace

bool window_available() { return true; }

int run_window(const World& world, GameConfig config, int frames, const std::string& screenshot) {
    if (!glfwInit()) {
        std::cerr << "aerial-sample: --window: GLFW could not start (no display?)\n";
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    GLFWwindow* window =
        glfwCreateWindow(config.width, config.height, "aerial sample", nullptr, nullptr);
    if (window == nullptr) {
        std::cerr << "aerial-sample: --window: no GL 2.1 window could be created\n";
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    int status = 0;
    {
        auto api = aerial::gl::load_api(load_gl, nullptr);
        if (!api) {
            std::cerr << "aerial-sample: --window: " << api.error().message << '\n';
            glfwDestroyWindow(window);
            glfwTerminate();
            return 1;
        }
        aerial::scene::RendererOptions options;
        options.backend = config.backend;
        options.path = config.path;
        auto renderer = aerial::scene::SceneRenderer::create(*api, options);
        if (!renderer) {
            std::cerr << "aerial-sample: --backend: " << renderer.error().message << '\n';
            glfwDestroyWindow(window);
            glfwTerminate();
            return 1;
        }
        auto sky = install_sky(renderer.value(), *api, config);
        if (!sky) {
            std::cerr << "aerial-sample: --sky: " << sky.error().message << '\n';
            glfwDestroyWindow(window);
            glfwTerminate();
            return 1;
        }
        config.sky = sky->used;
        GameRenderer game{std::move(renderer).value(), *sky};
        FlightState state = flight_at(world, 0.0, config.sun);
        double speed = 100.0;  // m/s
        double utc_min = state.utc_min;
        std::size_t time_step = 0;  // into kTimeFactors
        auto last = std::chrono::steady_clock::now();
        std::printf(
            "aerial-sample: keys: arrows turn/climb, W/S speed, T/G an hour back/on, ] [ time "
            "faster/slower, F fog, P policy, 1-5 presets, Esc quits\n");
        for (int frame = 0; !glfwWindowShouldClose(window) && (frames <= 0 || frame < frames);
             ++frame) {
            const auto now = std::chrono::steady_clock::now();
            const double dt = std::min(0.1, std::chrono::duration<double>(now - last).count());
            last = now;
            glfwPollEvents();
            const auto down = [&](int key) { return glfwGetKey(window, key) == GLFW_PRESS; };
            if (down(GLFW_KEY_ESCAPE)) break;
            if (down(GLFW_KEY_LEFT)) state.heading_rad -= 0.8 * dt;
            if (down(GLFW_KEY_RIGHT)) state.heading_rad += 0.8 * dt;
            if (down(GLFW_KEY_UP))
                state.altitude_agl = std::min(5000.0, state.altitude_agl + 150 * dt);
            if (down(GLFW_KEY_DOWN))
                state.altitude_agl = std::max(20.0, state.altitude_agl - 150 * dt);
            if (down(GLFW_KEY_W)) speed = std::min(1000.0, speed + 100 * dt);
            if (down(GLFW_KEY_S)) speed = std::max(0.0, speed - 100 * dt);
            if (down(GLFW_KEY_T)) utc_min -= kHourKeyMinutesPerSecond * dt;
            if (down(GLFW_KEY_G)) utc_min += kHourKeyMinutesPerSecond * dt;
            for (int i = 0; i < 5; ++i) {
                if (down(GLFW_KEY_1 + i)) config.preset = kPresets[i];
            }
            static bool f_was = false, p_was = false, faster_was = false, slower_was = false;
            if (down(GLFW_KEY_F) && !f_was) state.fog = !state.fog;
            if (down(GLFW_KEY_P) && !p_was) config.policy = !config.policy;
            if (down(GLFW_KEY_RIGHT_BRACKET) && !faster_was)
                time_step = std::min(time_step + 1, std::size(kTimeFactors) - 1);
            if (down(GLFW_KEY_LEFT_BRACKET) && !slower_was && time_step > 0) --time_step;
            f_was = down(GLFW_KEY_F);
            p_was = down(GLFW_KEY_P);
            faster_was = down(GLFW_KEY_RIGHT_BRACKET);
            slower_was = down(GLFW_KEY_LEFT_BRACKET);
            config.time_factor = kTimeFactors[time_step];
            utc_min += config.time_factor * dt / 60.0;
            // Fly; keep the height above the ground below.
            const double ground = ground_height(world, state.x, state.y);
            state.x += std::sin(state.heading_rad) * speed * dt;
            state.y += std::cos(state.heading_rad) * speed * dt;
            state.altitude_agl += ground - ground_height(world, state.x, state.y);
            state.altitude_agl = std::max(20.0, state.altitude_agl);
            place_sky(state, config.sun, utc_min);

            glfwGetFramebufferSize(window, &config.width, &config.height);
            auto outcome = render_frame(*api, game, world, state, config);
            if (!outcome) {
                std::cerr << "aerial-sample: " << outcome.error().message << '\n';
                status = 1;
                break;
            }
            const bool last_frame = frames > 0 && frame + 1 == frames;
            if (last_frame && !screenshot.empty()) {
                std::vector<std::uint8_t> rgba(std::size_t(config.width) * config.height * 4);
                api->PixelStorei(GL_PACK_ALIGNMENT, 1);
                api->ReadPixels(0, 0, config.width, config.height, GL_RGBA, GL_UNSIGNED_BYTE,
                                rgba.data());
                aerial::tools::Rgb8Image image{config.width, config.height, {}};
                image.rgb.resize(std::size_t(config.width) * config.height * 3);
                for (int y = 0; y < config.height; ++y) {  // GL's rows are bottom first
                    for (int x = 0; x < config.width; ++x) {
                        for (int c = 0; c < 3; ++c) {
                            image.rgb[(std::size_t(y) * config.width + x) * 3 + c] =
                                rgba[(std::size_t(config.height - 1 - y) * config.width + x) * 4 +
                                     c];
                        }
                    }
                }
                if (auto e = aerial::tools::write_png(screenshot, image)) {
                    std::cerr << "aerial-sample: --out " << *e << '\n';
                    status = 2;
                } else {
                    std::printf("aerial-sample: %d window frames %dx%d renderer=\"%s\" -> %s\n",
                                frames, config.width, config.height, api->caps.renderer.c_str(),
                                screenshot.c_str());
                }
            }
            glfwSwapBuffers(window);
        }
    }
    glfwDestroyWindow(window);
    glfwTerminate();
    return status;
}

}  // namespace sample
