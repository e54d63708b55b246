// aerial-sample: a flight over 16 × 16 km of procedural terrain with sky, sun and aerial
// perspective from aerial::scene, headless by default: a scripted flythrough (noon, dusk,
// twilight and a moonlit night, a ground-fog segment) rendered to PNG frames, a contact sheet and
// a CSV of what each frame did.
// Built only on the public API.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "aerial/adaptive_scene.hpp"
#include "aerial/aerial.hpp"
#include "aerial/headless.hpp"
#include "aerial/scene_renderer.hpp"
#include "game.hpp"
#include "soak.hpp"
#include "support/cli.hpp"
#include "support/png.hpp"
#include "world.hpp"

namespace {

constexpr const char* kTool = "aerial-sample";
constexpr const char* kDescription =
    "Flies over 16 x 16 km of procedural, textured terrain with a sky and a sun; F_ex and\n"
    "L_in per vertex from the aerial module (aerial::scene, cpu colours or the ARB program),\n"
    "applied by the fixed pipeline. The sun stands where it does on --date at --latitude and\n"
    "--longitude (NOAA solar calculator), the moon and the stars where they do (libnova, the\n"
    "Yale Bright Star Catalogue). Headless (default): renders a scripted flythrough (solar noon\n"
    "into the night, the sun 15 deg down; ground fog in the middle) to DIR/frame_NNNN.png,\n"
    "DIR/contact_sheet.png and DIR/frames.csv, and prints one summary line.\n"
    "Exit status: 0 on success, 2 on bad input, 1 when the GL context or rendering fails.";

constexpr int kMaxSide = 4096;
constexpr int kMaxFrames = 10000;
constexpr int kThumbnailWidth = 240;

int fail(const std::string& message, int status = 2) {
    std::cerr << kTool << ": " << message << '\n';
    return status;
}

bool parse_size(const std::string& text, int& width, int& height) {
    unsigned long w = 0, h = 0;
    int consumed = 0;
    if (std::sscanf(text.c_str(), "%lux%lu%n", &w, &h, &consumed) != 2 ||
        std::size_t(consumed) != text.size() || text[0] == '-' || w < 16 || h < 16 ||
        w > kMaxSide || h > kMaxSide) {
        return false;
    }
    width = int(w);
    height = int(h);
    return true;
}

bool parse_date(const std::string& text, int& year, int& month, int& day) {
    int consumed = 0;
    return std::sscanf(text.c_str(), "%4d-%2d-%2d%n", &year, &month, &day, &consumed) == 3 &&
           std::size_t(consumed) == text.size() && text.size() == 10;
}

/// A box-filtered thumbnail `factor` times smaller.
aerial::tools::Rgb8Image shrink(const aerial::tools::Rgb8Image& image, int factor) {
    aerial::tools::Rgb8Image out;
    out.width = std::max(1, image.width / factor);
    out.height = std::max(1, image.height / factor);
    out.rgb.resize(std::size_t(out.width) * out.height * 3);
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                int sum = 0;
                for (int dy = 0; dy < factor; ++dy) {
                    for (int dx = 0; dx < factor; ++dx) {
                        sum += image.pixel(x * factor + dx, y * factor + dy)[c];
                    }
                }
                out.rgb[(std::size_t(y) * out.width + x) * 3 + std::size_t(c)] =
                    std::uint8_t((sum + factor * factor / 2) / (factor * factor));
            }
        }
    }
    return out;
}

