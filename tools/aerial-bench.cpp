// aerial-bench: benchmarks of the module. --cpu-throughput measures the CPU batch path against a
// plain std::exp loop and against the memory limit, all in one run (ratios, not absolute times,
// are what a shared machine reproduces). --out DIR charts speed against accuracy of every method
// on the bench scenes (bench/pareto.hpp): DIR/bench.csv and the Pareto charts drawn by
// tools/plot_bench.py.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/batch.hpp"
#include "aerial/validation/test_hooks.hpp"
#include "bench/pareto.hpp"
#include "bench/stability.hpp"
#include "support/cli.hpp"

namespace {

constexpr const char* kTool = "aerial-bench";

/// A terrain-like cloud: a square grid of `count` vertices spanning 20 km around the origin,
/// gently undulating, seen from 100 m up. AoS floats, 12-byte records.
std::vector<float> terrain_positions(std::size_t count) {
    const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(double(count))));
    std::vector<float> xyz;
    xyz.reserve(3 * count);
    for (std::size_t i = 0; i < count; ++i) {
        const double u = double(i % side) / double(side) - 0.5;
        const double v = double(i / side) / double(side) - 0.5;
        const double x = 20000.0 * u, y = 20000.0 * v;
        xyz.push_back(float(x));
        xyz.push_back(float(y));
        xyz.push_back(float(60.0 * std::sin(x * 0.0011) * std::cos(y * 0.0007)));
    }
    return xyz;
}

/// Best wall time of each run over `repetitions` rounds, seconds; each round runs every one
/// once, in order.
std::vector<double> best_of_interleaved(int repetitions,
                                        const std::vector<std::function<void()>>& runs) {
    std::vector<double> best(runs.size(), 1e300);
    for (int r = 0; r < repetitions; ++r) {
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const auto start = std::chrono::steady_clock::now();
            runs[i]();
            const auto stop = std::chrono::steady_clock::now();
            best[i] = std::min(best[i], std::chrono::duration<double>(stop - start).count());
        }
    }
    return best;
}

