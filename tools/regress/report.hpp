// What a run reports: the summary table, results.csv, JUnit XML, and the comparison with a
// baseline of known failures and skips (so that only changes fail a run).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "aerial/error.hpp"
#include "regress/result.hpp"
#include "regress/suite.hpp"

namespace aerial::regress {

struct Outcome {
    const Case* c = nullptr;
    CaseResult result;
};

/// What the run was pointed at, for every report.
struct Identity {
    std::string platform, driver, device;
    std::string vendor, renderer, version, simd_target;
    std::vector<std::string> environment;  ///< the Mesa variables in effect, NAME=VALUE
};

/// Expected statuses other than pass, by case name.
using Baseline = std::map<std::string, Status>;

/// Reads "CASE STATUS" lines ('#' comments); the error names the line.
Result<Baseline> load_baseline(const std::string& path);
/// Writes every case whose status is not pass, as load_baseline reads it.
std::optional<std::string> write_baseline(const std::string& path,
                                          const std::vector<Outcome>& outcomes);

/// How the run compares with the baseline (pass expected for cases it does not list).
struct Verdict {
    std::vector<std::string> regressions;  ///< fail or crash, not expected: these fail the run
    std::vector<std::string> fixes;        ///< pass where the baseline expected otherwise
    std::vector<std::string> changes;      ///< any other status change (skip, not-supported)
};
Verdict judge(const std::vector<Outcome>& outcomes, const Baseline& baseline);

/// The table printed at the end: one line a case that did not pass, the counts per status and
/// tier, and the changes against the baseline (the caller adds the verdict line).
std::string summary(const Identity& id, const std::vector<Outcome>& outcomes,
                    const Verdict& verdict);

std::optional<std::string> write_csv(const std::string& path, const Identity& id,
                                     const std::vector<Outcome>& outcomes);
std::optional<std::string> write_junit(const std::string& path, const Identity& id,
                                       const std::vector<Outcome>& outcomes);
/// DEVICE/device.txt beside a device's goldens: what they were blessed on.
std::optional<std::string> write_device_file(const std::string& path, const Identity& id,
                                             const Suite& suite);

}  // namespace aerial::regress