aerial::tools::Rgb8Image contact_sheet(const std::vector<aerial::tools::Rgb8Image>& thumbs) {
    aerial::tools::Rgb8Image sheet;
    if (thumbs.empty()) return sheet;
    const int columns = std::min<int>(int(thumbs.size()), 6);
    const int rows = (int(thumbs.size()) + columns - 1) / columns;
    const int gap = 2, tw = thumbs[0].width, th = thumbs[0].height;
    sheet.width = columns * (tw + gap) + gap;
    sheet.height = rows * (th + gap) + gap;
    sheet.rgb.assign(std::size_t(sheet.width) * sheet.height * 3, 32);
    for (std::size_t i = 0; i < thumbs.size(); ++i) {
        const int x0 = gap + int(i % std::size_t(columns)) * (tw + gap);
        const int y0 = gap + int(i / std::size_t(columns)) * (th + gap);
        for (int y = 0; y < th; ++y) {
            std::copy_n(
                thumbs[i].pixel(0, y), std::size_t(tw) * 3,
                sheet.rgb.begin() + std::ptrdiff_t((std::size_t(y0 + y) * sheet.width + x0) * 3));
        }
    }
    return sheet;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{kDescription, kTool};
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    std::string out = "build/out/flythrough", size = "480x270", preset = "earth",
                model_text = "height", backend_text = "cpu", path_text = "automatic",
                gl_text = "osmesa", sky_text = "cubemap", tessellation_text = "uniform";
    int frames = 24;
    unsigned seed = 7;
    double error_target = 2.0, latitude_deg = sample::kDefaultLatitudeDeg,
           longitude_deg = sample::kDefaultLongitudeDeg;
    char default_date[16];
    std::snprintf(default_date, sizeof default_date, "%04d-%02d-%02d", sample::kDefaultYear,
                  sample::kDefaultMonth, sample::kDefaultDay);
    std::string date = default_date;
    bool headless = false, window = false, no_policy = false, no_readout = false;
    app.add_flag("--headless", headless, "Render the scripted flythrough off-screen (the default)");
    app.add_flag("--window", window, "Fly interactively in a window (needs GLFW and a display)");
    app.add_option("--frames", frames, "Frames of the flythrough, 1.." + std::to_string(kMaxFrames))
        ->capture_default_str();
    app.add_option("--out", out, "Directory for frame_NNNN.png, contact_sheet.png, frames.csv")
        ->capture_default_str();
    app.add_option("--size", size, "Image size WxH in pixels, 16.." + std::to_string(kMaxSide))
        ->capture_default_str();
    app.add_option("--preset", preset, "Atmosphere preset: earth, hazy, foggy, hp2002, mars")
        ->capture_default_str();
    app.add_option("--model", model_text,
                   "Model that sets the accuracy: hoffman-preetham, height, single-scattering, "
                   "reference (cpu only)")
        ->capture_default_str();
    app.add_option("--backend", backend_text, "cpu (colours from aerial::shade_into) or arb (GPU)")
        ->capture_default_str();
    app.add_option("--path", path_text,
                   "Fixed-function path of the cpu backend: automatic, secondary-color, combiner, "
                   "two-pass")
        ->capture_default_str();
    app.add_option("--gl", gl_text, "Headless context: osmesa or egl")->capture_default_str();
    app.add_option("--seed", seed, "Terrain seed")->capture_default_str();
    app.add_option("--error-target", error_target,
                   "Largest 8-bit difference to --model the update policy accepts, >= 0")
        ->capture_default_str();
    app.add_option("--date", date, "UTC date of the flight, YYYY-MM-DD (1901..2099)")
        ->capture_default_str();
    app.add_option("--latitude", latitude_deg, "Latitude of the terrain, degrees north, -90..90")
        ->capture_default_str();
    app.add_option("--longitude", longitude_deg,
                   "Longitude of the terrain, degrees east, -180..180")
        ->capture_default_str();
    app.add_option("--sky", sky_text,
                   "cubemap (CPU sky cubemap and sun sprite; the dome where cube maps are "
                   "missing) or dome (per-vertex dome and flat sun)")
        ->capture_default_str();
    app.add_option("--tessellation", tessellation_text,
                   "uniform (the sky as --sky says) or adaptive (a per-vertex sky dome refined "
                   "where its colour needs vertices, aerial::mesh; implies the dome)")
        ->capture_default_str();
    app.add_flag("--no-policy", no_policy, "Shade every visible vertex every frame with --model");
    app.add_flag("--no-readout", no_readout, "Leave out the on-screen readout (for goldens)");
    int soak_frames = 0, tile_resolution = sample::WorldOptions{}.tile_resolution;
    int tess_budget = int(sample::SoakOptions{}.tessellation_budget);
    int cube_size = sample::GameConfig{}.cube_size;
    app.add_option("--soak", soak_frames,
                   "Soak test: render FRAMES frames (1..1000000) flying back and forth, no files; "
                   "print RSS and the difference to fresh renders; exit 1 when memory grows or a "
                   "frame differs");
    app.add_option("--tess-budget", tess_budget,
                   "--soak: vertex budget of the adaptive sky dome refined every frame, "
                   "0..100000 (0: none)")
        ->capture_default_str();
    app.add_option("--tile-resolution", tile_resolution,
                   "Vertices along a terrain tile's side, 2..65 (fewer: a cheaper world)")
        ->capture_default_str();
    double world_km = sample::WorldOptions{}.size_m / 1000.0;
    app.add_option("--world-size", world_km,
                   "Side of the terrain square in km, 1..128 (the flight path scales with it)")
        ->capture_default_str();
    app.add_option("--cube-size", cube_size,
                   "Texels along a face of the cubemap sky, 1..512 (fewer: a cheaper refresh)")
        ->capture_default_str();
    if (auto exit_code = aerial::tools::parse_command_line(app, argc, argv, kTool)) {
        return *exit_code;
    }

    int width = 0, height = 0;
    if (!parse_size(size, width, height)) {
        return fail("--size: expected WxH with W and H in 16.." + std::to_string(kMaxSide) +
                    ", got '" + size + "'");
    }
    if (frames < 1 || frames > kMaxFrames) {
        return fail("--frames: expected 1.." + std::to_string(kMaxFrames) + ", got " +
                    std::to_string(frames));
    }
    if (auto atmosphere = aerial::atmosphere_preset(preset); !atmosphere) {
        return fail("--preset: " + atmosphere.error().message);
    }
    auto model = aerial::parse_model(model_text);
    if (!model) return fail("--model: " + model.error().message);
    auto backend = aerial::scene::parse_backend(backend_text);
    if (!backend) return fail("--backend: " + backend.error().message);
    auto path = aerial::gl::parse_path(path_text);
    if (!path) {
        return fail("--path: '" + path_text +
                    "' is unknown (expected automatic, secondary-color, combiner or two-pass)");
    }
    if (*backend == aerial::scene::Backend::arb && *path != aerial::gl::Path::automatic) {
        return fail("--path: only with --backend cpu");
    }
    if (*backend == aerial::scene::Backend::arb && aerial::is_numerical(*model)) {
        return fail("--model: the arb backend has programs for hoffman-preetham and height only");
    }
    auto gl_backend = aerial::headless::parse_platform(gl_text);
    if (!gl_backend) return fail("--gl: '" + gl_text + "' is unknown (expected osmesa or egl)");
    if (!(error_target >= 0.0) || !std::isfinite(error_target)) {
        return fail("--error-target: expected a finite value >= 0");
    }
    if (out.empty()) return fail("--out: expected a directory");
    if (sky_text != "cubemap" && sky_text != "dome") {
        return fail("--sky: '" + sky_text + "' is unknown (expected cubemap or dome)");
    }
    if (tessellation_text != "uniform" && tessellation_text != "adaptive") {
        return fail("--tessellation: '" + tessellation_text +
                    "' is unknown (expected uniform or adaptive)");
    }
    const bool adaptive_sky = tessellation_text == "adaptive";
    if (adaptive_sky) sky_text = "dome";
    int year = 0, month = 0, day = 0;
    if (!parse_date(date, year, month, day)) {
        return fail("--date: expected YYYY-MM-DD, got '" + date + "'");
    }
    if (!(latitude_deg >= -90.0 && latitude_deg <= 90.0)) {
        return fail("--latitude: expected -90..90 degrees, got " + std::to_string(latitude_deg));
    }
    if (!(longitude_deg >= -180.0 && longitude_deg <= 180.0)) {
        return fail("--longitude: expected -180..180 degrees, got " +
                    std::to_string(longitude_deg));
    }
    constexpr double kDegree = 3.14159265358979323846 / 180.0;
    auto schedule = sample::make_sun_schedule(year, month, day, latitude_deg * kDegree,
                                              longitude_deg * kDegree);
    if (!schedule) {
        const std::string& field = schedule.error().field;
        const std::string flag = field == "latitude"    ? "--latitude"
                                 : field == "longitude" ? "--longitude"
                                                        : "--date";
        return fail(flag + (flag == "--date" ? " " + date : std::string()) + ": " +
                    schedule.error().message);
    }
    if (window && headless) return fail("--window: not together with --headless");
    if (app.count("--soak") > 0 && (soak_frames < 1 || soak_frames > 1000000)) {
        return fail("--soak: expected 1..1000000 frames, got " + std::to_string(soak_frames));
    }
    if (app.count("--soak") > 0 && window) return fail("--soak: not together with --window");
    if (tess_budget < 0 || tess_budget > 100000) {
        return fail("--tess-budget: expected 0..100000, got " + std::to_string(tess_budget));
    }
    if (cube_size < 1 || cube_size > 512) {
        return fail("--cube-size: expected 1..512, got " + std::to_string(cube_size));
    }
    if (!(world_km >= 1.0 && world_km <= 128.0)) {
        return fail("--world-size: expected 1..128 km, got " + std::to_string(world_km));
    }
    if (tile_resolution < 2 || tile_resolution > 65) {
        return fail("--tile-resolution: expected 2..65, got " + std::to_string(tile_resolution));
    }
    if (window && !sample::window_available()) {
        return fail("--window: this build has no window support (GLFW); use --headless");
    }

    sample::WorldOptions world_options;
    world_options.seed = seed;
    world_options.tile_resolution = tile_resolution;
    world_options.size_m = world_km * 1000.0;
    const sample::World world = sample::build_world(world_options);
    sample::GameConfig config;
    config.preset = preset;
    config.model = *model;
    config.backend = *backend;
    config.path = *path;
    config.policy = !no_policy;
    config.error_target_lsb = error_target;
    config.readout = !no_readout;
    config.sky = sky_text == "dome" ? sample::SkyKind::dome : sample::SkyKind::cubemap;
    config.sun = *schedule;
    config.width = width;
    config.height = height;
    config.cube_size = cube_size;
    if (app.count("--soak") > 0) {
        sample::SoakOptions soak;
        soak.frames = soak_frames;
        // 10 000 frames: legs of 500 frames (sun and camera over the whole script and back in
        // 1 000), RSS baseline after the first round trip; shorter soaks scale the legs down and
        // take the baseline halfway (the adaptive dome fills its budget over the first frames).
        soak.baseline_frame = std::min(1000, std::max(1, soak_frames / 2));
        soak.leg_frames = std::min(500, std::max(1, soak_frames / 20));
        soak.gl = *gl_backend;
        soak.tessellation_budget = std::size_t(tess_budget);
        auto report = sample::run_soak(world, config, soak);
        if (!report) return fail("--soak: " + report.error().message, 1);
        std::printf("%s: %s\n", kTool, report->summary().c_str());
        if (!report->passed()) return fail("--soak: " + report->summary(), 1);
        return 0;
    }
    if (window) {
        // Interactive until closed; with --frames given, that many frames, the last saved.
        const bool counted = app.count("--frames") > 0;
        return sample::run_window(world, config, counted ? frames : 0,
                                  counted ? out + "/window.png" : "");
    }

    auto context = aerial::headless::Context::create({*gl_backend, width, height});
    if (!context) return fail("--gl " + gl_text + ": " + context.error().message, 1);
    const aerial::gl::Api& api = context->api();
    aerial::scene::RendererOptions options;
    options.backend = *backend;
    options.path = *path;
    auto renderer = aerial::scene::SceneRenderer::create(api, options);
    if (!renderer) {
        const int status = renderer.error().field == "path" ? 2 : 1;
        return fail("--backend " + backend_text + ": " + renderer.error().message, status);
    }

    auto sky = sample::install_sky(renderer.value(), api, config);
    if (!sky) return fail("--sky: " + sky.error().message, 1);
    config.sky = sky->used;
    sample::GameRenderer game{std::move(renderer).value(), *sky};
    auto sky_stats = std::make_shared<aerial::scene::AdaptiveSkyStats>();
    if (adaptive_sky)
        game.renderer.set_sky_drawer(aerial::scene::adaptive_sky_drawer({}, sky_stats));

    if (auto e = aerial::tools::make_parent_directories(out + "/frames.csv"))
        return fail("--out " + *e);
    std::ofstream csv(out + "/frames.csv");
    if (!csv) return fail("--out: cannot write " + out + "/frames.csv");
    csv << "frame,t,utc,solar_time,sun_elevation_deg,sun_azimuth_deg,fog,exposure,"
           "vertices_shaded,vertices_drawn,cache_hits,culled,skipped,nodes_hoffman_preetham,"
           "nodes_height,nodes_reference,method,shading_ms,ms,sky,sky_refreshes,sky_refresh_ms,"
           "tessellation,sky_vertices,sky_directions,sky_bound_steps,moon_elevation_deg,"
           "moon_phase_deg,moon_fraction,lights,stars_drawn\n";

    std::vector<aerial::tools::Rgb8Image> thumbnails;
    const int factor = std::max(1, width / kThumbnailWidth);
    double total_ms = 0.0, total_shaded = 0.0;
    std::size_t most_stars = 0;
    double last_sun_deg = 0.0;
    for (int i = 0; i < frames; ++i) {
        const double t = frames == 1 ? 0.0 : double(i) / double(frames - 1);
        const sample::FlightState state = sample::flight_at(world, t, config.sun);
        auto outcome = sample::render_frame(api, game, world, state, config);
        if (!outcome) return fail("frame " + std::to_string(i) + ": " + outcome.error().message, 1);
        const aerial::scene::FrameReport& report = outcome->report;
        const double ms = outcome->milliseconds;
        total_ms += ms;
        total_shaded += double(report.vertices_shaded);
        const double sun_deg = state.sun_elevation_rad / kDegree;
        const aerial::tools::Rgb8Image image =
            aerial::tools::rgb_from_rgba8(width, height, context->read_rgba8());
        char name[64];
        std::snprintf(name, sizeof name, "/frame_%04d.png", i);
        if (auto e = aerial::tools::write_png(out + name, image)) return fail("--out " + *e);
        thumbnails.push_back(shrink(image, factor));
        // The cubemap's refreshes so far, and the cost of this frame's refresh (0: none).
        const aerial::scene::CubemapSkyStats* stats = game.sky.stats.get();
        if (stats && !stats->error.empty())
            return fail("frame " + std::to_string(i) + ": " + stats->error, 1);
        if (!game.sky.night->stats->error.empty())
            return fail(
                "frame " + std::to_string(i) + ": night sky: " + game.sky.night->stats->error, 1);
        most_stars = std::max(most_stars, outcome->stars_drawn);
        last_sun_deg = sun_deg;
        const int refreshes = stats ? stats->recomputes : 0;
        const double refresh_ms = stats ? stats->last_refresh_ms : 0.0;
        if (!sky_stats->error.empty())
            return fail("frame " + std::to_string(i) + ": adaptive sky: " + sky_stats->error, 1);
        // The moon: its place and phase, and its light as a fraction of the sun's (the renderer's
        // Moonlight::fraction).
        const auto& moon = state.moon;
        const auto& moonlight = outcome->settings.moon;
        char row[768];
        std::snprintf(
            row, sizeof row,
            "%d,%.4f,%s,%s,%.2f,%.2f,%d,%.3f,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%zu,%s,%.3f,%.3f,%s,%d,"
            "%.2f,%s,%zu,%d,%.2f,%.2f,%.2f,%.4g,%s,%zu\n",
            i, t, sample::clock_text(std::fmod(state.utc_min / 60.0 + 24.0, 24.0)).c_str(),
            sample::clock_text(state.clock_hours).c_str(), sun_deg, state.sun_azimuth_rad / kDegree,
            state.fog ? 1 : 0, double(outcome->settings.display.exposure), report.vertices_shaded,
            report.vertices_drawn, report.cache_hits, report.culled, report.skipped,
            report.shaded_hoffman_preetham, report.shaded_height, report.shaded_reference,
            report.main_method().c_str(), report.shading_milliseconds, ms,
            sample::sky_name(config.sky), refreshes, refresh_ms, tessellation_text.c_str(),
            adaptive_sky ? sky_stats->vertices : std::size_t(0),
            stats ? stats->directions_last_frame : 0, stats ? stats->bound_steps : 0.0,
            moon ? moon->elevation_rad / kDegree : 0.0,
            moon ? moon->phase_angle_rad / kDegree : 0.0, moonlight ? moonlight->fraction : 0.0,
            aerial::scene::lights_name(report.lights), outcome->stars_drawn);
        csv << row;
    }
    if (auto e = aerial::tools::write_png(out + "/contact_sheet.png", contact_sheet(thumbnails))) {
        return fail("--out " + *e);
    }
    const aerial::scene::CubemapSkyStats* stats = game.sky.stats.get();
    std::printf(
        "%s: %d frames %dx%d preset=%s model=%s backend=%s policy=%s sky=%s tessellation=%s "
        "date=%s "
        "latitude=%.4f longitude=%.4f tiles=%zu vertices=%zu mean_ms=%.2f "
        "mean_vertices_shaded=%.0f sky_refreshes=%d mean_sky_refresh_ms=%.1f last_sun_deg=%.2f "
        "most_stars=%zu star_searches=%d renderer=\"%s\" -> %s/\n",
        kTool, frames, width, height, preset.c_str(), model_text.c_str(), backend_text.c_str(),
        no_policy ? "off" : "on", sample::sky_name(config.sky), tessellation_text.c_str(),
        date.c_str(), latitude_deg, longitude_deg, world.tiles, world.vertices, total_ms / frames,
        total_shaded / frames, stats ? stats->recomputes : 0,
        stats ? stats->total_refresh_ms / frames : 0.0, last_sun_deg, most_stars,
        game.sky.night->stars.recomputes, api.caps.renderer.c_str(), out.c_str());
    return 0;
}
