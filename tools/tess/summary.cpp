// aerial-tess's summary tables: see summary.hpp.
#include "summary.hpp"

#include <algorithm>
#include <cstdio>
#include <functional>

namespace aerial::tess {
namespace {

// The fewest vertices of each method meeting `ok` per scene ("-" not graded, ">N" none did).
std::string fewest_table(const std::vector<std::string>& scenes, const std::vector<GradedRow>& rows,
                         const std::vector<std::string>& methods,
                         const std::function<bool(const GradedRow&)>& ok) {
    std::string text;
    char cell[64];
    std::snprintf(cell, sizeof cell, "%-24s", "scene");
    text += cell;
    for (const auto& m : methods) {
        std::snprintf(cell, sizeof cell, " %20s", m.c_str());
        text += cell;
    }
    text += "\n";
    for (const std::string& scene : scenes) {
        std::snprintf(cell, sizeof cell, "%-24s", scene.c_str());
        text += cell;
        for (const auto& m : methods) {
            std::string value = "-";
            std::size_t most = 0, fewest = 0;
            bool seen = false;
            for (const GradedRow& r : rows) {
                if (r.scene != scene || r.method != m) continue;
                seen = true;
                most = std::max(most, r.vertices);
                if (ok(r) && (fewest == 0 || r.vertices < fewest)) fewest = r.vertices;
            }
            if (fewest > 0) value = std::to_string(fewest);
            if (seen && value == "-") value = ">" + std::to_string(most);
            std::snprintf(cell, sizeof cell, " %20s", value.c_str());
            text += cell;
        }
        text += "\n";
    }
    return text;
}

}  // namespace

std::string summary_tables(const std::vector<std::string>& scenes,
                           const std::vector<GradedRow>& rows, int face_pixels, bool quick) {
    std::vector<std::string> methods;
    for (const GradedRow& r : rows)
        if (std::find(methods.begin(), methods.end(), r.method) == methods.end())
            methods.push_back(r.method);
    char head[256];
    std::snprintf(head, sizeof head,
                  "GL images against the per-pixel reference, six cube faces of %d x %d pixels "
                  "a mesh%s\n",
                  face_pixels, face_pixels,
                  quick ? "; QUICK RUN: a subset of scenes and levels, coarser grading" : "");
    return std::string(head) + "\nvertices for max <= 1 LSB\n" +
           fewest_table(scenes, rows, methods,
                        [](const GradedRow& r) { return r.error.max_lsb <= 1; }) +
           "\nvertices for at most 1e-4 of the pixels over 1 LSB (one pixel cannot flip it)\n" +
           fewest_table(scenes, rows, methods,
                        [](const GradedRow& r) { return r.error.over1 <= 1e-4; });
}

}  // namespace aerial::tess
