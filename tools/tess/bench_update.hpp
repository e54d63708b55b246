// aerial-tess --bench-update / --bench-dome: what a run-time mesh costs per frame.
//
//   terrain: a 224 x 224 grid (about 100k triangles) refined once, then a camera flying at 20 m/s,
//            40 m above the ground, 60 frames per second.
//   dome:    dome-sun10-g0.90 (tess_scenes.hpp) refined once, then the sun sinking at
//            `sun_deg_per_min` (0.25: real time), 60 frames per second.
// Each prints one line: the first update's time, then per later update the median, mean, 99th
// percentile and largest CPU time of this process (ms), the mesh's size and the work done. With
// `decimating` the mesh is a DecimatingMesh whose rebuilds run inside update() (so their CPU time
// is in the figures: the mean is the amortised cost on one core).
#pragma once

namespace aerial::tess {

struct BenchUpdateOptions {
    bool dome = false;
    bool decimating = false;
    int frames = 120;
    int relocate = -1;  ///< AdaptiveSettings::relocate (-1: the library's default)
    double sun_deg_per_min = 0.25;
    double rebuild_sun_deg = 0.25;  ///< adaptive-decimating's rebuild_sun_rad, in degrees
};

int bench_update(const BenchUpdateOptions& options);

}  // namespace aerial::tess
