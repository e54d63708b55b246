// Running one case of the suite, in the process that runs it (a child of aerial-regress): the
// context it needs, the images or vertex colours it compares, and its result.
#pragma once

#include <string>

#include "aerial/headless.hpp"
#include "regress/result.hpp"
#include "regress/suite.hpp"

namespace aerial::regress {

struct CaseSettings {
    headless::Platform platform = headless::Platform::osmesa;
    std::string device;      ///< the golden folder: tests/golden/DEVICE/ ("osmesa-llvmpipe")
    std::string images_dir;  ///< where fresh, reference and diff images of a case go
    bool bless = false;      ///< golden cases write this device's image instead of comparing
    bool bless_cpu = false;  ///< cpu-golden cases write the stored vertex colours
};

/// Runs `c`. Never throws for a driver's failure: a missing capability is not-supported, a
/// bound exceeded or an error is fail (the reason says which). A crash ends the process, which
/// is why the runner starts one process per case.
CaseResult run_case(const Suite& suite, const Case& c, const CaseSettings& settings);

/// The file name of a case's files: "cross/noon_valley/arb" -> "cross.noon_valley.arb".
std::string case_file_name(const std::string& case_name);

}  // namespace aerial::regress
