// The set-up aerial-tess's methods share between its still sweeps (aerial-tess.cpp) and its
// path mode (path_mode.hpp): the adaptive mesh's settings, base mesh and surface, and the
// decimation's options, per scene.
#pragma once

#include "aerial/mesh.hpp"
#include "aerial/validation/tess_scenes.hpp"

namespace aerial::tess {

/// The adaptive methods' settings on a scene: its colour options, split threshold `split_lsb`,
/// the boundary free (the horizon ring and the terrain's edge are refined too); on domes with
/// `quantized` the estimate of what the GL image shows (8-bit vertex colours, samples on the
/// dome's sphere). On terrain the GL path rounds F_ex and L_in apart, so the float estimate is
/// kept there.
mesh::AdaptiveSettings adaptive_settings(const validation::TessScene& scene, double split_lsb,
                                         bool quantized);

/// What the adaptive methods start from: a geodesic dome of frequency 4 (41 vertices), or an
/// 8 x 8 grid of the terrain.
mesh::Mesh adaptive_base(const validation::TessScene& scene);
mesh::Surface adaptive_surface(const validation::TessScene& scene);

/// The offline decimation's options at a bound of `max_lsb` (the same estimate as the adaptive
/// dome's with `quantized`).
mesh::DecimateOptions decimate_options(const validation::TessScene& scene, double max_lsb,
                                       bool quantized);

/// The run-time `adaptive-decimating` method's settings: rebuilds refine to `fine_split_lsb`
/// and decimate to `bound`; between them the adaptive mesh refines at `bound` too; rebuilds by
/// the library's default sun turn (0.25 deg), on terrain also every 10 % of the eye's height
/// above the ground it was built at (at least 5 m); on their own thread.
mesh::DecimatingSettings decimating_settings(const validation::TessScene& scene, double bound,
                                             double fine_split_lsb, bool quantized);

}  // namespace aerial::tess