/// --out: the Pareto bench; returns the exit status.
int pareto(const std::string& out, bool quick, const std::string& scenes_dir,
           const std::string& size, int repetitions, bool chart) {
    aerial::bench::BenchOptions options;
    options.quick = quick;
    options.repetitions = repetitions;
    if (quick) options.width = 96, options.height = 72;
    if (!size.empty()) {
        int w = 0, h = 0;
        char tail = 0;
        if (std::sscanf(size.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 8 || h < 8 ||
            w > 4096 || h > 4096) {
            return aerial::tools::fail(kTool,
                                       "--size: expected WxH with each in 8 .. 4096, got " + size);
        }
        options.width = w;
        options.height = h;
    }
    options.images_dir = out + "/images";
    auto scenes = aerial::bench::load_bench_scenes(scenes_dir, quick);
    if (!scenes) return aerial::tools::fail(kTool, scenes.error().message);
    const auto start = std::chrono::steady_clock::now();
    auto rows = aerial::bench::run_bench(*scenes, options, stderr);
    if (!rows) return aerial::tools::fail(kTool, rows.error().message);
    const std::string csv = out + "/bench.csv";
    if (auto e = aerial::bench::write_bench_csv(csv, *rows))
        return aerial::tools::fail(kTool, "--out: " + *e);
    const std::vector<std::string> summary = aerial::bench::summarise(*rows);
    std::FILE* file = std::fopen((out + "/summary.txt").c_str(), "w");
    if (!file) return aerial::tools::fail(kTool, "--out: cannot write " + out + "/summary.txt");
    for (const auto& line : summary) {
        std::printf("%s\n", line.c_str());
        std::fprintf(file, "%s\n", line.c_str());
    }
    std::fclose(file);
    std::printf("total %.1f s; wrote %s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                csv.c_str());
    if (chart) {
        const std::string command = std::string("'") + AERIAL_BENCH_PYTHON + "' '" +
                                    AERIAL_BENCH_PLOT_SCRIPT + "' '" + csv + "' '" + out + "'";
        if (std::system(command.c_str()) != 0)
            return aerial::tools::fail(kTool, "the chart failed: " + command);
        std::printf("wrote %s/pareto.png and %s/pareto-SCENE.png\n", out.c_str(), out.c_str());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Benchmarks of the aerial module. --cpu-throughput: Mvertices/s of the CPU batch\n"
        "path (F_ex and L_in as RGBA8) with a plain std::exp loop (scalar), the SIMD\n"
        "kernels on one thread and on all, against a loop that only reads the same\n"
        "positions and writes the same bytes (stream, the memory limit; stream_threads:\n"
        "the same on all hardware threads); best of several repetitions, the variants\n"
        "interleaved, all in one run; for the height model also its SIMD kernel without\n"
        "the higher orders of scattering (simd_without).\n"
        "--out DIR: speed against accuracy. Every method (gl-fog, fg-fog, cpu-hp, arb-hp,\n"
        "cpu-height, arb-height, lut-texture, perpixel-reference; the per-vertex ones on\n"
        "uniform and adaptive meshes of several sizes) renders each scene of --scenes on\n"
        "OSMesa; ms per frame is the best of --repetitions interleaved rounds, the error is\n"
        "against the per-pixel image of the reference model of the same mesh. Writes\n"
        "DIR/bench.csv, DIR/summary.txt, DIR/images/, and DIR/pareto.png with\n"
        "DIR/pareto-SCENE.png (tools/plot_bench.py); default 160x120, 21 rounds. --quick: the\n"
        "scenes marked quick, 96x72, two sizes per tessellation, 3 rounds.",
        kTool};
    bool cpu_throughput = false;
    std::size_t vertices = 2'000'000;
    int repetitions = 15;
    std::string model_text = "hoffman-preetham", preset = "earth";
    app.add_flag("--cpu-throughput", cpu_throughput, "Measure the CPU batch path");
    std::string out_dir, scenes_dir = AERIAL_BENCH_SCENES, size;
    bool quick = false, no_chart = false;
    app.add_option("--out", out_dir,
                   "Speed against accuracy (or, with --stability, the stability map): write the "
                   "CSV and charts here");
    app.add_flag("--quick", quick,
                 "With --out: a small setting (well under a minute); with --stability a coarse "
                 "sweep (seconds)");
    app.add_option("--scenes", scenes_dir,
                   "With --out: directory of bench scene files (default tools/bench/scenes)");
    app.add_option("--size", size, "With --out: image size WxH (default 160x120, quick 96x72)");
    app.add_flag("--no-chart", no_chart, "With --out: write the CSV only");
    app.add_option("--vertices", vertices,
                   "Vertices per batch (default 2000000, at least 1000000 "
                   "for the figures the docs quote)");
    app.add_option("--repetitions", repetitions,
                   "Runs per figure; the best is kept (default 15: the fastest run is the one "
                   "least disturbed on a shared machine)");
    app.add_option("--model", model_text, "hoffman-preetham (default) or height");
    app.add_option("--preset", preset, "Atmosphere preset (default earth)");
    std::string simd_target;
    app.add_option("--simd-target", simd_target,
                   "With --cpu-throughput: run the SIMD kernels on this target (AVX3, AVX2, SSE4, "
                   "SSSE3, SCALAR; one the CPU supports) instead of the best");
    bool stability = false;
    app.add_flag("--stability", stability,
                 "Stability map: every method against the reference model over sweeps of sun "
                 "elevation, altitude, distance, g, turbidity and visibility; writes "
                 "DIR/stability.csv and DIR/stability.png");
    std::vector<std::string> sweep_names;
    app.add_option("--sweep", sweep_names,
                   "With --stability: run only this sweep (sun_elevation_deg, altitude_m, "
                   "distance_m, mie_g, turbidity, visibility_m; repeatable)");
    if (auto status = aerial::tools::parse_command_line(app, argc, argv, kTool)) return *status;
    if (!sweep_names.empty() && !stability) {
        return aerial::tools::fail(kTool, "--sweep: only with --stability");
    }
    if (!simd_target.empty() && !cpu_throughput) {
        return aerial::tools::fail(kTool, "--simd-target: only with --cpu-throughput");
    }
    if (stability) return aerial::bench::run_stability(out_dir, quick, sweep_names);
    if (cpu_throughput && !out_dir.empty()) {
        return aerial::tools::fail(kTool, "--out: not together with --cpu-throughput");
    }
    if (!cpu_throughput && out_dir.empty()) {
        return aerial::tools::fail(kTool, "nothing to do: give --cpu-throughput or --out DIR");
    }
    if (vertices < 1 || vertices > 200'000'000) {
        return aerial::tools::fail(
            kTool, "--vertices must be in [1, 200000000], got " + std::to_string(vertices));
    }
    if (repetitions < 1 || repetitions > 1000) {
        return aerial::tools::fail(
            kTool, "--repetitions must be in [1, 1000], got " + std::to_string(repetitions));
    }
    if (!out_dir.empty()) {
        const int rounds = app.count("--repetitions") ? repetitions : (quick ? 3 : 21);
        return pareto(out_dir, quick, scenes_dir, size, rounds, !no_chart);
    }
    if (!simd_target.empty() && !aerial::validation::simd_test_use_target(simd_target)) {
        std::string supported;
        for (const auto& t : aerial::validation::simd_test_targets()) supported += " " + t;
        return aerial::tools::fail(kTool, "--simd-target: '" + simd_target +
                                              "' is not a target this build and CPU run (they "
                                              "are:" +
                                              supported + ")");
    }
    const auto model = aerial::parse_model(model_text);
    if (!model) return aerial::tools::fail(kTool, "--model: " + model.error().message);
    if (aerial::is_numerical(*model)) {
        return aerial::tools::fail(kTool, "--model: " + std::string(aerial::model_name(*model)) +
                                              " has no SIMD kernel to measure");
    }
    const auto atmosphere = aerial::atmosphere_preset(preset);
    if (!atmosphere) return aerial::tools::fail(kTool, "--preset: " + atmosphere.error().message);

    aerial::View view;
    view.eye = {0.0, 0.0, 100.0};
    view.sun_dir = glm::normalize(glm::dvec3(0.3, 0.6, 0.5));
    const auto frame = aerial::prepare_frame<float>(*atmosphere, view, *model);
    if (!frame) return aerial::tools::fail(kTool, frame.error().message);

    const std::vector<float> xyz = terrain_positions(vertices);
    const aerial::Positions positions = aerial::Positions::aos(xyz.data(), vertices);
    std::vector<std::uint8_t> extinction(4 * vertices), in_scattering(4 * vertices);
    aerial::BatchOutputs out;
    out.extinction_rgba8 = extinction.data();
    out.in_scattering_rgba8 = in_scattering.data();

    // The height model without its higher orders (Frame::multiple_scattering reset): their
    // per-vertex cost, side by side in the same run.
    aerial::Frame<float> single = *frame;
    single.multiple_scattering.reset();
    auto batch = [&](aerial::Kernel kernel, unsigned threads,
                     const aerial::Frame<float>* shaded = nullptr) {
        return [&, kernel, threads, shaded] {
            aerial::BatchSettings settings;
            settings.kernel = kernel;
            settings.threads = threads;
            settings.display.exposure = 20.0f;
            const auto stats =
                aerial::shade_into(shaded ? *shaded : *frame, positions, out, settings);
            if (!stats) std::fprintf(stderr, "%s\n", stats.error().message.c_str());
        };
    };
    // The memory limit: read the same positions, write the same 8 bytes per vertex (vertices
    // first .. last).
    auto stream_part = [&](std::size_t first, std::size_t last) {
        std::uint32_t* e = reinterpret_cast<std::uint32_t*>(extinction.data());
        std::uint32_t* l = reinterpret_cast<std::uint32_t*>(in_scattering.data());
        for (std::size_t i = first; i < last; ++i) {
            std::uint32_t a, b, c;
            std::memcpy(&a, &xyz[3 * i], 4);
            std::memcpy(&b, &xyz[3 * i + 1], 4);
            std::memcpy(&c, &xyz[3 * i + 2], 4);
            e[i] = a ^ b;
            l[i] = b ^ c;
        }
    };
    auto stream_loop = [&] { stream_part(0, vertices); };
    // The memory limit of all hardware threads (what simd_threads can reach at best): the same
    // loop, cut into one contiguous part per thread.
    const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    auto stream_threads_loop = [&] {
        std::vector<std::thread> helpers;
        for (unsigned t = 1; t < hardware; ++t) {
            helpers.emplace_back(stream_part, vertices * t / hardware,
                                 vertices * (t + 1) / hardware);
        }
        stream_part(0, vertices / hardware);
        for (auto& helper : helpers) helper.join();
    };
    // Every variant once per repetition, in turn, so that a disturbance of the shared machine
    // hits them all alike; the best time of each is kept.
    const std::vector<std::function<void()>> variants = {stream_loop,
                                                         batch(aerial::Kernel::scalar, 1),
                                                         batch(aerial::Kernel::simd, 1),
                                                         batch(aerial::Kernel::simd_fast, 1),
                                                         batch(aerial::Kernel::simd, 0),
                                                         batch(aerial::Kernel::simd_fast, 0),
                                                         stream_threads_loop,
                                                         batch(aerial::Kernel::simd, 1, &single)};
    const std::vector<double> best = best_of_interleaved(repetitions, variants);
    const double mverts = double(vertices) / 1e6;
    const double stream = mverts / best[0];
    const double scalar = mverts / best[1];
    const double simd = mverts / best[2];
    const double simd_fast = mverts / best[3];
    const double simd_threads = mverts / best[4];
    const double simd_fast_threads = mverts / best[5];
    const double stream_threads = mverts / best[6];
    std::printf("model=%s preset=%s vertices=%zu repetitions=%d simd_target=%s threads=%u\n",
                model_text.c_str(), preset.c_str(), vertices, repetitions, aerial::simd_target(),
                std::max(1u, std::thread::hardware_concurrency()));
    std::printf(
        "throughput: scalar=%.1f simd=%.1f simd_threads=%.1f stream=%.1f "
        "ratio_simd_stream=%.2f ratio_simd_scalar=%.1f\n",
        scalar, simd, simd_threads, stream, simd / stream, simd / scalar);
    std::printf(
        "fast exp: simd_fast=%.1f simd_fast_threads=%.1f ratio_fast_simd=%.2f "
        "ratio_threads_simd=%.2f\n",
        simd_fast, simd_fast_threads, simd_fast / simd, simd_threads / simd);
    std::printf(
        "memory: stream_threads=%.1f ratio_stream_threads_stream=%.2f "
        "ratio_simd_threads_stream_threads=%.2f\n",
        stream_threads, stream_threads / stream, simd_threads / stream_threads);
    if (frame->multiple_scattering) {
        const double single_simd = mverts / best[7];
        std::printf("higher orders: simd=%.1f simd_without=%.1f ratio_with_without=%.2f\n", simd,
                    single_simd, simd / single_simd);
    }
    return 0;
}
