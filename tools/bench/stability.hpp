// The stability map (issue 7): where each method fails against the `reference` model.
//
// How to use this:
//   1. `aerial-bench --stability --out DIR [--quick] [--sweep NAME]...` calls
//      run_stability(DIR, quick, names).
//   2. It sweeps one parameter at a time around a base case (earth, sun 10 deg, eye 2 m): sun
//      elevation, camera altitude, view distance, Mie g, turbidity and visibility, and measures
//      every method in 8-bit steps (LSB) of the values the fixed pipeline is handed: F_ex and
//      L_in after exposure and the GL clamp.
//   3. It writes DIR/stability.csv (docs/benchmarks.md, "Where methods fail", names the columns)
// and
//      DIR/stability.png through tools/plot_stability.py.
#pragma once

#include <string>
#include <vector>

namespace aerial::bench {

/// Runs the stability sweep into `out_dir` (created if missing). `quick` takes a coarse grid
/// (seconds); `sweeps` names the sweeps to run (the CSV's `sweep` values; empty: all of them).
/// Prints progress and a summary on stdout; returns the process exit status: 0, or 2 after one
/// line on stderr naming what went wrong (an unknown sweep name among them).
int run_stability(const std::string& out_dir, bool quick,
                  const std::vector<std::string>& sweeps = {});

}  // namespace aerial::bench
