#include "aerial/scene.hpp"

#include <algorithm>
#include <cmath>

#include <glm/vec2.hpp>

#include "../common/error_text.hpp"
#include "../common/names.hpp"
#include "validated_meshes.hpp"

namespace aerial::scene {
namespace {

bool is_power_of_two(int v) { return v > 0 && (v & (v - 1)) == 0; }

using aerial::detail::invalid;
using aerial::detail::number;
constexpr const char* kValidate = "scene::validate";

/// An error of a node (field: its path) in scene::validate.
Error bad_node(const std::string& path, const std::string& text) {
    return aerial::detail::error(kValidate, path, text);
}

/// The error of a node's mesh or texture (validate(MeshData), validate(Texture)) under the node.
Error bad_part(const std::string& path, const char* part, const Error& e) {
    return bad_node(
        path, std::string(part) + " " + e.field + ": " + std::string(aerial::detail::text_of(e)));
}

/// Lattice value in [0, 1) at integer point (ix, iy): a 32-bit integer hash (murmur3 finaliser).
double lattice_value(std::int64_t ix, std::int64_t iy, std::uint32_t seed) {
    std::uint32_t h = static_cast<std::uint32_t>(ix) * 0x8da6b343u ^
                      static_cast<std::uint32_t>(iy) * 0xd8163841u ^ seed * 0xcb1ab31fu;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return static_cast<double>(h) * (1.0 / 4294967296.0);
}

/// Smooth value noise in [0, 1], lattice period 1 (quintic fade, continuous slope).
double value_noise(double x, double y, std::uint32_t seed) {
    const double fx = std::floor(x), fy = std::floor(y);
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
    const auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
    const double u = fade(x - fx), v = fade(y - fy);
    const double a = lattice_value(ix, iy, seed), b = lattice_value(ix + 1, iy, seed);
    const double c = lattice_value(ix, iy + 1, seed), d = lattice_value(ix + 1, iy + 1, seed);
    const double bottom = a + (b - a) * u, top = c + (d - c) * u;
    return bottom + (top - bottom) * v;
}

std::optional<Error> validate_node(const Node& node, const std::string& path,
                                   detail::ValidatedMeshes* memo) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(node.transform[c][r])) {
                return invalid(kValidate, path, "a finite transform",
                               "a non-finite value in column " + number(c) + ", row " + number(r));
            }
        }
    }
    if (node.adaptive) {
        if (node.kind != NodeKind::mesh && node.kind != NodeKind::terrain) {
            return invalid(kValidate, path,
                           "a mesh or terrain node (the kinds that can hold an adaptive mesh)",
                           std::string("a ") + node_kind_name(node.kind) + " node");
        }
        if (!(node.texture_repeat >= 0.0) || !std::isfinite(node.texture_repeat)) {
            return bad_node(path, "texture_repeat: expected a finite value >= 0, got " +
                                      number(node.texture_repeat));
        }
    } else if (node.kind == NodeKind::mesh || node.kind == NodeKind::terrain) {
        if (!node.mesh)
            return bad_node(path, std::string(node_kind_name(node.kind)) + " without a mesh");
        if (!memo || !memo->contains(*node.mesh)) {
            if (auto e = validate(*node.mesh)) return bad_part(path, "mesh", *e);
            if (memo) memo->add(*node.mesh);
        }
        if (node.kind == NodeKind::terrain && node.mesh->normals.empty())
            return bad_node(path, "terrain mesh without normals (lighting needs them)");
    }
    if (node.texture) {
        if (auto e = validate(*node.texture)) return bad_part(path, "texture", *e);
    }
    if (!(node.albedo.r >= 0.0f && node.albedo.g >= 0.0f && node.albedo.b >= 0.0f) ||
        !std::isfinite(node.albedo.r + node.albedo.g + node.albedo.b)) {
        return bad_node(path, "albedo: expected finite values >= 0, got " +
                                  aerial::detail::vector(node.albedo));
    }
    for (const auto& child : node.children) {
        if (!child) return bad_node(path, "a null child");
        if (auto e = validate_node(*child, path + "/" + child->name, memo)) return e;
    }
    return std::nullopt;
}

void traverse_node(const Node& node, const glm::dmat4& parent,
                   const std::function<void(const Node&, const glm::dmat4&)>& visit) {
    if (!node.visible) return;
    const glm::dmat4 world = parent * node.transform;
    visit(node, world);
    for (const auto& child : node.children) {
        if (child) traverse_node(*child, world, visit);
    }
}

std::unique_ptr<Node> make_node(NodeKind kind, std::string name) {
    auto node = std::make_unique<Node>();
    node->kind = kind;
    node->name = std::move(name);
    return node;
}

}  // namespace

