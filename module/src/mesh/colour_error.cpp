// The colour error of interpolating per-vertex colours across a triangle (the dense measure the
// tools grade meshes with is aerial::validation's, validation/src/dense_error.cpp).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {
namespace {

// Samples per edge for the estimate: the Mie lobe's width (about 1 - g rad for the normalised
// Henyey-Greenstein phase) is sampled at least twice across.
int estimate_samples_per_edge(const Frame<float>& frame, const ColourOptions& options,
                              const glm::dvec3 (&p)[3], int multiple) {
    const double lobe_rad = std::max(1.0 - std::abs(double(frame.mie_g)), 0.02);
    const double n = std::ceil(angular_size(frame, p) / (0.5 * lobe_rad));
    return int(std::clamp(n, 2.0, double(options.max_samples_per_edge))) * multiple;
}

}  // namespace

float channel_error_lsb(const glm::vec3& a, const glm::vec3& b) {
    const glm::vec3 d = glm::abs(a - b);
    return 255.0f * std::max(d.x, std::max(d.y, d.z));
}

// Angle (rad) the longest edge subtends from the eye, bounded by the nearest vertex's distance.
double angular_size(const Frame<float>& frame, const glm::dvec3 (&p)[3]) {
    const glm::dvec3 eye = frame.view.eye;
    double nearest =
        std::min({glm::length(p[0] - eye), glm::length(p[1] - eye), glm::length(p[2] - eye)});
    const double longest =
        std::max({glm::length(p[1] - p[0]), glm::length(p[2] - p[1]), glm::length(p[0] - p[2])});
    nearest = std::max(nearest, 1e-6 * longest + 1e-9);
    return longest / nearest;
}

std::optional<Error> validate(const ColourOptions& options) {
    using aerial::detail::invalid;
    using aerial::detail::number;
    constexpr const char* kFunction = "mesh::validate";
    if (!(options.display.exposure > 0.0f) || !std::isfinite(options.display.exposure)) {
        return invalid(kFunction, "exposure", "a finite value > 0",
                       number(options.display.exposure));
    }
    for (int c = 0; c < 3; ++c) {
        if (!(options.texel[c] >= 0.0f && options.texel[c] <= 1.0f)) {
            return invalid(kFunction, "texel", "values in [0, 1]",
                           aerial::detail::vector(options.texel));
        }
    }
    if (options.max_samples_per_edge < 2 || options.max_samples_per_edge > 32) {
        return invalid(kFunction, "max_samples_per_edge", "2 .. 32",
                       number(options.max_samples_per_edge));
    }
    return std::nullopt;
}

glm::vec3 display_colour(const Frame<float>& frame, const ColourOptions& options,
                         const glm::dvec3& position) {
    const Scattering<float> s = scatter(frame, glm::vec3(position));
    glm::vec3 c;
    for (int i = 0; i < 3; ++i) {
        const float v =
            s.extinction[i] * options.texel[i] + display_value(options.display, s.in_scattering[i]);
        c[i] = std::clamp(v, 0.0f, 1.0f);
    }
    return c;
}

namespace {

// The point the sample q shows: q itself, or with on_dome_sphere where the view ray from the eye
// through q meets the dome's sphere (the eye is inside it).
glm::dvec3 shown_point(const Frame<float>& frame, const ColourOptions& options,
                       const glm::dvec3& q) {
    if (!options.on_dome_sphere) return q;
    const glm::dvec3 eye = frame.view.eye;
    const glm::dvec3 ray = q - eye;
    const double length = glm::length(ray);
    if (!(length > 0.0)) return q;
    const glm::dvec3 d = ray / length;
    const glm::dvec3 oc = eye - options.dome.centre;
    const double b = glm::dot(oc, d);
    const double disc = b * b - (glm::dot(oc, oc) - options.dome.radius_m * options.dome.radius_m);
    if (!(disc >= 0.0)) return q;
    const double t = -b + std::sqrt(disc);
    return t > 0.0 ? eye + t * d : q;
}

}  // namespace

float colour_error_skipping(const Frame<float>& frame, const ColourOptions& options,
                            const glm::dvec3 (&p)[3], const glm::vec3 (&c)[3],
                            const bool (&skip_edge)[3], int sample_multiple) {
    const int n = estimate_samples_per_edge(frame, options, p, sample_multiple);
    glm::vec3 shown[3] = {c[0], c[1], c[2]};
    if (options.quantized_vertices)
        for (glm::vec3& v : shown) v = glm::round(glm::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
    float worst = 0.0f;
    auto sample = [&](double a, double b, double d) {
        const glm::dvec3 q = a * p[0] + b * p[1] + d * p[2];
        const glm::vec3 interpolated =
            float(a) * shown[0] + float(b) * shown[1] + float(d) * shown[2];
        worst = std::max(
            worst, channel_error_lsb(interpolated, display_colour(frame, options,
                                                                  shown_point(frame, options, q))));
    };
    // Always the edge midpoints (where bisection puts the new vertex) and the centroid.
    if (n % 2 == 1) {
        if (!skip_edge[0]) sample(0.5, 0.5, 0.0);
        if (!skip_edge[1]) sample(0.0, 0.5, 0.5);
        if (!skip_edge[2]) sample(0.5, 0.0, 0.5);
    }
    if (n % 3 != 0) sample(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
    visit_grid(n, skip_edge, sample);
    return worst;
}

float edge_midpoint_error(const Frame<float>& frame, const ColourOptions& options,
                          const glm::dvec3& a, const glm::dvec3& b, const glm::vec3& ca,
                          const glm::vec3& cb) {
    glm::vec3 shown[2] = {ca, cb};
    if (options.quantized_vertices)
        for (glm::vec3& v : shown) v = glm::round(glm::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
    const glm::dvec3 q = 0.5 * (a + b);
    return channel_error_lsb(0.5f * (shown[0] + shown[1]),
                             display_colour(frame, options, shown_point(frame, options, q)));
}

float colour_error(const Frame<float>& frame, const ColourOptions& options, const glm::dvec3& p0,
                   const glm::dvec3& p1, const glm::dvec3& p2, const glm::vec3& c0,
                   const glm::vec3& c1, const glm::vec3& c2) {
    const glm::dvec3 p[3] = {p0, p1, p2};
    const glm::vec3 c[3] = {c0, c1, c2};
    const bool skip[3] = {false, false, false};
    return colour_error_skipping(frame, options, p, c, skip);
}

}  // namespace aerial::mesh
