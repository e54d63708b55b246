#include "soak.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "aerial/mesh.hpp"

namespace sample {
namespace {

/// The value in KiB of a "Name:   1234 kB" line of /proc/self/status.
std::size_t status_kib(const std::string& text, const char* name) {
    const std::size_t at = text.find(name);
    if (at == std::string::npos) return 0;
    return std::size_t(
        std::strtoull(text.c_str() + at + std::char_traits<char>::length(name), nullptr, 10));
}

/// The largest difference of two RGBA8 images on the colour channels, in 8-bit steps.
int max_difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    if (a.size() != b.size()) return 255;
    int worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (i % 4 == 3) continue;
        worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
    }
    return worst;
}

/// The image a renderer created now draws of `state` (fresh caches, fresh sky), with the soaked
/// game's stars: the set of visible stars is the application's cache (found again only when the
/// sun or the moon moved by half a degree), not the renderer's.
aerial::Result<std::vector<std::uint8_t>> fresh_render(const aerial::headless::Context& context,
                                                       const World& world, const FlightState& state,
                                                       const GameConfig& config,
                                                       const StarCache& stars) {
    auto game = make_game_renderer(context.api(), config);
    if (!game) return game.error();
    game.value().sky.night->stars = stars;
    auto outcome = render_frame(context.api(), game.value(), world, state, config);
    if (!outcome) return outcome.error();
    return context.read_rgba8();
}

/// memory_use() after handing the allocator's free pages back to the system (glibc's
/// malloc_trim): VmRSS then counts what the process holds, not the pages llvmpipe's binning of
/// the last frame and the last fresh render left free in the heap.
MemoryUse held_memory_use() {
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
    return memory_use();
}

}  // namespace

MemoryUse memory_use() {
    std::ifstream file("/proc/self/status");
    const std::string text((std::istreambuf_iterator<char>(file)),
                           std::istreambuf_iterator<char>());
    return {status_kib(text, "VmRSS:"), status_kib(text, "VmHWM:")};
}

std::string SoakReport::summary() const {
    char line[896];
    std::snprintf(
        line, sizeof line,
        "soak: %d frames rss_kib@%d=%zu hwm_kib@%d=%zu rss_kib@%d=%zu hwm_kib@%d=%zu "
        "rss_floor_kib@%d..%d=%zu rss_floor_kib@%d..%d=%zu "
        "growth_kib=%lld margin_kib=%zu memory=%s comparisons=%d worst_lsb=%d "
        "(frame %d) tolerance_lsb=%d frames=%s tess_max_vertices=%zu tess_budget=%zu "
        "tess_budget_frames=%d tess_max_slots=%zu tess_compactions=%d tessellation=%s "
        "mean_ms=%.2f",
        frames, baseline_frame, rss_baseline_kib, baseline_frame, hwm_baseline_kib, frames,
        rss_end_kib, frames, hwm_end_kib, baseline_frame - floor_frames + 1, baseline_frame,
        rss_floor_baseline_kib, frames - floor_frames + 1, frames, rss_floor_end_kib,
        (long long)rss_floor_end_kib - (long long)rss_floor_baseline_kib, rss_margin_kib,
        memory_flat() ? "flat" : "GROWING", comparisons, worst_lsb, worst_frame, tolerance_lsb,
        frames_match() ? "match" : "DIFFER", tessellation_max_vertices, tessellation_budget,
        tessellation_budget_frames, tessellation_max_slots, tessellation_compactions,
        tessellation_within_budget() ? "within" : "OVER", mean_ms);
    return line;
}