std::optional<Error> validate(const Texture& texture) {
    if (!is_power_of_two(texture.width) || texture.width > 4096)
        return invalid(kValidate, "width", "a power of two in 1 .. 4096", number(texture.width));
    if (!is_power_of_two(texture.height) || texture.height > 4096)
        return invalid(kValidate, "height", "a power of two in 1 .. 4096", number(texture.height));
    const std::size_t expected = std::size_t(texture.width) * std::size_t(texture.height) * 3;
    if (texture.rgb.size() != expected) {
        return invalid(kValidate, "rgb", number(expected) + " bytes (width x height x 3)",
                       number(texture.rgb.size()));
    }
    return std::nullopt;
}

std::vector<std::vector<std::uint8_t>> mipmap_levels(const Texture& t) {
    std::vector<std::vector<std::uint8_t>> levels{t.rgb};
    int w = t.width, h = t.height;
    while (w > 1 || h > 1) {
        const int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
        const auto& src = levels.back();
        std::vector<std::uint8_t> dst(std::size_t(nw) * nh * 3);
        for (int y = 0; y < nh; ++y) {
            for (int x = 0; x < nw; ++x) {
                for (int c = 0; c < 3; ++c) {
                    int sum = 0, n = 0;
                    for (int dy = 0; dy < (h > 1 ? 2 : 1); ++dy) {
                        for (int dx = 0; dx < (w > 1 ? 2 : 1); ++dx) {
                            sum += src[(std::size_t(2 * y + dy) * w + std::size_t(2 * x + dx)) * 3 +
                                       c];
                            ++n;
                        }
                    }
                    dst[(std::size_t(y) * nw + x) * 3 + c] = std::uint8_t((sum + n / 2) / n);
                }
            }
        }
        levels.push_back(std::move(dst));
        w = nw;
        h = nh;
    }
    return levels;
}

std::optional<Error> validate(const MeshData& mesh) {
    if (mesh.positions.size() % 3 != 0) {
        return invalid(kValidate, "positions", "3 floats a vertex",
                       number(mesh.positions.size()) + " floats");
    }
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        if (!std::isfinite(mesh.positions[i])) {
            return invalid(kValidate, "positions", "finite values",
                           number(mesh.positions[i]) + " at value " + number(i));
        }
    }
    const std::size_t n = mesh.vertex_count();
    if (!mesh.normals.empty() && mesh.normals.size() != 3 * n) {
        return invalid(kValidate, "normals", number(3 * n) + " floats (3 a vertex)",
                       number(mesh.normals.size()));
    }
    if (!mesh.texcoords.empty() && mesh.texcoords.size() != 2 * n) {
        return invalid(kValidate, "texcoords", number(2 * n) + " floats (2 a vertex)",
                       number(mesh.texcoords.size()));
    }
    if (mesh.indices.size() % 3 != 0) {
        return invalid(kValidate, "indices", "3 a triangle",
                       number(mesh.indices.size()) + " indices");
    }
    for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
        if (mesh.indices[i] >= n) {
            return invalid(kValidate, "indices", "values < " + number(n) + " (the vertex count)",
                           number(mesh.indices[i]) + " at index " + number(i));
        }
    }
    return std::nullopt;
}

Result<MeshData> heightfield_mesh(const HeightfieldSpec& spec,
                                  const std::function<double(double, double)>& height) {
    constexpr const char* kFunction = "scene::heightfield_mesh";
    if (!(spec.size > 0.0) || !std::isfinite(spec.size))
        return invalid(kFunction, "size", "a finite value > 0", number(spec.size));
    if (spec.resolution < 2 || spec.resolution > 4097) {
        return invalid(kFunction, "resolution", "2 .. 4097 vertices a side",
                       number(spec.resolution));
    }
    if (!(spec.texture_repeat > 0.0) || !std::isfinite(spec.texture_repeat)) {
        return invalid(kFunction, "texture_repeat", "a finite value > 0",
                       number(spec.texture_repeat));
    }
    if (!std::isfinite(spec.origin_x) || !std::isfinite(spec.origin_y)) {
        return invalid(kFunction, "origin", "finite coordinates",
                       aerial::detail::vector(glm::dvec2(spec.origin_x, spec.origin_y)));
    }
    if (!height) return invalid(kFunction, "height", "a height function", "an empty one");
    const int n = spec.resolution;
    const double step = spec.size / double(n - 1);
    MeshData mesh;
    mesh.positions.reserve(std::size_t(n) * n * 3);
    mesh.normals.reserve(std::size_t(n) * n * 3);
    mesh.texcoords.reserve(std::size_t(n) * n * 2);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double x = spec.origin_x + step * i, y = spec.origin_y + step * j;
            const double z = height(x, y);
            // Central differences at half a grid step: the same normal on both sides of a seam.
            const double h = 0.5 * step;
            const double dx = (height(x + h, y) - height(x - h, y)) / (2.0 * h);
            const double dy = (height(x, y + h) - height(x, y - h)) / (2.0 * h);
            if (!std::isfinite(z) || !std::isfinite(dx) || !std::isfinite(dy)) {
                return invalid(kFunction, "height", "finite heights and slopes",
                               "a non-finite one at " + aerial::detail::vector(glm::dvec2(x, y)));
            }
            const double norm = std::sqrt(dx * dx + dy * dy + 1.0);
            mesh.positions.insert(mesh.positions.end(), {float(x), float(y), float(z)});
            mesh.normals.insert(mesh.normals.end(),
                                {float(-dx / norm), float(-dy / norm), float(1.0 / norm)});
            mesh.texcoords.insert(mesh.texcoords.end(),
                                  {float(x / spec.texture_repeat), float(y / spec.texture_repeat)});
        }
    }
    mesh.indices.reserve(std::size_t(n - 1) * (n - 1) * 6);
    for (int j = 0; j + 1 < n; ++j) {
        for (int i = 0; i + 1 < n; ++i) {
            const std::uint32_t a = std::uint32_t(j * n + i), b = a + 1, c = a + std::uint32_t(n),
                                d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    }
    return mesh;
}

