// aerial/adaptive_scene.hpp — adaptive meshes (aerial/mesh.hpp) in the scene graph: mesh and
// terrain nodes whose triangles SceneRenderer refines for the view every frame, a sky dome drawer
// refined the same way, and OpenMesh meshes as MeshData.
//
// How to use this:
//   Terrain: build an aerial::mesh::AdaptiveMesh (terrain_grid + Surface::terrain), then
//     `root->add(aerial::scene::make_adaptive_terrain("ground", adaptive, texture, 250.0));`
//     Each frame SceneRenderer::render calls adaptive->update() with a frame of
//     FrameSettings::model at the camera, rebuilds the node's arrays when the mesh changed,
//     shades every vertex with that model, morphs the colours of new and vanishing vertices
//     (AdaptiveMesh::morph_into) and draws the live faces.
//   Sky: `renderer.set_sky_drawer(aerial::scene::adaptive_sky_drawer());` with a sky-dome node in
//     the graph: a geodesic dome refined to the colour error of the sky it shows.
//   A mesh refined offline: `aerial::scene::mesh_data_from(adaptive.mesh(), 250.0)`.
//
// Adaptive nodes are in world coordinates: their world transform must be the identity (the
// renderer names the node otherwise). The update policy may skip them (negligible scattering)
// but never reuses their colours, which morph. The arb backend draws the refined mesh with its
// program: there the colours of new vertices show at once (no morph).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "aerial/mesh.hpp"
#include "aerial/scene.hpp"
#include "aerial/scene_renderer.hpp"

namespace aerial::scene {

/// An OpenMesh mesh as MeshData: every vertex slot, deleted ones too (so that array index =
/// vertex handle, as AdaptiveMesh::morph_into expects), and the live faces. Texture coordinates
/// (x / texture_repeat, y / texture_repeat) when texture_repeat > 0; unit vertex normals (the
/// area-weighted normals of the adjacent live faces; +z for a vertex without any) when `normals`.
MeshData mesh_data_from(const mesh::Mesh& mesh, double texture_repeat = 0.0, bool normals = false);

/// A mesh node (drawn unlit) whose geometry is `adaptive`, refined by the renderer.
std::unique_ptr<Node> make_adaptive_mesh(std::string name,
                                         std::shared_ptr<mesh::AdaptiveMesh> adaptive,
                                         std::shared_ptr<const Texture> texture = nullptr,
                                         double texture_repeat = 0.0);
/// A terrain node (lit by sun and sky, normals from the refined mesh) whose geometry is
/// `adaptive`, refined by the renderer.
std::unique_ptr<Node> make_adaptive_terrain(std::string name,
                                            std::shared_ptr<mesh::AdaptiveMesh> adaptive,
                                            std::shared_ptr<const Texture> texture = nullptr,
                                            double texture_repeat = 0.0,
                                            glm::vec3 albedo = glm::vec3(1.0f));

/// The adaptive sky dome: a geodesic dome of `base_frequency` around the eye's first position,
/// `radius_m` for shading (past the atmosphere overhead, a long path at the horizon), refined to
/// `split_lsb` steps of colour error with the height model, drawn at half the far plane around
/// the eye. Each vertex shows L_in (on a black primary, through the renderer's fixed-function
/// path), morphed over `morph_updates` updates. A skirt below the open horizon (a ring down to
/// `skirt_depression_deg`, then a fan to the nadir) keeps the eye, above the terrain, from seeing
/// past the terrain's edge where nothing is drawn.
struct AdaptiveSkyOptions {
    double radius_m = 400000.0;  ///< > 0
    int base_frequency = 4;      ///< 1 .. 2048
    float split_lsb = 1.0f;      ///< > 0
    int morph_updates = 8;       ///< >= 1
    std::size_t max_vertices = 20000;
    double time_slice_ms = 4.0;          ///< refinement time per frame (0: unlimited)
    double skirt_depression_deg = 30.0;  ///< [0, 90]
};

/// What the adaptive sky did in the last frame.
struct AdaptiveSkyStats {
    std::size_t vertices = 0;  ///< live vertices of the dome
    double update_ms = 0.0;    ///< its refinement and coarsening
    std::string error;         ///< set when the dome could not be built, shaded or drawn
};

/// The drawer (SceneRenderer::set_sky_drawer). `stats`, when given, is filled every frame.
SkyDrawer adaptive_sky_drawer(const AdaptiveSkyOptions& options = {},
                              std::shared_ptr<AdaptiveSkyStats> stats = nullptr);

}  // namespace aerial::scene
