// libFuzzer target: the point reader of aerial-eval (tools::parse_points) and the vector flags'
// parsers. Accepted points and vectors must be finite; directions of unit length.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_check.hpp"
#include "support/cli.hpp"

using aerial::fuzz::check;
using aerial::fuzz::finite;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto points = aerial::tools::parse_points(text, "fuzz.csv");
    if (points) {
        for (const glm::dvec3& p : *points)
            check(finite(p), "parse_points accepted a non-finite point");
    } else {
        check(points.error().message.rfind("fuzz.csv", 0) == 0,
              "a parse_points error that does not start with the source");
    }
    // The first line is also a flag value.
    const std::string_view line = text.substr(0, text.find('\n'));
    if (auto v = aerial::tools::parse_vec3(line, "--eye")) {
        check(finite(*v), "parse_vec3 accepted a non-finite vector");
    }
    if (auto d = aerial::tools::parse_direction(line, "--sun")) {
        const double length = std::sqrt(d->x * d->x + d->y * d->y + d->z * d->z);
        check(finite(*d) && std::abs(length - 1.0) < 1e-9,
              "parse_direction gave a non-unit vector");
    }
    if (auto s = aerial::tools::parse_size(line, "--size")) {
        check(s->first >= 1 && s->first <= 8192 && s->second >= 1 && s->second <= 8192,
              "parse_size accepted a size out of range");
    }
    if (auto n = aerial::tools::parse_number(line)) check(std::isfinite(*n), "non-finite number");
    return 0;
}
