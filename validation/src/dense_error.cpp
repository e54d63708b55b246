// The dense measure the tools grade meshes with: every face sampled on a barycentric grid.
#include "aerial/validation/dense_error.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "common/error_text.hpp"
#include "mesh/mesh_internal.hpp"

namespace aerial::validation {

using mesh::angular_size;
using mesh::channel_error_lsb;
using mesh::display_colour;
using mesh::to_glm;
using mesh::validate;
using mesh::validate_mesh;
using mesh::visit_grid;

Result<DenseError> dense_error(const aerial::mesh::Mesh& mesh, const Frame<float>& frame,
                               const aerial::mesh::ColourOptions& options, double spacing_rad,
                               int max_per_edge) {
    constexpr const char* kFunction = "validation::dense_error";
    if (auto e = validate(options)) return aerial::detail::from(kFunction, *e);
    if (auto e = validate_mesh(mesh)) return aerial::detail::from(kFunction, *e);
    if (!(spacing_rad > 0.0) || !std::isfinite(spacing_rad)) {
        return aerial::detail::invalid(kFunction, "spacing_rad", "a finite value > 0",
                                       aerial::detail::number(spacing_rad));
    }
    if (max_per_edge < 2 || max_per_edge > 4096) {
        return aerial::detail::invalid(kFunction, "max_per_edge", "2 .. 4096",
                                       aerial::detail::number(max_per_edge));
    }
    std::vector<glm::vec3> colour(mesh.n_vertices());
    for (auto v : mesh.vertices())
        if (!mesh.status(v).deleted())
            colour[v.idx()] = display_colour(frame, options, to_glm(mesh.point(v)));
    // Errors are binned at 1/64 step for the percentile (exact max kept apart).
    constexpr double kBinsPerStep = 64.0;
    std::vector<std::size_t> histogram(256 * 64 + 1, 0);
    DenseError out;
    double sum_sq = 0.0;
    std::size_t over1 = 0, over2 = 0;
    const bool no_skip[3] = {false, false, false};
    for (auto f : mesh.faces()) {
        if (mesh.status(f).deleted()) continue;
        glm::dvec3 p[3];
        glm::vec3 c[3];
        int k = 0;
        for (auto v : mesh.fv_range(f)) {
            p[k] = to_glm(mesh.point(v));
            c[k] = colour[v.idx()];
            ++k;
        }
        const int n = int(
            std::clamp(std::ceil(angular_size(frame, p) / spacing_rad), 2.0, double(max_per_edge)));
        visit_grid(n, no_skip, [&](double a, double b, double d) {
            const glm::dvec3 q = a * p[0] + b * p[1] + d * p[2];
            const glm::vec3 interpolated = float(a) * c[0] + float(b) * c[1] + float(d) * c[2];
            const double e = channel_error_lsb(interpolated, display_colour(frame, options, q));
            out.max_lsb = std::max(out.max_lsb, e);
            sum_sq += e * e;
            over1 += e > 1.0 ? 1 : 0;
            over2 += e > 2.0 ? 1 : 0;
            histogram[std::size_t(std::min(e * kBinsPerStep, double(histogram.size() - 1)))]++;
            ++out.count;
        });
    }
    if (out.count > 0) {
        const double n = double(out.count);
        out.rmse_lsb = std::sqrt(sum_sq / n);
        out.over1 = double(over1) / n;
        out.over2 = double(over2) / n;
        const std::size_t rank = std::size_t(std::ceil(0.99 * n));
        std::size_t seen = 0;
        for (std::size_t b = 0; b < histogram.size(); ++b) {
            seen += histogram[b];
            if (seen >= rank) {
                out.p99_lsb = std::min(double(b + 1) / kBinsPerStep, out.max_lsb);
                break;
            }
        }
    }
    return out;
}

}  // namespace aerial::validation
