// The base meshes: geodesic and latitude-longitude domes, heightfield grids, and the surfaces
// new vertices are projected onto.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

using aerial::detail::invalid;
using aerial::detail::number;
using aerial::detail::vector;

std::optional<Error> validate_dome(const DomeOptions& dome, const char* function) {
    if (!finite(dome.centre))
        return invalid(function, "centre", "finite coordinates", vector(dome.centre));
    if (!finite(dome.up) || std::abs(glm::length(dome.up) - 1.0) > 1e-3) {
        return invalid(function, "up", "a unit vector",
                       vector(dome.up) + " (length " + number(glm::length(dome.up)) + ")");
    }
    if (!(dome.radius_m > 0.0) || !std::isfinite(dome.radius_m))
        return invalid(function, "radius_m", "a finite value > 0", number(dome.radius_m));
    return std::nullopt;
}

// East and north completing `up` to a right-handed frame (east x north = up).
void horizon_frame(const glm::dvec3& up, glm::dvec3& east, glm::dvec3& north) {
    const glm::dvec3 helper = std::abs(up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    east = glm::normalize(helper - up * glm::dot(helper, up));
    north = glm::cross(up, east);
}

Error range_error(const char* field, const char* function, int value, int lo, int hi) {
    return invalid(function, field, number(lo) + " .. " + number(hi), number(value));
}

}  // namespace

Result<Mesh> geodesic_dome(int frequency, const DomeOptions& dome) {
    if (auto e = validate_dome(dome, "mesh::geodesic_dome")) return *e;
    if (frequency < 1 || frequency > 2048)
        return range_error("frequency", "mesh::geodesic_dome", frequency, 1, 2048);
    glm::dvec3 east, north;
    horizon_frame(dome.up, east, north);
    const glm::dvec3 corner[4] = {east, north, -east, -north};
    Mesh mesh;
    // rings[i] holds the 4 i vertices at level i from the top (one for i = 0).
    std::vector<std::vector<Mesh::VertexHandle>> rings(frequency + 1);
    for (int i = 0; i <= frequency; ++i) {
        const int count = i == 0 ? 1 : 4 * i;
        for (int j = 0; j < count; ++j) {
            glm::dvec3 flat = dome.up;
            if (i > 0) {
                const int k = j / i;
                const double t = double(j % i) / i;
                const double s = double(i) / frequency;
                flat = dome.up * (1.0 - s) + (corner[k] * (1.0 - t) + corner[(k + 1) % 4] * t) * s;
            }
            rings[i].push_back(
                mesh.add_vertex(to_point(dome.centre + dome.radius_m * glm::normalize(flat))));
        }
    }
    auto at = [&](int i, int j) {
        const auto& ring = rings[i];
        return ring[std::size_t(j) % ring.size()];
    };
    for (int i = 0; i < frequency; ++i) {
        for (int k = 0; k < 4; ++k) {
            for (int m = 0; m <= i; ++m)
                mesh.add_face(at(i, k * i + m), at(i + 1, k * (i + 1) + m),
                              at(i + 1, k * (i + 1) + m + 1));
            for (int m = 0; m < i; ++m)
                mesh.add_face(at(i, k * i + m), at(i + 1, k * (i + 1) + m + 1),
                              at(i, k * i + m + 1));
        }
    }
    return mesh;
}

