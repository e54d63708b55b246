// The scenes aerial-tess grades, as data: a JSON file (--scenes FILE) in place of the built-in
// list, and the built-in list written out as such a file (--list-scenes).
//
// How to use this:
//   `auto specs = read_scene_list(text);` then build each scene from its SceneSpec; errors name
//   the field ("scenes[2].sun_elevation_deg: expected a number in [-10, 90], got 95").
//
// The file: {"scenes": [{"kind": "dome", "sun_elevation_deg": 10, "mie_g": 0.9},
//                       {"kind": "terrain", "eye_m": 300, "sun_elevation_deg": 10}]}
// with optional "name" and "preset" (default earth for domes, hazy for terrain); unknown fields
// are an error.
#pragma once

#include <string>
#include <vector>

#include "aerial/error.hpp"

namespace aerial::tess {

struct SceneSpec {
    std::string kind;    ///< "dome" or "terrain"
    std::string name;    ///< empty: made from the parameters
    std::string preset;  ///< empty: earth (dome), hazy (terrain)
    double sun_elevation_deg = 10.0;
    double mie_g = 0.0;    ///< dome: the haze's g (0: the preset's)
    double eye_m = 300.0;  ///< terrain: the eye above the ground
};

Result<std::vector<SceneSpec>> read_scene_list(const std::string& json_text);
std::string write_scene_list(const std::vector<SceneSpec>& specs);

}  // namespace aerial::tess
