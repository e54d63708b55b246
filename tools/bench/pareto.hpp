// aerial-bench --out: speed against accuracy (issue 7). Every method of the module and the two
// fog baselines render the bench scenes on one headless context; frames are timed best of
// several repetitions, interleaved (each repetition runs every method once, so load on a shared
// machine hits all alike); each image is compared with the per-pixel image of the `reference`
// model of the same mesh.
//
// How to use this:
//   1. `auto scenes = load_bench_scenes(dir, quick);` reads DIR/*.json (see load_bench_scene).
//   2. `auto rows = run_bench(scenes, options, progress);` gives one row per (scene, method,
//      tessellation, vertices); `write_bench_csv(path, rows)` writes them.
//   3. `summarise(rows)` gives the lines of the checks (printed, and in summary.txt).
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "aerial/error.hpp"
#include "aerial/scene_file.hpp"

namespace aerial::bench {

/// A bench scene file (JSON object; unknown fields are errors):
///   "scene": {...}               a scene file (aerial/scene_file.hpp), required
///   "description": "..."         one line, optional
///   "quick": false               part of the --quick run
///   "sky_dome_radius": r         draw a geodesic sky dome of this radius (engine units) around
///                                the eye instead of the scene's geometry (> 0; the scene's far
///                                plane must lie beyond it; the scene format requires geometry,
///                                which is then not drawn)
///   "sky_dome_frequency": 32     the dome's default geodesic frequency, 2 .. 256
/// The scene's terrain.resolution is the default tessellation of terrain scenes.
struct BenchScene {
    std::string name;  ///< the file name without .json
    std::string description;
    bool quick = false;
    scene::SceneFile scene;
    double sky_dome_radius = 0.0;  ///< 0: the terrain
    int sky_dome_frequency = 32;
};

/// Errors start with the path and name the field.
Result<BenchScene> load_bench_scene(const std::string& path);
/// The *.json files of `dir` in name order (only those marked quick when `quick`). Error: the
/// directory cannot be read, holds no scene, or a file is bad.
Result<std::vector<BenchScene>> load_bench_scenes(const std::string& dir, bool quick);

struct BenchOptions {
    bool quick = false;
    int width = 160, height = 120;  ///< image size, pixels
    int repetitions = 21;           ///< timed frames per variant; the best is kept
    std::string images_dir;         ///< where to write the default mesh's images (empty: none)
};

struct BenchRow {
    std::string scene, method, tessellation;
    std::size_t vertices = 0;
    double ms_per_frame = 0.0;
    int max_lsb = 0, p99_lsb = 0;
    double rmse_lsb = 0.0, de2000_mean = 0.0;
    bool default_mesh = false;  ///< drawn on the scene's default tessellation
};

/// The method names, in the order the CSV lists them.
const std::vector<std::string>& bench_method_names();

/// Runs the bench; progress lines go to `progress` (one per scene step and per variant).
Result<std::vector<BenchRow>> run_bench(const std::vector<BenchScene>& scenes,
                                        const BenchOptions& options, std::FILE* progress);

/// The CSV header: scene,method,tessellation,vertices,ms_per_frame,max_lsb,p99_lsb,rmse_lsb,
/// de2000_mean.
std::optional<std::string> write_bench_csv(const std::string& path,
                                           const std::vector<BenchRow>& rows);

/// Per scene: arb-hp against gl-fog frame time (same mesh), the lowest per-vertex error against
/// gl-fog's, and how many rows of that row's method (our best method) are on the Pareto front of
/// (ms_per_frame, rmse_lsb), and whether that most accurate row itself is; one line each, then
/// one line per check over all scenes.
std::vector<std::string> summarise(const std::vector<BenchRow>& rows);

}  // namespace aerial::bench
