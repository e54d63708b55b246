// aerial/validation/tess_scenes.hpp — the scenes aerial-tess grades meshes on, as data: a sky
// dome or a terrain, with its atmosphere, sun, eye, display and where the reference is taken.
//
// How to use this:
//   1. Specs: `builtin_tess_scenes(false)` (aerial-tess's default list), or
//      `read_tess_scenes(json_text)` for a file of your own; `write_tess_scenes(specs)` writes
//      them back (aerial-tess --list-scenes).
//   2. `auto scene = make_tess_scene(spec);` gives the frame, the colour options, the dome or the
//      terrain's height field, and the grading setting (scene->setting) MeshGrader takes
//      (mesh_grader.hpp).
//   3. `tess_scene_fits(*scene, data)`: whether a mesh read from a file is of the scene's kind (a
//      dome's vertices lie on its sphere).
//
// The file: {"scenes": [{"kind": "dome", "sun_elevation_deg": 10, "mie_g": 0.9},
//                       {"kind": "terrain", "eye_m": 300, "sun_elevation_deg": 10}]}
// with optional "name" and "preset" (default earth for domes, hazy for terrain) and an optional
// "path" (aerial-tess --path): {"frames": 48, "sun_elevation_end_deg": 2, "sun_azimuth_end_deg":
// 0, "eye_move_m": [1200, 0]}, the sun and (on terrain) the eye moving linearly from the scene's
// start over that many frames. Unknown fields are an error naming them.
//
// Dome: eye 2 m above sea level, a dome of 80 km around it showing L_in only (texel 0), the
// exponential tone curve; the exposure puts the sky 30 degrees up and 90 degrees from the sun in
// azimuth at 0.5. Terrain: 20 km of rolling hills (100 m, 3 km wavelength, the eye above the
// origin), texel 0.6, exponential tone; the exposure puts L_in of the ground 10 km away towards
// the sun at 0.4. The sun at azimuth 0 (along +x), z up, the `height` model.
#pragma once

#include <string>
#include <vector>

#include "aerial/error.hpp"
#include "aerial/mesh.hpp"
#include "aerial/scene.hpp"
#include "aerial/validation/mesh_grader.hpp"

namespace aerial::validation {

/// A motion over a scene: the sun and the eye go linearly from the scene's start to these ends
/// over `frames` frames (frame 0 is the start, frames - 1 the end).
struct TessPath {
    int frames = 0;                       ///< 0: a still; else 2 .. 10000
    double sun_elevation_end_deg = 10.0;  ///< -10 .. 90
    double sun_azimuth_end_deg = 0.0;     ///< -360 .. 360; the sun starts at azimuth 0 (+x)
    /// Terrain only: the eye's horizontal move over the path (m, x and y, each within 10 km); it
    /// stays eye_m above the ground under it.
    double eye_move_m[2] = {0.0, 0.0};
};

struct TessSceneSpec {
    std::string kind;                 ///< "dome" or "terrain"
    std::string name;                 ///< empty: made from the parameters ("dome-sun10-g0.90")
    std::string preset;               ///< empty: earth (dome), hazy (terrain)
    double sun_elevation_deg = 10.0;  ///< -10 .. 90
    double mie_g = 0.0;               ///< dome: the haze's g (0: the preset's), 0 .. 0.999
    double eye_m = 300.0;             ///< terrain: the eye above the ground, 0.5 .. 20000
    TessPath path;                    ///< path.frames 0: no path
};

/// Errors name the field: "aerial::validation::read_tess_scenes(): scenes[2].sun_elevation_deg:
/// expected a number in [-10, 90], got 95".
Result<std::vector<TessSceneSpec>> read_tess_scenes(const std::string& json_text);
std::string write_tess_scenes(const std::vector<TessSceneSpec>& specs);

/// aerial-tess's default paths (--path without --scenes): dome-sun10-g0.90 with the sun sinking
/// to 2 degrees, and terrain-eye300-sun10 flown 1200 m towards the sun, each over 48 frames.
std::vector<TessSceneSpec> builtin_tess_paths();

/// aerial-tess's default scenes: domes at g 0.76 and 0.90 with the sun at 2, 10, 30 and 60
/// degrees; terrain seen from 2, 300 and 3000 m with the sun at 10 and 60 degrees. With `quick`,
/// its quick run's three (dome-sun10-g0.76, dome-sun10-g0.90, terrain-eye300-sun10).
std::vector<TessSceneSpec> builtin_tess_scenes(bool quick);

struct TessScene {
    std::string name;
    bool dome = true;
    mesh::DomeOptions dome_options;  ///< the dome's sphere (domes)
    mesh::Heightfield field;         ///< the ground (terrain)
    GradeSetting setting;            ///< frame, colour options and grading options
};

/// The scene a spec describes; with `frame`, that frame of its path (0 .. path.frames - 1): the
/// sun and eye moved, the display (exposure) of frame 0 kept, so that what changes on screen is
/// the light and the mesh. Errors: the spec's fields out of range (as read_tess_scenes names
/// them), an unknown preset, a frame outside the path.
Result<TessScene> make_tess_scene(const TessSceneSpec& spec, int frame = 0);

/// Whether a mesh is of the scene's kind: a dome's vertices all lie on its sphere (within 1 % of
/// the radius); any other mesh is terrain.
bool tess_scene_fits(const TessScene& scene, const scene::MeshData& data);

}  // namespace aerial::validation
