// The regression suite as data (tests/golden/suite.txt): how every case is rendered, the
// tolerances, and the cases of each tier. aerial-regress reads it; nothing else holds a
// tolerance.
//
// Format, one statement a line ('#' starts a comment line):
//   setting size WxH                 the image size of every rendered case
//   setting env NAME=VALUE           set for every case unless the caller set NAME otherwise
//   tolerance CHECK BOUND=VALUE ...  the bounds of a check (below); a bound not given is not
//   checked cross SCENE [BOUND=VALUE ...]    portable: cpu and arb against perpixel, fog against
//   perpixel golden SCENE BACKEND [PATH]      per device:
//   tests/golden/DEVICE/SCENE-BACKEND[-PATH].png selftest crash|fail|hang         a case that
//   crashes, fails or hangs on purpose (the
//                                    harness's own tests; never in suite.txt)
// Bounds: max_lsb, p99_lsb (at most), min_p99_lsb (at least), max_over1, max_over2 (fractions of
// pixels off by more than 1 and 2 steps, at most). Checks: cross (default of the cross lines),
// fog, paths, cpu-model, golden, cpu-golden.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "aerial/error.hpp"
#include "common/image_metrics.hpp"

namespace aerial::regress {

/// Bounds on the differences of two images (or two sets of vertex colours), in 8-bit steps.
using Tolerance = tools::LsbTolerance;

enum class Tier { portable, golden, selftest };
const char* tier_name(Tier tier);

/// What a case does (docs/regression-testing.md, "The cases").
enum class CaseKind {
    context,     ///< creates the context and reports GL_VENDOR, GL_RENDERER, GL_VERSION
    cross,       ///< a per-vertex backend (cpu, arb) against perpixel on the same driver
    fog,         ///< plain GL fog against perpixel: must differ visibly (min_p99_lsb)
    paths,       ///< a cpu path against the secondary-color path on the same driver
    state,       ///< the GL state after a SceneRenderer frame equals the state before
    cpu_model,   ///< the CPU's vertex colours (shade_into) against the double-precision model
    golden,      ///< a rendered image against this device's stored one
    cpu_golden,  ///< the CPU's vertex colours against the stored, device-independent ones
    selftest,    ///< crashes, fails or hangs on purpose
};
const char* case_kind_name(CaseKind kind);

struct Case {
    std::string name;  ///< "cross/noon_valley/arb", "golden/hazy-cpu-combiner", ...
    Tier tier = Tier::portable;
    CaseKind kind = CaseKind::context;
    std::string scene;    ///< scene file stem (tests/golden/scenes/SCENE.json)
    std::string backend;  ///< cpu, arb, perpixel, fog, none
    std::string path;     ///< cpu fixed-function path, or empty (automatic)
    Tolerance tolerance;
};

struct Suite {
    std::string directory;  ///< where the suite file is: scenes/ and the golden folders
    int width = 160, height = 120;
    std::vector<std::pair<std::string, std::string>> environment;
    std::vector<Case> cases;  ///< the context case first

    const Case* find(const std::string& name) const;
    std::string scene_path(const std::string& scene) const;
};

/// Reads a suite file; the error names the line and what is wrong with it.
Result<Suite> load_suite(const std::string& path);

}  // namespace aerial::regress
