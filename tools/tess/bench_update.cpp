// aerial-tess's update benches: see bench_update.hpp.
#include "bench_update.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <functional>
#include <numeric>
#include <optional>
#include <vector>

#include "aerial/mesh.hpp"
#include "aerial/validation/tess_scenes.hpp"
#include "tess/methods.hpp"

namespace aerial::tess {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;

double cpu_ms_since(std::clock_t start) {
    return 1000.0 * double(std::clock() - start) / CLOCKS_PER_SEC;
}

/// One mesh type behind one call: update for a frame, returning its stats.
using Update = std::function<mesh::UpdateStats(const Frame<float>&)>;

validation::TessScene bench_scene(bool dome) {
    validation::TessSceneSpec spec;
    spec.kind = dome ? "dome" : "terrain";
    spec.sun_elevation_deg = 10.0;
    spec.mie_g = 0.9;
    spec.eye_m = 40.0;
    return validation::make_tess_scene(spec).value();
}

}  // namespace

int bench_update(const BenchUpdateOptions& options) {
    const validation::TessScene scene = bench_scene(options.dome);
    const mesh::Mesh base =
        options.dome ? adaptive_base(scene) : mesh::terrain_grid(scene.field, 224, 224).value();
    // The still methods' settings (quantized estimate on the dome); terrain at the library's
    // split threshold as before.
    mesh::AdaptiveSettings a = adaptive_settings(scene, 1.0, options.dome);
    if (options.relocate >= 0) a.relocate = options.relocate == 1;
    Update update;
    std::size_t rebuilds = 0;
    std::optional<mesh::AdaptiveMesh> adaptive;
    std::optional<mesh::DecimatingMesh> decimating;
    const mesh::Mesh* shown = nullptr;
    if (options.decimating) {
        mesh::DecimatingSettings d =
            decimating_settings(scene, 1.0, options.dome ? 0.55 : 0.2, options.dome);
        d.adaptive.relocate = a.relocate;
        d.background = false;
        d.rebuild_sun_rad = options.rebuild_sun_deg * kPi / 180.0;
        decimating.emplace(mesh::DecimatingMesh::create(base, adaptive_surface(scene), d).value());
        update = [&](const Frame<float>& f) { return decimating->update(f).value(); };
    } else {
        adaptive.emplace(mesh::AdaptiveMesh::create(base, adaptive_surface(scene), a).value());
        update = [&](const Frame<float>& f) { return adaptive->update(f); };
    }
    const auto first_start = Clock::now();
    const auto first = update(scene.setting.frame);
    const double first_ms =
        std::chrono::duration<double, std::milli>(Clock::now() - first_start).count();
    std::vector<double> cpu;
    std::size_t estimated = 0, splits = 0, merges = 0, fewest = first.vertices, most = 0;
    double vertices = 0.0;
    View view = scene.setting.frame.view;
    const Atmosphere atmosphere = scene.setting.frame.atmosphere;
    for (int i = 1; i <= options.frames; ++i) {
        if (options.dome) {
            const double elevation = (10.0 - options.sun_deg_per_min / 3600.0 * i) * kPi / 180.0;
            view.sun_dir = {std::cos(elevation), 0.0, std::sin(elevation)};
        } else {
            view.eye.x = 20.0 / 60.0 * i;
            view.eye.z = scene.field.height_m(view.eye.x, 0.0) + 40.0;
        }
        const auto frame = prepare_frame<float>(atmosphere, view, Model::height);
        const std::clock_t cpu_start = std::clock();
        const auto stats = update(frame.value());
        cpu.push_back(cpu_ms_since(cpu_start));
        estimated += stats.faces_estimated;
        splits += stats.splits;
        merges += stats.merges;
        vertices += double(stats.vertices);
        fewest = std::min(fewest, stats.vertices);
        most = std::max(most, stats.vertices);
    }
    if (decimating) rebuilds = decimating->stats().rebuilds - 1;
    shown = decimating ? &decimating->mesh() : &adaptive->mesh();
    const double mean = std::accumulate(cpu.begin(), cpu.end(), 0.0) / double(cpu.size());
    std::sort(cpu.begin(), cpu.end());
    std::printf(
        "bench-update: %s %s triangles=%zu first_update_ms=%.1f median_update_cpu_ms=%.3f "
        "mean_update_cpu_ms=%.3f p99_update_cpu_ms=%.3f max_update_cpu_ms=%.3f "
        "vertices_mean=%.0f vertices_min=%zu vertices_max=%zu faces_estimated_per_update=%.0f "
        "splits=%zu merges=%zu rebuilds=%zu frames=%d\n",
        options.dome ? "dome" : "terrain", options.decimating ? "adaptive-decimating" : "adaptive",
        mesh::live_faces(*shown), first_ms, cpu[cpu.size() / 2], mean,
        cpu[std::min(cpu.size() - 1, cpu.size() * 99 / 100)], cpu.back(), vertices / options.frames,
        fewest, most, double(estimated) / options.frames, splits, merges, rebuilds, options.frames);
    return 0;
}

}  // namespace aerial::tess
