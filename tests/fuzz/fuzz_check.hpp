// Shared helpers of the libFuzzer targets: a check that stops the fuzzer with a message (any
// trap is a crash libFuzzer keeps as an artifact) and finiteness tests.
#pragma once

#include <cmath>
#include <cstdio>

#include <glm/vec3.hpp>

namespace aerial::fuzz {

/// Prints what went wrong and traps: libFuzzer records the input as a crash.
[[noreturn]] inline void fail(const char* what) {
    std::fprintf(stderr, "fuzz check failed: %s\n", what);
    std::fflush(stderr);
    __builtin_trap();
}

inline void check(bool ok, const char* what) {
    if (!ok) fail(what);
}

template <class T>
bool finite(const glm::vec<3, T>& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace aerial::fuzz
