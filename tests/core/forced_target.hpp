// forced_target.hpp — test helper: the SIMD target hooks of batch_simd.cpp and a guard that
// forces one target for a scope (shared by the batch kernel and RGBA8 tests).
#pragma once

#include <string>
#include <vector>

namespace aerial::detail {
// Test hooks defined in batch_simd.cpp.
std::vector<std::string> simd_test_targets();
bool simd_test_use_target(const std::string& name);
}  // namespace aerial::detail

namespace aerial::testing {

/// Forces one SIMD target for its lifetime, then goes back to the best one.
class ForcedTarget {
  public:
    explicit ForcedTarget(const std::string& name)
        : ok_(aerial::detail::simd_test_use_target(name)) {}
    ~ForcedTarget() { aerial::detail::simd_test_use_target(""); }
    ForcedTarget(const ForcedTarget&) = delete;
    ForcedTarget& operator=(const ForcedTarget&) = delete;
    bool ok() const { return ok_; }

  private:
    bool ok_;
};

}  // namespace aerial::testing
