// The scene file's procedural content (aerial/scene_file.hpp): the terrain height field (the
// scene graph's procedural_height), the boxes and the texture.
#include <algorithm>
#include <cmath>

#include "../common/names.hpp"
#include "aerial/scene_file.hpp"

namespace aerial::scene {
namespace {

/// A 32-bit integer hash (lowbias32) of a lattice point and a seed.
std::uint32_t hash(std::int64_t x, std::int64_t y, std::uint32_t seed) {
    std::uint32_t h =
        seed * 0x9E3779B9u ^ std::uint32_t(x) * 0x85EBCA6Bu ^ std::uint32_t(y) * 0xC2B2AE35u;
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    return h;
}

double lattice(std::int64_t x, std::int64_t y, std::uint32_t seed) {
    return double(hash(x, y, seed) >> 8) / double(1u << 24);
}

/// Value noise in [0, 1] with smoothstep interpolation; with period > 0 the lattice repeats
/// every `period` cells (a seamless tile).
double value_noise(double x, double y, std::uint32_t seed, std::int64_t period = 0) {
    const double fx = std::floor(x), fy = std::floor(y);
    const auto ix = std::int64_t(fx), iy = std::int64_t(fy);
    const double tx = x - fx, ty = y - fy;
    const double sx = tx * tx * (3.0 - 2.0 * tx), sy = ty * ty * (3.0 - 2.0 * ty);
    const auto wrap = [period](std::int64_t i) { return period > 0 ? i % period : i; };
    const double a = lattice(wrap(ix), wrap(iy), seed), b = lattice(wrap(ix + 1), wrap(iy), seed);
    const double c = lattice(wrap(ix), wrap(iy + 1), seed);
    const double d = lattice(wrap(ix + 1), wrap(iy + 1), seed);
    return (a + (b - a) * sx) + ((c + (d - c) * sx) - (a + (b - a) * sx)) * sy;
}

}  // namespace

double terrain_height(const TerrainSpec& t, double x, double y) {
    ProceduralTerrain terrain;
    terrain.seed = t.seed;
    terrain.amplitude = t.height_amplitude;
    terrain.feature_size = t.feature_size;
    terrain.octaves = t.octaves;
    return procedural_height(terrain, x, y);
}

namespace {

void add_terrain(const TerrainSpec& t, MeshData& mesh) {
    const int n = t.resolution;
    const auto base = std::uint32_t(mesh.vertex_count());
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const double x = t.center.x + t.size * (double(i) / n - 0.5);
            const double y = t.center.y + t.size * (double(j) / n - 0.5);
            const double z = terrain_height(t, x, y);
            mesh.positions.insert(mesh.positions.end(), {float(x), float(y), float(z)});
            mesh.texcoords.insert(mesh.texcoords.end(),
                                  {float(x / t.texture_repeat), float(y / t.texture_repeat)});
        }
    }
    const auto row = std::uint32_t(n + 1);
    for (std::uint32_t j = 0; j < std::uint32_t(n); ++j) {
        for (std::uint32_t i = 0; i < std::uint32_t(n); ++i) {
            const std::uint32_t a = base + j * row + i, b = a + 1, c = a + row, d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    }
}

void add_box(const BoxSpec& box, double texture_repeat, MeshData& mesh) {
    const int n = box.subdivisions;
    const glm::dvec3 half = 0.5 * box.size;
    // Each face: an outward axis and two in-plane axes that make a counter-clockwise quad.
    for (int axis = 0; axis < 3; ++axis) {
        for (int sign = -1; sign <= 1; sign += 2) {
            const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
            const auto base = std::uint32_t(mesh.vertex_count());
            for (int j = 0; j <= n; ++j) {
                for (int i = 0; i <= n; ++i) {
                    glm::dvec3 p = box.center;
                    p[axis] += sign * half[axis];
                    p[u_axis] += half[u_axis] * (2.0 * i / n - 1.0);
                    p[v_axis] += half[v_axis] * (2.0 * j / n - 1.0);
                    mesh.positions.insert(mesh.positions.end(),
                                          {float(p.x), float(p.y), float(p.z)});
                    mesh.texcoords.insert(
                        mesh.texcoords.end(),
                        {float(p[u_axis] / texture_repeat), float(p[v_axis] / texture_repeat)});
                }
            }
            const auto row = std::uint32_t(n + 1);
            for (std::uint32_t j = 0; j < std::uint32_t(n); ++j) {
                for (std::uint32_t i = 0; i < std::uint32_t(n); ++i) {
                    const std::uint32_t a = base + j * row + i, b = a + 1, c = a + row, d = c + 1;
                    if (sign > 0) {
                        mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
                    } else {
                        mesh.indices.insert(mesh.indices.end(), {a, d, b, a, c, d});
                    }
                }
            }
        }
    }
}

}  // namespace

MeshData scene_geometry(const SceneFile& scene) {
    MeshData mesh;
    const double repeat =
        scene.terrain ? scene.terrain->texture_repeat : TerrainSpec{}.texture_repeat;
    if (scene.terrain) add_terrain(*scene.terrain, mesh);
    for (const BoxSpec& box : scene.boxes) add_box(box, repeat, mesh);
    return mesh;
}

Texture scene_texture(const TextureSpec& spec) {
    Texture texture;
    texture.width = texture.height = spec.size;
    texture.rgb.resize(std::size_t(spec.size) * std::size_t(spec.size) * 3);
    const int cell = spec.size / spec.cells;
    for (int y = 0; y < spec.size; ++y) {
        for (int x = 0; x < spec.size; ++x) {
            double t = 0.0;
            if (spec.kind == TextureKind::checker) {
                t = ((x / cell + y / cell) % 2) ? 1.0 : 0.0;
            } else {
                // Tiles seamlessly: the noise lattice repeats every `cells` cells.
                const double scale = double(spec.cells) / spec.size;
                t = value_noise(x * scale, y * scale, spec.seed, spec.cells);
            }
            const glm::dvec3 c = spec.colors[0] + (spec.colors[1] - spec.colors[0]) * t;
            for (int k = 0; k < 3; ++k) {
                texture.rgb[(std::size_t(y) * spec.size + x) * 3 + k] = to_unorm8(float(c[k]));
            }
        }
    }
    return texture;
}

std::unique_ptr<Node> scene_graph(const SceneFile& scene) {
    auto root = make_group("scene");
    root->add(make_mesh("geometry", std::make_shared<MeshData>(scene_geometry(scene)),
                        std::make_shared<Texture>(scene_texture(scene.texture))));
    return root;
}

constexpr aerial::detail::NameTable<TextureKind, 2> kTextureKindNames{
    {{TextureKind::checker, "checker"}, {TextureKind::noise, "noise"}}};

const char* texture_kind_name(TextureKind kind) {
    return aerial::detail::name_in(kTextureKindNames, kind);
}

Result<TextureKind> parse_texture_kind(std::string_view name) {
    return aerial::detail::parse_in("scene::parse_texture_kind", kTextureKindNames, "texture_kind",
                                    name);
}

}  // namespace aerial::scene
