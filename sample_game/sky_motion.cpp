// The cubemap sky's cache in motion: see sky_motion.hpp.
#include "sky_motion.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>

namespace sample {
namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

/// The largest difference between two sets of faces, in 8-bit steps.
int largest_difference(const std::array<std::vector<std::uint8_t>, 6>& a,
                       const std::array<std::vector<std::uint8_t>, 6>& b) {
    int most = 0;
    for (std::size_t f = 0; f < 6; ++f) {
        for (std::size_t k = 0; k < a[f].size() && k < b[f].size(); ++k)
            most = std::max(most, std::abs(int(a[f][k]) - int(b[f][k])));
    }
    return most;
}

}  // namespace

aerial::Result<SkyMotionReport> run_sky_motion(const SkyMotionOptions& o) {
    auto atmosphere = aerial::atmosphere_preset("earth");
    if (!atmosphere) return atmosphere.error();
    aerial::SkyCubemapCache cache(o.cache);
    SkyMotionReport r;
    std::array<std::vector<std::uint8_t>, 6> previous_fresh;
    double total_ms = 0, directions = 0;
    for (int i = 0; i < o.frames; ++i) {
        const double e = (o.start_sun_deg - o.sun_deg_per_frame * i) * kDegree;
        aerial::View view;
        view.eye = {0.0, 0.0, 500.0 + o.climb_m_per_frame * i};
        view.sun_dir = {std::cos(e) * 0.6, std::cos(e) * 0.8, std::sin(e)};
        const aerial::Display display{8.0f, aerial::ToneCurve::exponential};
        const int before = cache.recomputes();
        const auto start = std::chrono::steady_clock::now();
        auto changed = cache.update(*atmosphere, view, display);
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        total_ms += ms;
        if (i > 0) r.max_update_ms = std::max(r.max_update_ms, ms);
        if (!changed) return changed.error();
        const auto& s = cache.stats();
        directions += s.directions_last_update;
        if (i > 0) r.max_directions = std::max(r.max_directions, s.directions_last_update);
        r.max_bound_steps = std::max(r.max_bound_steps, s.bound_steps);
        if (i > 0 && cache.recomputes() != before)
            r.max_switch_steps = std::max(r.max_switch_steps, s.last_switch_steps);
        if (i % o.check_every == 0) {
            auto sky = aerial::prepare_sky(*atmosphere, view, o.cache.method);
            if (!sky) return sky.error();
            auto fresh = aerial::compute_sky_cubemap(*sky, o.cache.size);
            if (!fresh) return fresh.error();
            const auto codes = aerial::cubemap_to_rgba8(*fresh, display.exposure, display.tone);
            r.max_steps_from_fresh =
                std::max(r.max_steps_from_fresh, largest_difference(cache.rgba8(), codes));
            if (i > 0) {
                r.max_fresh_change_steps = std::max(
                    r.max_fresh_change_steps, double(largest_difference(previous_fresh, codes)));
            }
            previous_fresh = codes;
        }
    }
    {
        // A whole sky at once: the sun 5 degrees lower than the last frame's, beyond any lag.
        const double e = (o.start_sun_deg - o.sun_deg_per_frame * o.frames - 5.0) * kDegree;
        aerial::View view;
        view.eye = {0.0, 0.0, 500.0 + o.climb_m_per_frame * o.frames};
        view.sun_dir = {std::cos(e) * 0.6, std::cos(e) * 0.8, std::sin(e)};
        const auto start = std::chrono::steady_clock::now();
        auto changed = cache.update(*atmosphere, view, {8.0f, aerial::ToneCurve::exponential});
        if (!changed) return changed.error();
        r.whole_sky_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
    }
    r.frames = o.frames;
    r.recomputes = cache.recomputes();
    r.encodes = cache.stats().encodes;
    r.mean_directions = directions / std::max(1, o.frames);
    r.mean_update_ms = total_ms / std::max(1, o.frames);
    return r;
}

}  // namespace sample
