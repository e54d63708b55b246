// aerial-tess --path: schemes compared in motion. Every frame of each scene's path (the sun and
// the eye moving, aerial/validation/tess_scenes.hpp) is graded for every method: the error
// against the per-pixel reference, the time the method's mesh took to follow the frame, and a
// popping measure.
//
// How to use this:
//   `run_path_mode(specs, grader, options, out_dir)` writes OUT/path.csv and OUT/path_summary.txt
//   (printed too) and returns the process exit status.
//
// Methods: on domes the run-time `adaptive` and `adaptive-relocate` meshes (AdaptiveMesh::update
// each frame, split threshold 1 step), `adaptive-decimating` (DecimatingMesh at a bound of 1 step,
// rebuilt inside the update every rebuild_sun_deg of the sun), a `uniform-geodesic` dome of a fixed
// frequency and the `decimated` dome made once at frame 0 (offline: it does not follow the sun); on
// terrain the run-time `adaptive` mesh and `uniform-distance-lod` rebuilt around the eye every
// frame; your own meshes (--mesh) as they are, every frame. Popping: per pixel covered in two
// consecutive frames, how much more its drawn colour changed than its reference colour did, max(0,
// |drawn_t - drawn_t-1| - |ref_t - ref_t-1|) over R, G, B; popping_lsb is the largest over the
// pixels, pop_over1 the fraction of them above 1 step.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "aerial/scene.hpp"
#include "aerial/validation/mesh_grader.hpp"
#include "aerial/validation/tess_scenes.hpp"

namespace aerial::tess {

struct PathOptions {
    int geodesic_frequency = 48;    ///< the uniform dome's frequency
    int lod_cells = 32;             ///< the distance LOD's cells per side
    double rebuild_sun_deg = 0.25;  ///< adaptive-decimating's rebuild_sun_rad, in degrees
    /// --mesh: (file stem, triangles) graded as method `own_method` on the scenes of their kind.
    std::vector<std::pair<std::string, scene::MeshData>> own_meshes;
    std::string own_method;
    bool builtin = true;  ///< grade the built-in methods (--no-builtin: off)
};

int run_path_mode(const std::vector<validation::TessSceneSpec>& specs,
                  validation::MeshGrader& grader, const PathOptions& options,
                  const std::string& out_dir);

}  // namespace aerial::tess