Result<Mesh> latlong_dome(int rings, int segments, const DomeOptions& dome) {
    if (auto e = validate_dome(dome, "mesh::latlong_dome")) return *e;
    if (rings < 1 || rings > 4096)
        return range_error("rings", "mesh::latlong_dome", rings, 1, 4096);
    if (segments < 3 || segments > 16384)
        return range_error("segments", "mesh::latlong_dome", segments, 3, 16384);
    glm::dvec3 east, north;
    horizon_frame(dome.up, east, north);
    Mesh mesh;
    std::vector<Mesh::VertexHandle> v;
    for (int r = 0; r < rings; ++r) {
        const double elevation = 0.5 * kPi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double azimuth = 2.0 * kPi * s / segments;
            const glm::dvec3 d =
                std::cos(elevation) * (std::cos(azimuth) * east + std::sin(azimuth) * north) +
                std::sin(elevation) * dome.up;
            v.push_back(mesh.add_vertex(to_point(dome.centre + dome.radius_m * d)));
        }
    }
    const auto pole = mesh.add_vertex(to_point(dome.centre + dome.radius_m * dome.up));
    auto at = [&](int r, int s) { return v[std::size_t(r * segments + (s % segments))]; };
    for (int r = 0; r + 1 < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            mesh.add_face(at(r, s), at(r, s + 1), at(r + 1, s + 1));
            mesh.add_face(at(r, s), at(r + 1, s + 1), at(r + 1, s));
        }
    }
    for (int s = 0; s < segments; ++s) mesh.add_face(at(rings - 1, s), at(rings - 1, s + 1), pole);
    return mesh;
}

Heightfield rolling_hills(double x0, double y0, double size_m, double amplitude_m,
                          double wavelength_m, unsigned seed, int octaves) {
    struct Wave {
        double kx, ky, phase, amplitude;
    };
    std::vector<Wave> waves;
    unsigned state = seed * 2654435761u + 12345u;
    auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return double(state >> 8) / double(1u << 24);
    };
    for (int o = 0; o < octaves; ++o) {
        const double angle = 2.0 * kPi * next();
        const double k = 2.0 * kPi / (wavelength_m * std::pow(0.5, o));
        waves.push_back({k * std::cos(angle), k * std::sin(angle), 2.0 * kPi * next(),
                         amplitude_m * std::pow(0.5, o + 1)});
    }
    Heightfield field;
    field.x0 = x0;
    field.y0 = y0;
    field.size_x_m = size_m;
    field.size_y_m = size_m;
    field.height_m = [waves](double x, double y) {
        double h = 0.0;
        for (const Wave& w : waves) h += w.amplitude * std::sin(w.kx * x + w.ky * y + w.phase);
        return h;
    };
    return field;
}

