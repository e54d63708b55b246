// sample_game/sky_motion.hpp — the cubemap sky's cache in real-time motion
// (aerial-scene-bench --sky-motion): the sun and the eye moving a little each frame, as in a
// game, and what aerial::SkyCubemapCache does about it: how often and how much it recomputes,
// how far its texels are from a sky computed afresh, and how much they jump when a recomputed
// sky is shown (popping).
#pragma once

#include "aerial/error.hpp"
#include "aerial/sky.hpp"

namespace sample {

struct SkyMotionOptions {
    int frames = 600;
    double sun_deg_per_frame = 0.01;  ///< the sun sinking (a day of 10 minutes at 30 frames/s)
    double climb_m_per_frame = 1.0;   ///< the eye climbing
    double start_sun_deg = 20.0;
    int check_every = 10;  ///< frames between comparisons with a fresh sky
    aerial::SkyCubemapCache::Options cache = {32, aerial::SkyMethod::height_chained};
};

struct SkyMotionReport {
    int frames = 0, recomputes = 0, encodes = 0;
    double mean_directions = 0;    ///< sky directions evaluated a frame
    int max_directions = 0;        ///< after the first frame (which makes the whole sky)
    double max_bound_steps = 0;    ///< the cache's own bound on how far its texels are off
    double max_switch_steps = 0;   ///< largest texel change when a new sky was shown
    int max_steps_from_fresh = 0;  ///< largest texel difference to a fresh sky (checked frames)
    double max_fresh_change_steps = 0;  ///< largest change of the fresh sky between checks
    double mean_update_ms = 0;
    /// The slowest update after the first (which also builds tables): a whole sky made at once
    /// when the motion demands it, else the most a spread recompute took in one frame.
    double max_update_ms = 0;
    /// A whole sky made and encoded at once, after the motion (the time-lapse's case), ms.
    double whole_sky_ms = 0;
};

/// Flies options.frames frames over the `earth` preset at 500 m with the sample's exposure.
aerial::Result<SkyMotionReport> run_sky_motion(const SkyMotionOptions& options);

}  // namespace sample
