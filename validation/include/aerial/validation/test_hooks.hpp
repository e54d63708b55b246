// aerial/validation/test_hooks.hpp — hooks into the SIMD dispatch of aerial::core, so that tests
// and tools cover every code path a user's CPU may take (aerial::validation; engines do not use
// them). They are defined where the Highway dispatch lives (module/src/core/batch_simd.cpp, in
// aerial::detail, since they touch its dispatch tables) and declared here only.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace aerial::detail {

/// The SIMD targets compiled into aerial::core that this CPU runs (Highway's names: "AVX2", ...).
std::vector<std::string> simd_test_targets();
/// Forces one of simd_test_targets() for every later batch call (an empty name goes back to the
/// best); false, and nothing changed, for a name that is not one of them.
bool simd_test_use_target(const std::string& name);

// The dispatched target's vector building blocks, n values each, for the kernel tests.
void simd_erfcx(const float* y, float* out, std::size_t n);
void simd_fast_exp2(const float* x, float* out, std::size_t n);
void simd_fast_log2(const float* x, float* out, std::size_t n);
/// exp and expm1 of y / (8 log2(e)) for y in eighths of a binary order (the 2002 kernel's unit).
void simd_exp_and_expm1(const float* y, float* exp_out, float* expm1_out, std::size_t n, bool fast);

}  // namespace aerial::detail

namespace aerial::validation {

using detail::simd_test_targets;
using detail::simd_test_use_target;

}  // namespace aerial::validation