aerial::Result<SoakReport> run_soak(const World& world, GameConfig config,
                                    const SoakOptions& options) {
    config.readout = false;
    auto context = aerial::headless::Context::create({options.gl, config.width, config.height});
    if (!context) return context.error();
    const aerial::gl::Api& api = context->api();
    auto game = make_game_renderer(api, config);
    if (!game) return game.error();
    const SkySetup* sky = &game.value().sky;
    config.sky = sky->used;

    SoakReport report;
    report.frames = options.frames;
    report.baseline_frame = std::clamp(options.baseline_frame, 1, options.frames);
    report.rss_margin_kib = options.rss_margin_kib;
    // The policy reuses colours within its error target by design; the fresh render rounds once.
    report.tolerance_lsb = 1 + (config.policy ? int(std::ceil(config.error_target_lsb)) : 0);
    report.tessellation_budget = options.tessellation_budget;
    // The adaptive dome: 80 km around the middle of the terrain, refined for the eye and sun of
    // each frame where its interpolated sky colour would be more than 1 LSB off (created at the
    // first frame, with that frame's exposure).
    std::optional<aerial::mesh::AdaptiveMesh> dome;
    const int period = 2 * std::max(1, options.leg_frames);
    // The floors: the lowest RSS over one round trip (the same views) ending at the baseline frame
    // and ending at the last frame.
    report.floor_frames = std::min(period, report.baseline_frame);
    const auto lowest = [](std::size_t& floor, std::size_t rss) {
        if (floor == 0 || rss < floor) floor = rss;
    };
    double total_ms = 0.0;
    for (int i = 0; i < options.frames; ++i) {
        const int phase = i % period;
        const double t = phase <= period / 2 ? double(phase) / (period / 2)
                                             : double(period - phase) / (period / 2);
        const FlightState state = flight_at(world, t, config.sun);
        auto outcome = render_frame(api, game.value(), world, state, config);
        if (!outcome) {
            return aerial::Error{"frame",
                                 "frame " + std::to_string(i) + ": " + outcome.error().message};
        }
        total_ms += outcome->milliseconds;
        if (options.tessellation_budget > 0) {
            if (!dome) {
                aerial::mesh::DomeOptions shape;
                auto base = aerial::mesh::geodesic_dome(8, shape);
                if (!base) return base.error();
                aerial::mesh::AdaptiveSettings settings;
                settings.max_vertices = options.tessellation_budget;
                settings.colour.display = outcome->settings.display;
                settings.colour.texel = glm::vec3(0.0f);
                auto made = aerial::mesh::AdaptiveMesh::create(
                    std::move(base).value(), aerial::mesh::Surface::sphere(shape), settings);
                if (!made) return made.error();
                dome.emplace(std::move(made).value());
            }
            aerial::View view;
            view.eye = camera_for(world, state, double(config.width) / config.height).eye;
            view.sun_dir = outcome->settings.sun_dir;
            view.up = outcome->settings.up;
            auto frame = aerial::prepare_frame<float>(outcome->settings.atmosphere, view,
                                                      aerial::Model::height);
            if (!frame) return frame.error();
            const aerial::mesh::UpdateStats stats = dome->update(*frame);
            report.tessellation_max_vertices =
                std::max(report.tessellation_max_vertices, stats.vertices);
            if (!stats.complete) ++report.tessellation_budget_frames;
            // No compact() here: the update compacts the mesh itself (compact_garbage_ratio).
            report.tessellation_max_slots =
                std::max(report.tessellation_max_slots, dome->mesh().n_vertices());
            report.tessellation_compactions += stats.compacted;
        }
        if (sky->stats && !sky->stats->error.empty()) {
            return aerial::Error{"sky", "frame " + std::to_string(i) + ": " + sky->stats->error};
        }
        if (!sky->night->stats->error.empty()) {
            return aerial::Error{
                "sky", "frame " + std::to_string(i) + ": night sky: " + sky->night->stats->error};
        }
        const bool last = i + 1 == options.frames;
        // The first frame too: the fresh renderer's allocations are then part of the baseline.
        if (i == 0 || (i + 1) % std::max(1, options.compare_every) == 0 || last) {
            const std::vector<std::uint8_t> soaked = context->read_rgba8();
            auto fresh = fresh_render(*context, world, state, config, sky->night->stars);
            if (!fresh) {
                return aerial::Error{"fresh", "fresh render of frame " + std::to_string(i) + ": " +
                                                  fresh.error().message};
            }
            const int lsb = max_difference(soaked, *fresh);
            ++report.comparisons;
            if (lsb > report.worst_lsb || report.worst_frame < 0) {
                report.worst_lsb = std::max(report.worst_lsb, lsb);
                if (lsb == report.worst_lsb) report.worst_frame = i;
            }
        }
        const int done = i + 1;
        const bool in_baseline_trip =
            done > report.baseline_frame - report.floor_frames && done <= report.baseline_frame;
        const bool in_last_trip = done > options.frames - report.floor_frames;
        if (in_baseline_trip || in_last_trip) {
            const MemoryUse m = held_memory_use();
            if (in_baseline_trip) lowest(report.rss_floor_baseline_kib, m.rss_kib);
            if (in_last_trip) lowest(report.rss_floor_end_kib, m.rss_kib);
            if (done == report.baseline_frame) {
                report.rss_baseline_kib = m.rss_kib;
                report.hwm_baseline_kib = m.hwm_kib;
            }
        }
    }
    const MemoryUse m = held_memory_use();
    report.rss_end_kib = m.rss_kib;
    report.hwm_end_kib = m.hwm_kib;
    report.mean_ms = total_ms / options.frames;
    return report;
}

}  // namespace sample
