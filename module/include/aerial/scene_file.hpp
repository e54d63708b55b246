// aerial/scene_file.hpp — the scene file: a camera, a sun, an atmosphere, a model, a display and
// procedural geometry (a textured terrain height field and boxes) in JSON, all deterministic, so
// that a scene file plus a backend gives the same image on every run (the golden images, the
// speed-against-accuracy chart and the tessellation tools rely on it). aerial-render draws it.
//
// How to use this:
//   1. `auto file = aerial::scene::load_scene_file(path);` (or scene_file_from_json(text)); the
//      error names the field ("camera.fov_y_deg", "terrain.resolution", "boxes[1].size", ...) and
//      the bad value, as the atmosphere JSON does.
//   2. `auto root = aerial::scene::scene_graph(*file);` is the scene as a graph (one textured mesh
//      node, unlit); `file->frame_settings()` and `file->camera_for(width, height)` are what
//      SceneRenderer::render takes with it.
//   3. Tools that tessellate the surface themselves use terrain_height, scene_geometry and
//      scene_texture directly.
//
// The format (JSON object; every field optional unless marked; unknown fields are errors):
//   "camera": {
//     "eye": [x, y, z]             engine units; default [0, 0, 300]
//     "look_at": [x, y, z]         a point to look at, or
//     "direction": [x, y, z]       a direction to look in (exactly one of the two; required)
//     "up": [x, y, z]              default [0, 0, 1]
//     "fov_y_deg": 50              vertical field of view, degrees, (0, 180)
//     "near": 10, "far": 100000    clip planes, engine units, 0 < near < far
//   }
//   "sun": {"direction": [x, y, z]}  towards the sun (normalised), or
//          {"elevation_deg": e, "azimuth_deg": a}  azimuth clockwise from +y towards +x
//          (required)
//   "atmosphere": "earth"          a preset name (earth, hp2002, hazy, foggy, mars), or an object
//                                  with the atmosphere JSON fields (missing ones are earth's);
//                                  default "earth"
//   "model": "hoffman-preetham"    or "height" (reference is far too slow per pixel)
//   "display": {"exposure": 8, "tone": "clamp" | "exponential"}  L_in times exposure, then the
//                                  tone curve (aerial::Display); default 8, clamp
//   "meters_per_unit": 1           engine units to metres, > 0
//   "background": [r, g, b]        clear colour in [0, 1] where no geometry is; default 0, 0, 0
//   "texture": {
//     "kind": "checker" | "noise"  default "checker"
//     "size": 64                   texels per side, a power of two 2 .. 1024
//     "cells": 8                   checker cells per side (a divisor of size)
//     "colors": [[r, g, b], [r, g, b]]  the two colours in [0, 1] (8-bit sRGB display values)
//     "seed": 1                    noise seed, integer >= 0
//   }
//   "terrain": {                   a height field on the z = 0 plane (z up); absent: none
//     "center": [x, y]             default [0, 0]
//     "size": 20000                side of the square, engine units, > 0
//     "resolution": 64             cells per side, 1 .. 1024
//     "height_amplitude": 300      largest height above z = 0, engine units, >= 0 (0: a flat
//                                  ground plane)
//     "feature_size": 5000         size of the largest hills, engine units, > 0
//     "seed": 1                    integer >= 0
//     "octaves": 6                 of the fractal noise (scene::procedural_height), 1 .. 12
//     "texture_repeat": 2000       engine units per repetition of the texture, > 0
//   }
//   "boxes": [{"center": [x, y, z], "size": [sx, sy, sz], "subdivisions": 4}, ...]
//                                  axis-aligned, textured with the same texture, each face split
//                                  into subdivisions × subdivisions quads (1 .. 64)
// The world's up axis is +z and sea level is z = 0 (aerial::View's defaults). Later scene
// graphs will add fields; files written for this version stay valid.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"
#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"

namespace aerial::scene {

enum class TextureKind { checker, noise };
/// "checker", "noise".
const char* texture_kind_name(TextureKind kind);
Result<TextureKind> parse_texture_kind(std::string_view name);

struct TextureSpec {
    TextureKind kind = TextureKind::checker;
    int size = 64;
    int cells = 8;
    glm::dvec3 colors[2] = {{0.32, 0.42, 0.22}, {0.55, 0.52, 0.40}};
    std::uint32_t seed = 1;
};

struct TerrainSpec {
    glm::dvec2 center{0.0, 0.0};
    double size = 20000.0;
    int resolution = 64;
    double height_amplitude = 300.0;
    double feature_size = 5000.0;
    std::uint32_t seed = 1;
    int octaves = 6;
    double texture_repeat = 2000.0;
};

struct BoxSpec {
    glm::dvec3 center{0.0};
    glm::dvec3 size{100.0};
    int subdivisions = 4;
};

struct SceneFile {
    /// The file's camera; `aspect` is the viewport's, not the file's (camera_for sets it).
    Camera camera = default_camera();
    glm::dvec3 sun_dir{0.0, 0.0, 1.0};  ///< unit, towards the sun
    Atmosphere atmosphere;
    Model model = Model::hoffman_preetham;
    Display display{8.0f, ToneCurve::clamp};
    double meters_per_unit = 1.0;
    glm::dvec3 background{0.0};
    TextureSpec texture;
    std::optional<TerrainSpec> terrain;
    std::vector<BoxSpec> boxes;

    /// The camera of a file without one: eye (0, 0, 300), 50 degrees, near 10, far 100000.
    static Camera default_camera();
    /// The aerial::View of this scene (world up +z).
    View view() const;
    /// The camera with the aspect ratio of a width x height viewport.
    Camera camera_for(int width, int height) const;
    /// What SceneRenderer::render takes: the scene's atmosphere, sun, display and model, world
    /// up +z, the update policy off (every node shaded with `model` every frame) and no sky.
    FrameSettings frame_settings() const;
};

/// Parses a scene file; errors name the field (dotted path, "boxes[1].size") and the value.
Result<SceneFile> scene_file_from_json(std::string_view json_text);
/// Reads and parses a file; errors start with the path.
Result<SceneFile> load_scene_file(const std::string& path);

/// Height of the terrain at (x, y), engine units: the surface scene_geometry samples at its
/// grid vertices, procedural_height (aerial/scene.hpp) with the spec's seed, amplitude, feature
/// size and octaves, in [0, height_amplitude].
double terrain_height(const TerrainSpec& terrain, double x, double y);

/// The terrain and the boxes of the scene as one mesh (positions, texture coordinates).
MeshData scene_geometry(const SceneFile& scene);

/// The scene's RGB8 texture (level 0; SceneRenderer builds the mipmaps with mipmap_levels).
Texture scene_texture(const TextureSpec& spec);

/// The scene as a graph: a group "scene" holding one mesh node "geometry" (scene_geometry with
/// scene_texture).
std::unique_ptr<Node> scene_graph(const SceneFile& scene);

}  // namespace aerial::scene
