// aerial-tess's rows and the summary tables built from them (printed and written to
// OUT/summary.txt).
#pragma once

#include <string>
#include <vector>

#include "common/image_metrics.hpp"

namespace aerial::tess {

/// One graded mesh: a row of tess.csv.
struct GradedRow {
    std::string scene, method, level;  ///< level: the sweep's parameter, or a mesh file's stem
    std::size_t vertices = 0, triangles = 0;
    tools::LsbDifferences error;
    double build_ms = 0.0, grade_ms = 0.0;
};

/// Per scene (in `scenes`' order), the fewest vertices of each method for max <= 1 step and for
/// a criterion one pixel cannot flip (at most 1e-4 of the pixels more than 1 step off); "-"
/// where a method was not graded on a scene, ">N" where none of its meshes (N vertices at most)
/// met it. The first line gives the face size and marks a quick run.
std::string summary_tables(const std::vector<std::string>& scenes,
                           const std::vector<GradedRow>& rows, int face_pixels, bool quick);

}  // namespace aerial::tess