namespace {

/// The grid of terrain_grid with the point of grid coordinates (s, t) in [0, 1]^2 at place(s, t).
Result<Mesh> grid_mesh(const Heightfield& field, int cells_x, int cells_y, const char* f,
                       const std::function<glm::dvec2(double, double)>& place) {
    if (!field.height_m) return invalid(f, "height_m", "a height function", "an empty one");
    if (!(field.size_x_m > 0.0) || !(field.size_y_m > 0.0) || !std::isfinite(field.size_x_m) ||
        !std::isfinite(field.size_y_m) || !std::isfinite(field.x0) || !std::isfinite(field.y0)) {
        return invalid(f, "size_m", "a finite origin and sizes > 0",
                       "origin " + vector(glm::dvec2(field.x0, field.y0)) + ", sizes " +
                           vector(glm::dvec2(field.size_x_m, field.size_y_m)));
    }
    if (cells_x < 1 || cells_x > 4096) return range_error("cells_x", f, cells_x, 1, 4096);
    if (cells_y < 1 || cells_y > 4096) return range_error("cells_y", f, cells_y, 1, 4096);
    Mesh mesh;
    std::vector<Mesh::VertexHandle> v;
    for (int j = 0; j <= cells_y; ++j) {
        for (int i = 0; i <= cells_x; ++i) {
            const glm::dvec2 xy = place(double(i) / cells_x, double(j) / cells_y);
            const double z = field.height_m(xy.x, xy.y);
            if (!std::isfinite(z)) {
                return invalid(f, "height_m", "finite heights", number(z) + " at " + vector(xy));
            }
            v.push_back(mesh.add_vertex(Mesh::Point(xy.x, xy.y, z)));
        }
    }
    auto at = [&](int i, int j) { return v[std::size_t(j * (cells_x + 1) + i)]; };
    for (int j = 0; j < cells_y; ++j) {
        for (int i = 0; i < cells_x; ++i) {
            mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    }
    return mesh;
}

}  // namespace

Result<Mesh> terrain_grid(const Heightfield& field, int cells_x, int cells_y) {
    return grid_mesh(field, cells_x, cells_y, "mesh::terrain_grid", [&](double s, double t) {
        return glm::dvec2(field.x0 + field.size_x_m * s, field.y0 + field.size_y_m * t);
    });
}

Result<Mesh> terrain_distance_lod(const Heightfield& field, int cells, const glm::dvec2& eye_xy,
                                  double exponent) {
    const char* f = "mesh::terrain_distance_lod";
    if (!(exponent >= 1.0 && exponent <= 8.0))
        return invalid(f, "exponent", "a value in [1, 8]", number(exponent));
    if (!std::isfinite(eye_xy.x) || !std::isfinite(eye_xy.y))
        return invalid(f, "eye_xy", "finite coordinates", vector(eye_xy));
    // The eye in grid coordinates, and each side's signed coordinate in [-1, 1].
    const glm::dvec2 e{std::clamp((eye_xy.x - field.x0) / field.size_x_m, 0.0, 1.0),
                       std::clamp((eye_xy.y - field.y0) / field.size_y_m, 0.0, 1.0)};
    auto side = [](double s, double eye) {
        const double extent = s >= eye ? 1.0 - eye : eye;
        return extent > 0.0 ? (s - eye) / extent : 0.0;
    };
    auto back = [](double u, double eye) { return eye + u * (u >= 0.0 ? 1.0 - eye : eye); };
    return grid_mesh(field, cells, cells, f, [&](double s, double t) {
        const double u = side(s, e.x), w = side(t, e.y);
        const double r = std::max(std::abs(u), std::abs(w));
        const double scale = r > 0.0 ? std::pow(r, exponent - 1.0) : 0.0;
        return glm::dvec2(field.x0 + field.size_x_m * back(u * scale, e.x),
                          field.y0 + field.size_y_m * back(w * scale, e.y));
    });
}

Surface Surface::sphere(const DomeOptions& dome) {
    Surface s;
    s.kind = Kind::sphere;
    s.centre = dome.centre;
    s.radius_m = dome.radius_m;
    return s;
}

Surface Surface::terrain(const Heightfield& field) {
    Surface s;
    s.kind = Kind::heightfield;
    s.height_m = field.height_m;
    return s;
}

glm::dvec3 Surface::project(const glm::dvec3& p) const {
    switch (kind) {
        case Kind::sphere: {
            const glm::dvec3 d = p - centre;
            const double length = glm::length(d);
            return length > 0.0 ? centre + d * (radius_m / length) : p;
        }
        case Kind::heightfield:
            return {p.x, p.y, height_m(p.x, p.y)};
        case Kind::plane:
            break;
    }
    return p;
}

std::size_t live_vertices(const Mesh& mesh) {
    std::size_t n = 0;
    for (auto v : mesh.vertices()) n += mesh.status(v).deleted() ? 0 : 1;
    return n;
}

std::size_t live_faces(const Mesh& mesh) {
    std::size_t n = 0;
    for (auto f : mesh.faces()) n += mesh.status(f).deleted() ? 0 : 1;
    return n;
}

std::optional<Error> validate_mesh(const Mesh& mesh, const char* what) {
    constexpr const char* kFunction = "mesh::validate_mesh";
    if (live_faces(mesh) == 0) return aerial::detail::error(kFunction, what, "has no faces");
    for (auto v : mesh.vertices()) {
        if (mesh.status(v).deleted()) continue;
        if (!finite(to_glm(mesh.point(v)))) {
            return invalid(kFunction, what, "finite positions",
                           vector(to_glm(mesh.point(v))) + " at vertex " + number(v.idx()));
        }
    }
    for (auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        if (mesh.valence(f) != 3) {
            return invalid(kFunction, what, "triangles",
                           "face " + number(f.idx()) + " of " + number(mesh.valence(f)) + " sides");
        }
    }
    return std::nullopt;
}

}  // namespace aerial::mesh
