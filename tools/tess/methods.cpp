// aerial-tess's shared method set-up: see methods.hpp.
#include "methods.hpp"

#include <algorithm>

namespace aerial::tess {

mesh::AdaptiveSettings adaptive_settings(const validation::TessScene& scene, double split_lsb,
                                         bool quantized) {
    mesh::AdaptiveSettings a;
    a.colour = scene.setting.colour;
    a.colour.quantized_vertices = quantized && scene.dome;
    a.colour.on_dome_sphere = quantized && scene.dome;
    a.colour.dome = scene.dome_options;
    a.split_lsb = float(split_lsb);
    a.lock_boundary = false;
    return a;
}

mesh::Mesh adaptive_base(const validation::TessScene& scene) {
    return scene.dome ? mesh::geodesic_dome(4, scene.dome_options).value()
                      : mesh::terrain_grid(scene.field, 8, 8).value();
}

mesh::Surface adaptive_surface(const validation::TessScene& scene) {
    return scene.dome ? mesh::Surface::sphere(scene.dome_options)
                      : mesh::Surface::terrain(scene.field);
}

mesh::DecimateOptions decimate_options(const validation::TessScene& scene, double max_lsb,
                                       bool quantized) {
    mesh::DecimateOptions d;
    d.colour = scene.setting.colour;
    d.colour.quantized_vertices = quantized;
    d.colour.on_dome_sphere = quantized;
    d.colour.dome = scene.dome_options;
    d.max_lsb = float(max_lsb);
    return d;
}

mesh::DecimatingSettings decimating_settings(const validation::TessScene& scene, double bound,
                                             double fine_split_lsb, bool quantized) {
    mesh::DecimatingSettings d;
    d.adaptive = adaptive_settings(scene, bound, quantized);
    d.fine_split_lsb = float(fine_split_lsb);
    d.decimate_lsb = float(bound);
    if (!scene.dome) {
        const glm::dvec3 eye = scene.setting.frame.view.eye;
        d.rebuild_eye_m = std::max(5.0, 0.1 * (eye.z - scene.field.height_m(eye.x, eye.y)));
    }
    return d;
}

}  // namespace aerial::tess
