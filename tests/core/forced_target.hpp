// forced_target.hpp — test helper: a guard that forces one SIMD target for a scope (shared by the
// batch kernel and RGBA8 tests), with the hooks of aerial/validation/test_hooks.hpp.
#pragma once

#include <string>

#include "aerial/validation/test_hooks.hpp"

namespace aerial::testing {

/// Forces one SIMD target for its lifetime, then goes back to the best one.
class ForcedTarget {
  public:
    explicit ForcedTarget(const std::string& name)
        : ok_(aerial::validation::simd_test_use_target(name)) {}
    ~ForcedTarget() { aerial::validation::simd_test_use_target(""); }
    ForcedTarget(const ForcedTarget&) = delete;
    ForcedTarget& operator=(const ForcedTarget&) = delete;
    bool ok() const { return ok_; }

  private:
    bool ok_;
};

}  // namespace aerial::testing
