// sample_game/soak.hpp — the sample game headless for many frames: memory stays flat and a
// long-lived renderer draws what a fresh one draws.
//
// How to use this:
//   1. Fill SoakOptions (frames, the frame that ends the baseline round trip, how often to
//      compare).
//   2. `auto report = run_soak(world, config, options);` with no current context: it creates its
//      own headless context of config.width x config.height and renders without writing files.
//   3. report->passed() is true when the lowest RSS of the last round trip of the flight stays
//      within options.rss_margin_kib of the lowest RSS of the round trip that ends at the
//      baseline frame, and every compared frame is within report->tolerance_lsb of a fresh
//      render; report->summary() is the one line to print.
//
// How memory is measured: after glibc's malloc_trim (the free pages that llvmpipe's binning of a
// frame, tens of MiB at 480x270, and a fresh renderer's comparison frame leave in the heap go
// back to the system), VmRSS after each frame of two round trips of the flight (the same views:
// a round trip goes through each view twice); the lowest of each is compared. What is held
// between frames still depends on the view and on llvmpipe (below), not on the frame count;
// memory that grows with the frame count raises the lowest value.
#pragma once

#include <cstddef>
#include <string>

#include "aerial/headless.hpp"
#include "game.hpp"
#include "world.hpp"

namespace sample {

struct SoakOptions {
    int frames = 600;
    /// The frame that ends the baseline round trip (clamped to frames): the caches and the
    /// allocator have settled by then.
    int baseline_frame = 1000;
    /// frames between comparisons with a fresh render, >= 1 (the first and last frames too)
    int compare_every = 100;
    /// frames of one flight leg: t goes 0 -> 1 and back every 2 * leg_frames (sun and camera move)
    int leg_frames = 500;
    /// Allowed growth of the lowest VmRSS of a round trip after the baseline round trip. Above
    /// what llvmpipe holds between frames in the 64 KiB data blocks of its binned scenes, which
    /// comes and goes over hundreds of frames whatever the frame count: 11 MiB for about 1 000
    /// frames of a 10 000-frame soak under heaptrack, a floor 21 MiB up in one of five
    /// 160-frame soaks (480x270, 33 x 33 tiles).
    std::size_t rss_margin_kib = 32768;
    /// An adaptive sky dome (aerial::mesh::AdaptiveMesh, 1 LSB split target) refined every frame
    /// for the flight's eye and sun within this vertex budget; 0: none.
    std::size_t tessellation_budget = 3000;
    aerial::headless::Platform gl = aerial::headless::Platform::osmesa;
};

struct SoakReport {
    int frames = 0;
    int baseline_frame = 0;
    std::size_t rss_baseline_kib = 0, hwm_baseline_kib = 0;  ///< VmRSS, VmHWM at baseline_frame
    std::size_t rss_end_kib = 0, hwm_end_kib = 0;            ///< VmRSS, VmHWM after the last
    /// The lowest VmRSS (after malloc_trim) after a frame of the round trip that ends at
    /// baseline_frame, and of the last round trip (floor_frames frames each).
    std::size_t rss_floor_baseline_kib = 0, rss_floor_end_kib = 0;
    int floor_frames = 0;
    std::size_t rss_margin_kib = 0;
    int comparisons = 0;
    int worst_lsb = 0;      ///< largest 8-bit difference of a compared frame to a fresh render
    int worst_frame = -1;   ///< the frame where worst_lsb was seen
    int tolerance_lsb = 1;  ///< 1, plus the policy's error target when the policy is on
    double mean_ms = 0.0;   ///< mean render time of the soak frames
    std::size_t tessellation_budget = 0;        ///< SoakOptions::tessellation_budget
    std::size_t tessellation_max_vertices = 0;  ///< most live vertices after any update
    int tessellation_budget_frames = 0;         ///< frames where the budget stopped refinement
    /// Most vertex slots of the dome's mesh (live and deleted) after any update, and the updates
    /// that compacted it (AdaptiveMesh compacts itself).
    std::size_t tessellation_max_slots = 0;
    int tessellation_compactions = 0;
    bool memory_flat() const {
        return rss_floor_end_kib <= rss_floor_baseline_kib + rss_margin_kib;
    }
    bool frames_match() const { return worst_lsb <= tolerance_lsb; }
    bool tessellation_within_budget() const {
        return tessellation_max_vertices <= tessellation_budget;
    }
    bool passed() const { return memory_flat() && frames_match() && tessellation_within_budget(); }
    std::string summary() const;
};

/// VmRSS and VmHWM of this process in KiB, from /proc/self/status (0 where unavailable).
struct MemoryUse {
    std::size_t rss_kib = 0, hwm_kib = 0;
};
MemoryUse memory_use();

/// Renders options.frames frames of the flight going back and forth (config.readout is ignored:
/// no readout, which shows timings). Errors: the context, the renderer or a frame failed.
aerial::Result<SoakReport> run_soak(const World& world, GameConfig config,
                                    const SoakOptions& options);

}  // namespace sample
