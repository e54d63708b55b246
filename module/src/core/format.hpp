// Internal: number formatting for error messages (one place, so every message reads alike).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

#include <glm/vec3.hpp>

namespace aerial::detail {

/// Shortest-looking round-trippable form of a double ("1.2", "5.802e-06", "nan", "inf").
inline std::string format_number(double value) {
    char buffer[64];
    for (int precision = 6; precision <= 17; ++precision) {
        std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
        if (std::strtod(buffer, nullptr) == value) break;
    }
    return buffer;
}

inline std::string format_vector(const glm::dvec3& v) {
    return format_number(v.x) + "," + format_number(v.y) + "," + format_number(v.z);
}

}  // namespace aerial::detail
