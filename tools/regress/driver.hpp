// Pointing the runner at a driver: the Mesa variables a request sets (never over what the caller
// set otherwise), and the check that the driver GL reports is the one asked for.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aerial/error.hpp"
#include "aerial/headless.hpp"

namespace aerial::regress {

using Environment = std::vector<std::pair<std::string, std::string>>;

/// The variables for `driver` on `platform` ("" = whatever the environment gives):
///   llvmpipe, softpipe, any Gallium name   GALLIUM_DRIVER=NAME
///   zink                                   GALLIUM_DRIVER=zink LIBGL_ALWAYS_SOFTWARE=1 (EGL's
///                                          software loader, which runs zink on lavapipe)
std::vector<std::pair<std::string, std::string>> driver_variables(headless::Platform platform,
                                                                  const std::string& driver);

/// Sets `driver_vars` and `suite_vars` in this process's environment for the cases. A driver
/// variable the caller set to another value is an error naming it (the caller asked for two
/// things); a suite setting the caller set otherwise keeps the caller's value. Returns what is
/// now in effect, one "NAME=VALUE" per variable, for the report.
Result<std::vector<std::string>> apply_environment(const Environment& driver_vars,
                                                   const Environment& suite_vars);

/// The Mesa variables set in this process that choose or change a driver
/// (MESA_LOADER_DRIVER_OVERRIDE, LIBGL_ALWAYS_SOFTWARE, MESA_GL_VERSION_OVERRIDE, ...), as
/// "NAME=VALUE" each: what a report says was in effect.
std::vector<std::string> mesa_variables();

/// Empty when GL_RENDERER names `driver` (or no driver was asked for); otherwise why not.
std::string driver_mismatch(const std::string& driver, const std::string& renderer);

/// "osmesa-llvmpipe", "egl-zink": the folder of a device's goldens.
std::string device_name(headless::Platform platform, const std::string& renderer);

}  // namespace aerial::regress
