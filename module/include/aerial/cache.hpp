// aerial/cache.hpp — skip re-shading a mesh while eye and sun have moved too little to change any
// of its 8-bit outputs by half a step.
//
// How to use this:
//   1. Once per mesh, and again whenever its vertices change:
//      `cache.bounds = aerial::mesh_bounds(positions);`  (bounding sphere and box, engine units)
//   2. Once per frame, describe what the shading depends on and prepare it (about 10 us):
//      `aerial::ShadingKey key{atmosphere, view, model, display};`  (copy ambient and albedo
//      from your Lighting when you bake lit colours), then
//      `auto now = aerial::prepare_shading_key(key);`
//   3. Per mesh (about 2 us):
//      `if (cache.needs_update(*now)) { aerial::shade_into(...); cache.mark_shaded(*now); }`
//
// What "skipped" guarantees: the stored outputs were shaded with the key of the last
// mark_shaded; max_change_lsb bounds, for every vertex inside `bounds`, how far any 8-bit output
// (F_ex, L_in and the lit colour F_ex (E_sun max(N.L, 0) + ambient) albedo, unit normals) would
// move before rounding if it were shaded again now. needs_update() is false only while that bound
// is below half a step, so a skipped mesh shows every channel within one code of a fresh shading
// (half a step of change plus the half step of the first rounding).
//
// The bound is derived from the model (docs/models.md, "When shading can be skipped"): it grows
// with the
// eye's move (m), the sun's turn (rad), the extinction and scattering coefficients, and the
// nearness of the mesh. It covers the models' mathematics and the rounding of eye and sun to float
// in prepare_frame<float>, not the kernels' arithmetic (a few 1e-5 steps for `simd`; `simd_fast`
// has its own error of up to 1 step on top). It is +infinity, i.e. always re-shade, when anything
// but the eye position and the sun direction changed, for the `reference` model, for the `height`
// model while the sun is on or below the horizon of any point of the mesh or of the eye (the
// model's sun switches off in a step there), for meshes reaching kMaxDistanceM, and when a key
// does not validate.
#pragma once

#include <limits>
#include <optional>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/scattering.hpp"

namespace aerial {

/// Where a mesh's vertices are, engine units (like View::eye): a sphere, and optionally their
/// axis-aligned box, which tightens the bound a lot for wide flat meshes such as terrain (their
/// nearest and farthest distance, lowest and highest altitude, and the phase angles they span).
struct MeshBounds {
    glm::dvec3 centre{0.0};
    /// >= 0; negative means the mesh has no finite vertex (nothing in it can change).
    double radius = 0.0;
    /// The box; leave the default (infinite) when only the sphere is known.
    glm::dvec3 box_min{-std::numeric_limits<double>::infinity()};
    glm::dvec3 box_max{std::numeric_limits<double>::infinity()};
};

/// Bounding sphere and box of the finite vertices (vertices with a NaN or infinite coordinate are
/// skipped: shade_into leaves their outputs constant). The sphere is centred on the box, its
/// radius the largest distance from there (never more than 1.73 times the smallest sphere).
/// Radius -1 when there is no finite vertex; +infinity (always re-shade) for arrays shade_into
/// rejects (a null array with count > 0, a stride below 4 bytes).
MeshBounds mesh_bounds(const Positions& positions);

/// Everything the 8-bit outputs of a mesh depend on besides its vertices and normals.
struct ShadingKey {
    Atmosphere atmosphere;
    View view;
    Model model = Model::height;
    Display display;
    /// Lighting::ambient and Lighting::albedo of the lit output (linear RGB); the defaults
    /// (no ambient, albedo 1) are right when lit_rgba8 is not used.
    glm::vec3 ambient{0.0f};
    glm::vec3 albedo{1.0f};
};

/// A ShadingKey with its per-frame constants (prepare_frame<double>: E_sun at the eye, the
/// eye's altitude and sun columns), computed once and shared by every mesh of the frame.
struct PreparedShadingKey {
    ShadingKey key;
    Frame<double> frame;
};

/// Validates the key (atmosphere, view; exposure finite and > 0) and prepares it.
Result<PreparedShadingKey> prepare_shading_key(const ShadingKey& key);

/// Upper bound, in 8-bit steps, on the change before rounding of any 8-bit output (F_ex, L_in,
/// lit colour; every channel, after exposure and tone curve) of any vertex inside `bounds`
/// between shading with `before` and with `now`. 0 when the keys are equal; +infinity when
/// anything but view.eye and view.sun_dir differs (atmosphere, model, display, ambient, albedo,
/// view.up, view.meters_per_unit), for the `reference` model, for `height` while the sun is on or
/// below the horizon somewhere in the mesh or at either eye, and for meshes reaching
/// kMaxDistanceM.
double max_change_lsb(const PreparedShadingKey& before, const PreparedShadingKey& now,
                      const MeshBounds& bounds);

/// The same from unprepared keys (prepares both: about 20 us). +infinity if either is invalid.
double max_change_lsb(const ShadingKey& before, const ShadingKey& now, const MeshBounds& bounds);

/// Changes below this many 8-bit steps do not need a re-shade.
inline constexpr double kSkipBelowLsb = 0.5;

/// What a mesh was last shaded with. Plain data: keep one per mesh next to its colour arrays.
struct ShadingCache {
    std::optional<PreparedShadingKey> shaded_with;  ///< none: never shaded (or invalidated)
    MeshBounds bounds;                              ///< set with mesh_bounds()

    /// True when never shaded or when max_change_lsb(*shaded_with, now, bounds) >= 0.5.
    bool needs_update(const PreparedShadingKey& now) const;
    /// The same, preparing `now` first (about 10 us); true when `now` is invalid.
    bool needs_update(const ShadingKey& now) const;
    /// Records that the mesh's outputs are now those of `now`.
    void mark_shaded(const PreparedShadingKey& now) { shaded_with = now; }
    /// The same, preparing `now` first; an invalid key clears shaded_with (always re-shade).
    void mark_shaded(const ShadingKey& now);
    /// Forget the shading (for example after editing the vertices: also refresh `bounds`).
    void invalidate() { shaded_with.reset(); }
};

}  // namespace aerial
