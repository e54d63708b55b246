// One case's result, as the child process writes it and the runner reads it back (a small text
// file: one "key=value" a line).
#pragma once

#include <map>
#include <optional>
#include <string>

namespace aerial::regress {

enum class Status { pass, fail, skip, crash, not_supported };

/// "pass", "fail", "skip", "crash", "not-supported".
const char* status_name(Status status);
std::optional<Status> parse_status(const std::string& name);

struct CaseResult {
    Status status = Status::fail;
    std::string reason;                          ///< one line; empty for a plain pass
    std::map<std::string, std::string> metrics;  ///< max_lsb, p99_lsb, ... and GL strings
    double seconds = 0.0;                        ///< wall time of the child process
};

/// Writes `result` to `path`; false when the file cannot be written.
bool write_result(const std::string& path, const CaseResult& result);
/// Reads what write_result wrote; nullopt when the file is missing or malformed.
std::optional<CaseResult> read_result(const std::string& path);

}  // namespace aerial::regress
