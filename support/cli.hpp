// Shared helpers of the command-line tools: parsing of vector flags and point files, and the
// one-line error convention (exit 2, "tool: what is wrong" on stderr).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include "aerial/error.hpp"

namespace aerial::tools {

/// Exit status for bad input (docs/conventions.md, Interfaces).
inline constexpr int kExitBadInput = 2;

/// Parses one finite number that fills the whole text (surrounding spaces allowed).
std::optional<double> parse_number(std::string_view text);

/// Parses "X,Y,Z" into three finite numbers; the error names `flag` and quotes the text.
Result<glm::dvec3> parse_vec3(std::string_view text, const std::string& flag);

/// Parses "X,Y,Z" and normalises it; the zero vector is an error naming `flag`.
Result<glm::dvec3> parse_direction(std::string_view text, const std::string& flag);

/// Parses an image size "WxH" with both sides in 1 .. max_side; the error names `flag`.
Result<std::pair<int, int>> parse_size(std::string_view text, const std::string& flag,
                                       int max_side = 8192);

/// Reads points "x,y,z", one per line; blank lines and '#' comments (whole-line or trailing)
/// are skipped. Errors name `source` and the 1-based line number.
Result<std::vector<glm::dvec3>> parse_points(std::string_view text, const std::string& source);

/// Prints "tool: message" on stderr and returns kExitBadInput.
int fail(std::string_view tool, std::string_view message);

/// Parses the command line with CLI11 the tools' way: --help prints the help and gives exit
/// status 0; any parse error prints one line "tool: what (see --help)" and gives
/// kExitBadInput. Returns nullopt when parsing succeeded and the tool should go on.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv, std::string_view tool);

}  // namespace aerial::tools