double procedural_height(const ProceduralTerrain& terrain, double x, double y) {
    const int octaves = std::clamp(terrain.octaves, 1, 12);
    const double wavelength0 = terrain.feature_size > 0.0 ? terrain.feature_size : 1.0;
    double sum = 0.0, amplitude = 1.0, norm = 0.0, wavelength = wavelength0;
    double u = x, v = y;
    for (int i = 0; i < octaves; ++i) {
        double n = value_noise(u / wavelength, v / wavelength, terrain.seed + std::uint32_t(i));
        if (i >= 1) n = 1.0 - std::abs(2.0 * n - 1.0);  // ridged above the first octave
        sum += amplitude * n;
        norm += amplitude;
        amplitude *= 0.5;
        wavelength *= 0.5;
        // Turn the lattice about 37 degrees between octaves so the grids do not line up.
        const double ru = 0.8 * u - 0.6 * v;
        v = 0.6 * u + 0.8 * v;
        u = ru;
    }
    const double t = sum / norm;  // [0, 1]
    // Flatten the valleys, sharpen the peaks.
    return terrain.base + std::max(0.0, terrain.amplitude) * t * t;
}

constexpr aerial::detail::NameTable<NodeKind, 5> kNodeKindNames{{{NodeKind::group, "group"},
                                                                 {NodeKind::mesh, "mesh"},
                                                                 {NodeKind::terrain, "terrain"},
                                                                 {NodeKind::sky_dome, "sky-dome"},
                                                                 {NodeKind::sun, "sun"}}};

const char* node_kind_name(NodeKind kind) { return aerial::detail::name_in(kNodeKindNames, kind); }

Node* Node::add(std::unique_ptr<Node> child) {
    children.push_back(std::move(child));
    return children.back().get();
}

std::unique_ptr<Node> make_group(std::string name) {
    return make_node(NodeKind::group, std::move(name));
}

std::unique_ptr<Node> make_mesh(std::string name, std::shared_ptr<const MeshData> mesh,
                                std::shared_ptr<const Texture> texture) {
    auto node = make_node(NodeKind::mesh, std::move(name));
    node->mesh = std::move(mesh);
    node->texture = std::move(texture);
    return node;
}

std::unique_ptr<Node> make_terrain_tile(std::string name, std::shared_ptr<const MeshData> mesh,
                                        std::shared_ptr<const Texture> texture, glm::vec3 albedo) {
    auto node = make_node(NodeKind::terrain, std::move(name));
    node->mesh = std::move(mesh);
    node->texture = std::move(texture);
    node->albedo = albedo;
    return node;
}

std::unique_ptr<Node> make_sky_dome(std::string name) {
    return make_node(NodeKind::sky_dome, std::move(name));
}

std::unique_ptr<Node> make_sun(std::string name) {
    return make_node(NodeKind::sun, std::move(name));
}

std::optional<Error> validate(const Node& root) { return validate_node(root, root.name, nullptr); }

std::optional<Error> detail::validate(const Node& root, detail::ValidatedMeshes& memo) {
    return validate_node(root, root.name, &memo);
}

void traverse(const Node& root, const std::function<void(const Node&, const glm::dmat4&)>& visit) {
    traverse_node(root, glm::dmat4(1.0), visit);
}

}  // namespace aerial::scene
