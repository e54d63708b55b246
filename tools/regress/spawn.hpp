// One process per case: the runner starts `aerial-regress --child CASE ...` for each case, so
// that a driver crash or hang is that case's result ("crash"), and the run goes on.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "regress/result.hpp"

namespace aerial::regress {

struct SpawnOptions {
    std::string executable;                ///< this program (/proc/self/exe)
    std::vector<std::string> common_args;  ///< --suite, --gl, --device, --out, --bless...
    std::string out_dir;                   ///< logs/ and results/ go here
    int timeout_seconds = 300;             ///< a case still running then is killed: crash
    int jobs = 1;                          ///< cases run at the same time
};

/// Runs every case in `names` in its own process, at most `jobs` at a time; `done` is called
/// (in the calling thread) as each finishes, with its index in `names`.
void run_children(const std::vector<std::string>& names, const SpawnOptions& options,
                  const std::function<void(std::size_t, const CaseResult&)>& done);

}  // namespace aerial::regress
