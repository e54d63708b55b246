// mesh_bounds (aerial/cache.hpp): the bounding sphere and box of a mesh's finite vertices.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "aerial/cache.hpp"

namespace aerial {
namespace {

using glm::dvec3;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool finite(const dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

MeshBounds mesh_bounds(const Positions& positions) {
    auto at = [&](const float* base, std::size_t i) {
        return double(*reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) +
                                                      i * positions.stride_bytes));
    };
    if (positions.count == 0) return MeshBounds{dvec3(0.0), -1.0};
    if (!positions.x || !positions.y || !positions.z || positions.stride_bytes < sizeof(float)) {
        return MeshBounds{dvec3(0.0), kInfinity};  // not an array shade_into accepts
    }
    dvec3 lo(kInfinity), hi(-kInfinity);
    bool any = false;
    for (std::size_t i = 0; i < positions.count; ++i) {
        const dvec3 p(at(positions.x, i), at(positions.y, i), at(positions.z, i));
        if (!finite(p)) continue;
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
        any = true;
    }
    if (!any) return MeshBounds{dvec3(0.0), -1.0};
    const dvec3 centre = 0.5 * (lo + hi);
    double radius2 = 0.0;
    for (std::size_t i = 0; i < positions.count; ++i) {
        const dvec3 p(at(positions.x, i), at(positions.y, i), at(positions.z, i));
        if (!finite(p)) continue;
        const dvec3 d = p - centre;
        radius2 = std::max(radius2, glm::dot(d, d));
    }
    // Rounding of the centre and the square root: a relative 1e-12 keeps every vertex inside.
    return MeshBounds{centre, std::sqrt(radius2) * (1.0 + 1e-12), lo, hi};
}

}  // namespace aerial
