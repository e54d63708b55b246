// aerial-scene-bench: what the scene renderer does per frame on the sample's world, with and
// without the update policy, for a static and a flying camera. Prints one line a scenario (means
// over the frames after the first, which shades everything in every scenario). Speed figures
// come from one run on a shared machine: compare the scenarios with each other.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "aerial/headless.hpp"
#include "aerial/scene_renderer.hpp"
#include "aerial/scene_sky.hpp"
#include "fog_compare.hpp"
#include "sky_motion.hpp"
#include "support/cli.hpp"
#include "support/png.hpp"
#include "world.hpp"

namespace {

constexpr const char* kTool = "aerial-scene-bench";

int fail(const std::string& message, int status = 2) {
    std::cerr << kTool << ": " << message << '\n';
    return status;
}

struct Totals {
    double vertices_shaded = 0, cache_hits = 0, culled = 0, render_ms = 0, frame_ms = 0;
    double shading_ms = 0;
    double hp_nodes = 0, height_nodes = 0;
};

int run_sky_motion(int frames) {
    sample::SkyMotionOptions options;
    options.frames = frames;
    auto r = sample::run_sky_motion(options);
    if (!r) return fail("--sky-motion: " + r.error().message, 1);
    std::printf(
        "sky-motion: frames=%d sun=%.3f deg/frame climb=%.1f m/frame cube=%d spread=%d "
        "recomputes=%d encodes=%d mean_directions=%.1f max_directions=%d mean_update_ms=%.3f "
        "max_update_ms=%.3f whole_sky_ms=%.3f us_per_texel=%.2f "
        "max_bound_steps=%.2f max_steps_from_fresh=%d max_switch_steps=%.0f "
        "max_fresh_change_steps_per_%d_frames=%.0f\n",
        r->frames, options.sun_deg_per_frame, options.climb_m_per_frame, options.cache.size,
        options.cache.spread_updates, r->recomputes, r->encodes, r->mean_directions,
        r->max_directions, r->mean_update_ms, r->max_update_ms, r->whole_sky_ms,
        1000.0 * r->whole_sky_ms / (6.0 * options.cache.size * options.cache.size),
        r->max_bound_steps, r->max_steps_from_fresh, r->max_switch_steps, options.check_every,
        r->max_fresh_change_steps);
    return 0;
}

int run_flythrough(const aerial::gl::Api& api, const sample::World& world, aerial::Model model,
                   aerial::scene::Backend backend, const std::string& sky, int width, int height,
                   int frames, int rounds, const std::string& out) {
    sample::GameConfig config;
    config.model = model;
    config.backend = backend;
    config.readout = false;
    config.sky = sky == "dome" ? sample::SkyKind::dome : sample::SkyKind::cubemap;
    config.sun = sample::default_sun_schedule();
    config.width = width;
    config.height = height;
    if (auto e = aerial::tools::make_parent_directories(out + "/fog_compare.csv"))
        return fail("--out " + *e);
    auto summary =
        sample::run_fog_compare(api, world, config, frames, rounds, out + "/fog_compare.csv");
    if (!summary) return fail("--flythrough: " + summary.error().message, 1);
    std::printf(
        "flythrough: frames=%d rounds=%d (means over the last %d, fastest round) world_km=%.0f "
        "tiles=%zu aerial_ms=%.2f "
        "fog_ms=%.2f ratio=%.3f still_aerial_ms=%.2f still_fog_ms=%.2f still_ratio=%.3f "
        "sky=%s size=%dx%d renderer=\"%s\" -> %s/fog_compare.csv\n",
        frames, rounds, summary->frames, world.options.size_m / 1000.0, world.tiles,
        summary->aerial_ms, summary->fog_ms, summary->ratio(), summary->still_aerial_ms,
        summary->still_fog_ms, summary->still_ratio(), sky.c_str(), width, height,
        api.caps.renderer.c_str(), out.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Per-frame work of aerial::scene::SceneRenderer on the sample's world: static\n"
        "and flying (100 m/s at 30 frames/s) cameras, update policy on and off.\n"
        "Exit status: 0 on success, 2 on bad input, 1 when GL fails.",
        kTool};
    int frames = 31, width = 480, height = 270;
    std::string size = "480x270", model_text = "height", backend_text = "cpu", gl_text = "osmesa";
    app.add_option("--frames", frames, "Frames per scenario, 2..10000")->capture_default_str();
    app.add_option("--size", size, "Image size WxH")->capture_default_str();
    app.add_option("--model", model_text, "hoffman-preetham, height or reference")
        ->capture_default_str();
    app.add_option("--backend", backend_text, "cpu or arb")->capture_default_str();
    app.add_option("--gl", gl_text, "osmesa or egl")->capture_default_str();
    std::string sky_text = "dome";
    app.add_option("--sky", sky_text, "dome (the renderer's) or cubemap (install_cubemap_sky)")
        ->capture_default_str();
    bool flythrough = false;
    std::string out = "build/out/fog-compare";
    double world_km = sample::WorldOptions{}.size_m / 1000.0;
    app.add_flag(
        "--flythrough", flythrough,
        "Instead of the scenarios: the sample's scripted flythrough (its defaults: cubemap "
        "sky, update policy) against the same flight with GL fog only, frame by frame, "
        "each frame also repeated with nothing moved; writes OUT/fog_compare.csv");
    int rounds = 3;
    app.add_option("--rounds", rounds, "--flythrough: flights, 1..100 (each frame's fastest kept)")
        ->capture_default_str();
    app.add_option("--out", out, "--flythrough: directory of fog_compare.csv")
        ->capture_default_str();
    app.add_option("--world-size", world_km, "Side of the terrain square in km, 1..128")
        ->capture_default_str();
    bool sky_motion = false;
    app.add_flag("--sky-motion", sky_motion,
                 "Instead of the scenarios: the cubemap sky's cache over --frames frames of a sun "
                 "sinking 0.01 deg and an eye climbing 1 m a frame (no GL): recomputes, work a "
                 "frame, its bound, the texels against a fresh sky every 10th frame, and popping");
    if (auto exit_code = aerial::tools::parse_command_line(app, argc, argv, kTool)) {
        return *exit_code;
    }
    if (!(world_km >= 1.0 && world_km <= 128.0)) return fail("--world-size: expected 1..128 km");
    if (rounds < 1 || rounds > 100) return fail("--rounds: expected 1..100");
    if (frames < 2 || frames > 10000) return fail("--frames: expected 2..10000");
    if (sky_motion) return run_sky_motion(frames);
    if (std::sscanf(size.c_str(), "%dx%d", &width, &height) != 2 || width < 16 || height < 16 ||
        width > 4096 || height > 4096) {
        return fail("--size: expected WxH with sides in 16..4096, got '" + size + "'");
    }
    auto model = aerial::parse_model(model_text);
    if (!model) return fail("--model: " + model.error().message);
    auto backend = aerial::scene::parse_backend(backend_text);
    if (!backend) return fail("--backend: " + backend.error().message);
    auto gl_backend = aerial::headless::parse_platform(gl_text);
    if (!gl_backend) return fail("--gl: '" + gl_text + "' is unknown (expected osmesa or egl)");

    if (sky_text != "dome" && sky_text != "cubemap") {
        return fail("--sky: '" + sky_text + "' is unknown (expected dome or cubemap)");
    }
    sample::WorldOptions world_options;
    world_options.size_m = world_km * 1000.0;
    const sample::World world = sample::build_world(world_options);
    auto context = aerial::headless::Context::create({*gl_backend, width, height});
    if (!context) return fail("--gl: " + context.error().message, 1);
    const aerial::gl::Api& api = context->api();
    if (flythrough) {
        return run_flythrough(api, world, *model, *backend,
                              app.count("--sky") > 0 ? sky_text : "cubemap", width, height, frames,
                              rounds, out);
    }

    const sample::FlightState start = sample::flight_at(world, 0.1, sample::default_sun_schedule());
    struct Scenario {
        const char* name;
        bool policy;
        bool flying;
    };
    for (const Scenario& sc :
         {Scenario{"static_policy", true, false}, Scenario{"static_no_policy", false, false},
          Scenario{"flying_policy", true, true}, Scenario{"flying_no_policy", false, true}}) {
        aerial::scene::RendererOptions options;
        options.backend = *backend;
        auto renderer = aerial::scene::SceneRenderer::create(api, options);
        if (!renderer) return fail("--backend: " + renderer.error().message, 1);
        std::shared_ptr<const aerial::scene::CubemapSkyStats> sky;
        if (sky_text == "cubemap") {
            auto installed = aerial::scene::install_cubemap_sky(renderer.value(), api);
            if (!installed) return fail("--sky: " + installed.error().message, 1);
            sky = *installed;
        }
        Totals totals;
        for (int i = 0; i < frames; ++i) {
            sample::FlightState state = start;
            if (sc.flying) {  // 100 m/s at 30 frames/s along the heading, level
                state.x += std::sin(state.heading_rad) * 100.0 / 30.0 * i;
                state.y += std::cos(state.heading_rad) * 100.0 / 30.0 * i;
            }
            aerial::scene::Camera camera =
                sample::camera_for(world, state, double(width) / double(height));
            if (sc.flying) {  // keep the altitude of the start, not the ground's
                const aerial::scene::Camera c0 =
                    sample::camera_for(world, start, double(width) / double(height));
                camera.target += glm::dvec3(0, 0, c0.eye.z - camera.eye.z);
                camera.eye.z = c0.eye.z;
            }
            auto settings = sample::settings_for(state, "earth", *model,
                                                 *backend == aerial::scene::Backend::cpu
                                                     ? aerial::ToneCurve::exponential
                                                     : aerial::ToneCurve::clamp);
            if (!settings) return fail(settings.error().message, 1);
            settings.value().policy = sc.policy;
            api.Viewport(0, 0, width, height);
            api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            const auto t0 = std::chrono::steady_clock::now();
            auto report = renderer.value().render(*world.root, camera, *settings);
            if (!report) return fail(report.error().message, 1);
            api.Finish();
            const double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
            if (i == 0) continue;
            totals.vertices_shaded += double(report->vertices_shaded);
            totals.cache_hits += double(report->cache_hits);
            totals.culled += double(report->culled);
            totals.render_ms += report->milliseconds;
            totals.shading_ms += report->shading_milliseconds;
            totals.frame_ms += ms;
            totals.hp_nodes += double(report->shaded_hoffman_preetham);
            totals.height_nodes += double(report->shaded_height);
        }
        const double n = frames - 1;
        std::printf(
            "%s: frames=%d vertices_shaded=%.0f cache_hits=%.1f culled=%.1f "
            "nodes_hoffman_preetham=%.1f nodes_%s=%.1f shading_ms=%.2f render_ms=%.2f "
            "frame_ms=%.2f sky_recomputes=%d\n",
            sc.name, frames - 1, totals.vertices_shaded / n, totals.cache_hits / n,
            totals.culled / n, totals.hp_nodes / n, model_text.c_str(), totals.height_nodes / n,
            totals.shading_ms / n, totals.render_ms / n, totals.frame_ms / n,
            sky ? sky->recomputes : 0);
    }
    std::printf("world: tiles=%zu vertices=%zu size=%dx%d backend=%s sky=%s renderer=\"%s\"\n",
                world.tiles, world.vertices, width, height, backend_text.c_str(), sky_text.c_str(),
                api.caps.renderer.c_str());
    return 0;
}
