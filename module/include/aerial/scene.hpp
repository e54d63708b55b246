// aerial/scene.hpp — a small scene graph for engines that adopt or mirror their nodes: groups,
// transforms, meshes (positions, normals, texcoords, a texture), terrain tiles, a sky dome and a
// sun. aerial/scene_renderer.hpp draws it with F_ex and L_in applied.
//
// How to use this:
//   1. `auto root = aerial::scene::make_group("world");`
//   2. Add children: `root->add(aerial::scene::make_mesh("house", mesh, texture));` with a
//      MeshData (validate() names the first bad field), a terrain tile
//      `make_terrain_tile("tile 0 0", heightfield_mesh(spec, height_fn).value(), texture)`, a mesh
//      read by OpenMesh `load_mesh_file("model.obj")` (OBJ, OFF, PLY), `make_sky_dome()` and
//      `make_sun()` (where these two are in the graph, the renderer draws the sky and the sun).
//   3. Move things with `node->transform` (local to the parent, engine units); meshes are
//      immutable and shared (std::shared_ptr<const MeshData>): to edit one, make a new one.
//
// Units: positions in engine units (aerial::View::meters_per_unit converts), world up is the
// renderer's View::up (+Z by default), texture coordinates repeat.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "aerial/error.hpp"

namespace aerial::mesh {
class AdaptiveMesh;
}

namespace aerial::scene {

/// An RGB8 texture, top row first; both sides a power of two (1 .. 4096) for GL 1.x. The
/// renderer uploads it once with box-filtered mipmaps and draws it trilinear, repeated.
struct Texture {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  ///< width × height × 3 bytes
};

/// The first bad field of a texture: a side not a power of two in 1..4096, a wrong byte count.
std::optional<Error> validate(const Texture& texture);

/// The texture's mipmap chain as the renderer uploads it, largest (the texture itself) first down
/// to 1 × 1: each level the 2 × 2 (or 2 × 1 at a side of 1) box average of the one above,
/// rounded half up, RGB8, top row first. For engines that upload the texture themselves and
/// want the renderer's exact texels (the OpenSceneGraph adapter's comparison, aerial/osg.hpp).
std::vector<std::vector<std::uint8_t>> mipmap_levels(const Texture& texture);

/// Triangles with per-vertex attributes, tightly packed floats.
struct MeshData {
    std::vector<float> positions;        ///< x, y, z per vertex, local engine units
    std::vector<float> normals;          ///< empty, or unit x, y, z per vertex (for lighting)
    std::vector<float> texcoords;        ///< empty, or s, t per vertex
    std::vector<std::uint32_t> indices;  ///< three per triangle, each < vertex_count()
    std::size_t vertex_count() const { return positions.size() / 3; }
};

/// The first bad field: positions not a multiple of 3 or not finite, normals or texcoords of
/// another vertex count, an index count not a multiple of 3, an index out of range.
std::optional<Error> validate(const MeshData& mesh);

/// Reads a triangle mesh: OBJ or PLY with OpenMesh, ASCII OFF ([ST][C][N]OFF) with the module's
/// own strict reader (by extension), polygons triangulated, vertex normals computed when the
/// file has none, texture coordinates kept when it has them. Errors name the path: a missing or
/// unreadable file, an unknown extension, a file that cannot be parsed (OFF: and its line), a
/// mesh without triangles.
Result<MeshData> load_mesh_file(const std::string& path);

/// A square grid of heights sampled from a function: one terrain tile.
struct HeightfieldSpec {
    double origin_x = 0.0;          ///< x of the tile's first corner, engine units
    double origin_y = 0.0;          ///< y of the tile's first corner
    double size = 1000.0;           ///< side, engine units, > 0
    int resolution = 33;            ///< vertices a side, 2 .. 4097
    double texture_repeat = 250.0;  ///< engine units per texture repetition, > 0
};

/// The tile as a mesh (z = height(x, y), normals from central differences of the function,
/// texcoords x / texture_repeat, y / texture_repeat). Errors name the spec field, or "height"
/// when the function returns a value that is not finite.
Result<MeshData> heightfield_mesh(const HeightfieldSpec& spec,
                                  const std::function<double(double x, double y)>& height);

/// Procedural hills and ridges: fractal value noise, deterministic in `seed`.
struct ProceduralTerrain {
    std::uint32_t seed = 1;
    double amplitude = 600.0;      ///< largest height above base, engine units, >= 0
    double feature_size = 4000.0;  ///< wavelength of the largest hills, engine units, > 0
    double base = 0.0;             ///< height of the lowest valleys
    int octaves = 6;               ///< 1 .. 12
};

/// Height of the procedural terrain at (x, y), in [base, base + amplitude].
double procedural_height(const ProceduralTerrain& terrain, double x, double y);

enum class NodeKind {
    group,     ///< only children
    mesh,      ///< a MeshData drawn unlit (F_ex × texture + L_in)
    terrain,   ///< a MeshData drawn lit by the sun and sky (needs normals)
    sky_dome,  ///< draws the sky around the eye (the renderer's sky drawer)
    sun,       ///< draws the sun disc (the renderer's sun drawer)
};

/// "group", "mesh", "terrain", "sky-dome", "sun".
const char* node_kind_name(NodeKind kind);

struct Node {
    NodeKind kind = NodeKind::group;
    std::string name;
    glm::dmat4 transform{1.0};               ///< local to the parent (affine), engine units
    bool visible = true;                     ///< false: the node and its children are not drawn
    std::shared_ptr<const MeshData> mesh;    ///< mesh and terrain nodes
    std::shared_ptr<const Texture> texture;  ///< optional; untextured means white
    glm::vec3 albedo{1.0f};                  ///< multiplies the lit colour of terrain (linear RGB)
    /// Mesh and terrain nodes: a mesh the renderer refines for the view every frame, drawn
    /// instead of `mesh` (aerial/adaptive_scene.hpp, make_adaptive_mesh).
    std::shared_ptr<mesh::AdaptiveMesh> adaptive;
    double texture_repeat = 0.0;  ///< adaptive nodes: texcoords x / repeat, y / repeat (0: none)
    std::vector<std::unique_ptr<Node>> children;

    /// Appends a child and returns it.
    Node* add(std::unique_ptr<Node> child);
};

std::unique_ptr<Node> make_group(std::string name);
std::unique_ptr<Node> make_mesh(std::string name, std::shared_ptr<const MeshData> mesh,
                                std::shared_ptr<const Texture> texture = nullptr);
std::unique_ptr<Node> make_terrain_tile(std::string name, std::shared_ptr<const MeshData> mesh,
                                        std::shared_ptr<const Texture> texture = nullptr,
                                        glm::vec3 albedo = glm::vec3(1.0f));
std::unique_ptr<Node> make_sky_dome(std::string name = "sky");
std::unique_ptr<Node> make_sun(std::string name = "sun");

/// The first bad node, by its path from the root ("world/tile 3 4"): a mesh or terrain node
/// without a valid mesh, a terrain mesh without normals, an invalid texture, a transform that
/// is not finite.
std::optional<Error> validate(const Node& root);

/// Calls `visit(node, world_transform)` for every visible node, parents first.
void traverse(const Node& root,
              const std::function<void(const Node&, const glm::dmat4& world)>& visit);

}  // namespace aerial::scene
