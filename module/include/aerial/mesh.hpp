// aerial/mesh.hpp — put vertices where the per-vertex colour needs them (OpenMesh).
//
// How to use this:
//   1. Build a base mesh: `geodesic_dome(4, dome)`, `latlong_dome(...)` or
//      `terrain_grid(heightfield, 16, 16)`, and describe the true surface new vertices go onto
//      (`Surface::sphere(...)`, `Surface::terrain(...)`).
//   2. `auto adaptive = aerial::mesh::AdaptiveMesh::create(std::move(base), surface, settings);`
//   3. Per frame: `auto frame = aerial::prepare_frame<float>(atmosphere, view, model);` then
//      `adaptive->update(*frame);` splits triangles whose colour error exceeds
//      settings.split_lsb (longest-edge bisection, Rivara's LEPP) within a vertex budget and a time
//      slice, and undoes splits whose parent triangle is back under split_lsb / merge_ratio.
//   4. Draw `adaptive->mesh()` (an OpenMesh TriMesh with double positions; skip faces with
//      `status(f).deleted()`). Deleted elements are removed by the update itself once they
//      exceed settings.compact_garbage_ratio of the live ones (UpdateStats::compacted says when:
//      vertex handles then change their numbers, keeping their order).
//   Offline: `decimate(mesh, frame, options)` removes vertices while the colour error stays below
//   a bound (an OpenMesh Decimater with a colour-error module).
//   Run time near the decimated count: `DecimatingMesh` (the end of this header) starts the
//   adaptive mesh from a decimated one and makes that again, on a thread of its own, when the sun
//   (or the eye) has moved on.
//
// The colour error (8-bit steps) of a triangle is the largest difference, over sample points,
// between the colour interpolated from its three vertices and the exact colour at the point, on
// the displayed colour clamp(F_ex * texel + display(L_in)) of each channel (ColourOptions).
// Samples: edge midpoints and the centroid, plus a barycentric grid when the triangle is large
// against the Mie lobe as seen from the eye.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "aerial/batch.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"

namespace aerial::mesh {

struct MeshTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;  ///< metres (engine units), double so domes of 100 km stay exact
    using Normal = OpenMesh::Vec3d;
    VertexAttributes(OpenMesh::Attributes::Status);
    EdgeAttributes(OpenMesh::Attributes::Status);
    HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
    FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
};

/// The mesh type of this module: triangles, double positions, status flags (for deletion).
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// ---- Shapes -----------------------------------------------------------------------------------

/// A hemispherical sky dome around `centre` (usually the eye), open at the horizon.
struct DomeOptions {
    glm::dvec3 centre{0.0, 0.0, 0.0};
    glm::dvec3 up{0.0, 0.0, 1.0};  ///< unit
    double radius_m = 80000.0;     ///< > 0
};

/// Geodesic dome of class I on the octahedron: the upper four faces subdivided `frequency` times
/// per edge and projected onto the sphere; 2 f^2 + 2 f + 1 vertices, the horizon ring has 4 f.
/// frequency in 1 .. 2048.
Result<Mesh> geodesic_dome(int frequency, const DomeOptions& dome = {});

/// Latitude-longitude dome as engines ship it: `rings` rings between the horizon and the pole
/// (equal elevation steps), `segments` vertices per ring, one pole vertex;
/// rings * segments + 1 vertices. rings in 1 .. 4096, segments in 3 .. 16384.
Result<Mesh> latlong_dome(int rings, int segments, const DomeOptions& dome = {});

/// Heights z = height_m(x, y) over the rectangle [x0, x0 + size_x] x [y0, y0 + size_y] (m).
struct Heightfield {
    std::function<double(double, double)> height_m;
    double x0 = 0.0, y0 = 0.0;
    double size_x_m = 1000.0, size_y_m = 1000.0;
};

/// Rolling hills: a sum of `octaves` sines with decreasing wavelengths, deterministic in `seed`.
/// Peak-to-peak height at most 2 * amplitude_m.
Heightfield rolling_hills(double x0, double y0, double size_m, double amplitude_m,
                          double wavelength_m, unsigned seed = 1, int octaves = 3);

/// Regular grid of cells_x by cells_y squares, each cut along the same diagonal; vertices on the
/// heightfield. cells in 1 .. 4096. The heightfield must give finite heights.
Result<Mesh> terrain_grid(const Heightfield& field, int cells_x, int cells_y);

/// Distance level of detail: the cells x cells grid of terrain_grid with its square rings pushed
/// away from the eye. A grid point at L-infinity radius t in [0, 1] around the eye (t = 1 on the
/// field's border, measured per side of the eye) moves to radius t^exponent, so near the eye the
/// cells are t^(exponent - 1) times the uniform grid's and far away up to `exponent` times
/// (side length about proportional to distance^((exponent - 1) / exponent)). Same vertex count,
/// topology and diagonals as terrain_grid: conforming, no T-junctions, nothing to stitch.
/// `eye_xy` is clamped into the field; cells in 1 .. 4096, exponent in [1, 8] (1 is
/// terrain_grid).
Result<Mesh> terrain_distance_lod(const Heightfield& field, int cells, const glm::dvec2& eye_xy,
                                  double exponent);

/// Where new vertices go: onto the sphere, onto the heightfield, or left at the edge midpoint.
struct Surface {
    enum class Kind { plane, sphere, heightfield };
    Kind kind = Kind::plane;
    glm::dvec3 centre{0.0};                          ///< sphere
    double radius_m = 1.0;                           ///< sphere
    std::function<double(double, double)> height_m;  ///< heightfield: z of (x, y)

    static Surface sphere(const DomeOptions& dome);
    static Surface terrain(const Heightfield& field);
    /// The point of the surface a new vertex at the edge midpoint `p` goes to.
    glm::dvec3 project(const glm::dvec3& p) const;
};

// ---- Colour error -----------------------------------------------------------------------------

/// What the screen shows at a vertex: clamp(F_ex * texel + display(L_in)) per channel.
struct ColourOptions {
    Display display;
    /// The brightest texel that F_ex multiplies; 0 for a sky dome, which shows only L_in.
    glm::vec3 texel{1.0f};
    /// Samples per triangle edge at most (the barycentric grid for triangles large against the
    /// Mie lobe); 2 gives edge midpoints and the centroid only. In 2 .. 32.
    int max_samples_per_edge = 8;
    /// The vertex colours are rounded to 8 bits before they are interpolated, as the GL path
    /// draws them (RGBA8): the error is then that of the rounded colours, interpolated, against
    /// the exact colour. The framebuffer's own rounding keeps the pixel within 1 step of the
    /// exact colour's rounding wherever this error is below 1 step. Exact for a sky dome
    /// (texel 0); with a texel, F_ex and L_in are rounded as one colour, an approximation.
    bool quantized_vertices = false;
    /// Sky domes: the exact colour of a sample is taken where the view ray through it meets the
    /// dome's sphere (what a per-pixel sky shows in that pixel), not on the flat triangle.
    bool on_dome_sphere = false;
    DomeOptions dome;  ///< the sphere, with on_dome_sphere
};

/// The first bad field of the options (exposure, texel, max_samples_per_edge).
std::optional<Error> validate(const ColourOptions& options);

/// The displayed colour at a position, each channel in [0, 1].
glm::vec3 display_colour(const Frame<float>& frame, const ColourOptions& options,
                         const glm::dvec3& position);

/// Colour error of the triangle (p0, p1, p2) whose vertices show c0, c1, c2, in 8-bit steps.
float colour_error(const Frame<float>& frame, const ColourOptions& options, const glm::dvec3& p0,
                   const glm::dvec3& p1, const glm::dvec3& p2, const glm::vec3& c0,
                   const glm::vec3& c1, const glm::vec3& c2);

/// Live vertices and faces (not counting deleted ones).
std::size_t live_vertices(const Mesh& mesh);
std::size_t live_faces(const Mesh& mesh);

/// The first problem of a mesh that the module cannot work on: no faces, a non-finite position,
/// a face that is not a triangle. The error field is `what`.
std::optional<Error> validate_mesh(const Mesh& mesh, const char* what = "mesh");

// ---- Adaptive refinement and coarsening -------------------------------------------------------

struct AdaptiveSettings {
    ColourOptions colour;
    float split_lsb = 1.0f;     ///< triangles above this colour error are bisected, > 0
    float merge_ratio = 1.75f;  ///< a split is undone when its parent is below split/merge_ratio,
                                ///< >= 1 (hysteresis: 1.5 to 2 keeps the mesh from oscillating)
    std::size_t max_vertices = 1u << 20;  ///< vertex budget (live vertices)
    double time_slice_ms = 0.0;           ///< per update; 0 means no limit
    /// Re-estimate through the index of estimates (only faces that can be stale are visited);
    /// false: the round-robin sweep over every face, the reference the index is tested against.
    bool indexed_sweep = true;
    bool lock_boundary = true;  ///< boundary edges (horizon ring, tile borders) are never split
    bool coarsen = true;        ///< undo splits where the error allows
    /// A face is re-estimated when the eye has moved by more than this fraction of its distance
    /// since its last estimate, or the sun has turned by more than sun_turn_rad.
    double eye_move_fraction = 0.02;
    double sun_turn_rad = 0.002;
    /// Morphing, in updates (0: off). A new vertex blends in from the colour its parent edge
    /// showed at its place to its own over this many updates, and a bisection that coarsening
    /// undoes first fades its vertex out over as many (see AdaptiveMesh::morph_into), so that
    /// nothing pops. In 0 .. 1000.
    int morph_updates = 0;
    /// Splits and merges leave deleted elements in the mesh's arrays. An update ends with
    /// compact() when the deleted vertices or faces exceed this fraction of the live ones, so the
    /// arrays stay within (1 + ratio) x the live mesh; compaction costs O(arrays) once per
    /// ratio x live deletions (amortised O(1 + 1 / ratio) per deletion) and changes no result.
    /// 0: never (call compact() yourself). Finite, >= 0.
    float compact_garbage_ratio = 0.5f;
    /// The edge a refinement step starts its longest-edge propagation path from: false, the
    /// face's longest edge (Rivara); true, the face's edge with the largest colour error at its
    /// midpoint among those whose bisection leaves every new triangle with a smallest angle of at
    /// least colour_edge_min_angle_deg (the longest edge when none does).
    bool colour_edge = true;
    float colour_edge_min_angle_deg = 15.0f;  ///< 0 .. 60
    /// After a bisection that leaves faces above split_lsb, move the new vertex along the surface
    /// within its one-ring to where the fewest of its faces are above split_lsb, then where the
    /// sum of their errors is smallest (a pattern search in the tangent plane, projected onto the
    /// surface). Base vertices and boundary vertices never move; a move that turns a face over
    /// or leaves a face with a smallest angle below min(relocate_min_angle_deg, the smallest at
    /// the midpoint) is refused. With it the estimates take twice the samples per edge that
    /// colour_error takes (a grid containing them), so that faces where only the edge midpoints
    /// and the centroid look good are refined. Undo (a collapse into an end of the split edge)
    /// and morphing (from the parents' mean) do not depend on where the vertex went. Off by
    /// default: it tries up to 48 positions per new vertex (a dome's refinement takes 10 to 30
    /// times as long), and on terrain it saved little (one scene needed more vertices) while the
    /// updates for a moving eye took about 3 times as long. Meant for sky domes.
    bool relocate = false;
    float relocate_min_angle_deg = 15.0f;  ///< 0 .. 60
};

std::optional<Error> validate(const AdaptiveSettings& settings);

struct UpdateStats {
    std::size_t faces_estimated = 0;  ///< colour errors computed this update
    std::size_t splits = 0;           ///< edges bisected
    std::size_t merges = 0;           ///< bisections undone
    std::size_t vertices = 0;         ///< live vertices after the update
    std::size_t faces = 0;            ///< live faces after the update
    float max_error_lsb = 0.0f;       ///< largest estimate over splittable faces after the update
    bool complete = true;       ///< false when the budget or the time slice stopped refinement
    bool compacted = false;     ///< the update ended with compact(): vertex handles renumbered
    std::size_t relocated = 0;  ///< new vertices moved off their edge (settings.relocate)
};

class AdaptiveMesh {
  public:
    /// Validates the base mesh (validate_mesh), the surface and the settings.
    static Result<AdaptiveMesh> create(Mesh base, Surface surface, AdaptiveSettings settings);

    /// Re-estimates the faces whose view changed, splits, then undoes splits (see the header).
    UpdateStats update(const Frame<float>& frame);

    const Mesh& mesh() const { return mesh_; }
    const AdaptiveSettings& settings() const { return settings_; }
    /// Vertices of the base mesh: their handles are 0 .. base_vertices - 1, never moved or
    /// removed.
    std::size_t base_vertices() const { return base_vertices_; }
    /// The last estimate of a face's colour error (8-bit steps).
    float face_error(OpenMesh::FaceHandle face) const;
    /// Removes deleted elements, renumbering the live ones in their order; the undo records, the
    /// morph state and the index of estimates follow, so later updates give exactly what they
    /// would have given without it. update() calls it (settings.compact_garbage_ratio).
    void compact();
    /// Marks every colour and estimate stale: call it when anything but the eye and the sun
    /// changed (atmosphere, model, display).
    void invalidate();

    /// How much of its own colour vertex v shows, in [0, 1]: 1 for base vertices and for new ones
    /// that have blended in; (updates since it was born) / morph_updates while it blends in; going
    /// down to 0 while coarsening fades it out (it is removed at 0).
    float morph_weight(OpenMesh::VertexHandle v) const;
    /// The ends of the edge whose bisection made vertex v (also after v was removed again);
    /// invalid handles for base vertices.
    std::pair<OpenMesh::VertexHandle, OpenMesh::VertexHandle> parents(
        OpenMesh::VertexHandle v) const;
    /// Morphs per-vertex values the engine computed for this update, in place: `values` holds
    /// `components` values per vertex, `stride` values apart, for every vertex handle
    /// (mesh().n_vertices() records; deleted ones are left alone). A vertex of weight w < 1 gets
    /// the mean of its parent edge's morphed values plus w × its detail (its value minus the
    /// mean of its parents' values): at w = 0 what the screen showed there before the split, and
    /// vertices born in one update move on straight lines to their values, 1 / morph_updates of
    /// the way per update. Parents are morphed before their children. Works for any attribute the
    /// engine interpolates linearly: F_ex and L_in floats, or RGBA8 (rounded). Coarsening undoes
    /// one level of bisections per morph_updates updates (a vertex fades out before its parent
    /// can).
    void morph_into(float* values, std::size_t components, std::size_t stride) const;
    void morph_into(std::uint8_t* values, std::size_t components, std::size_t stride) const;

  private:
    AdaptiveMesh() = default;
    struct Split {
        OpenMesh::VertexHandle vertex, a, b, c, d;  ///< new vertex; edge a-b; opposites c, d
        double born = 0.0;         ///< update its weight counts from (weight 0 then)
        double fade_start = -1.0;  ///< update its fade-out began; < 0: not fading
        float fade_weight = 1.0f;  ///< its weight when the fade-out began
        /// A vertex of the ring it was born with is gone (compact() dropped it): never undone,
        /// as its ring cannot be the one it was born with again.
        bool ring_lost = false;
    };
    float record_weight(const Split& s) const;
    bool undo_allowed(std::size_t index, UpdateStats& stats, float& error_c, float& error_d);
    template <typename T>
    void morph_values(T* values, std::size_t components, std::size_t stride) const;
    glm::vec3 vertex_colour(OpenMesh::VertexHandle v);
    float estimate(OpenMesh::FaceHandle f);
    bool splittable(OpenMesh::FaceHandle f) const;
    bool edge_locked(OpenMesh::EdgeHandle e) const;
    int sample_multiple() const;
    OpenMesh::EdgeHandle longest_edge(OpenMesh::FaceHandle f) const;
    OpenMesh::EdgeHandle colour_edge(OpenMesh::FaceHandle f);
    void bisect(OpenMesh::EdgeHandle e, UpdateStats& stats);
    void relocate(OpenMesh::VertexHandle v, UpdateStats& stats);
    bool try_undo(std::size_t record, UpdateStats& stats);
    void stamp(OpenMesh::FaceHandle f, float error);
    bool face_stale(OpenMesh::FaceHandle f) const;

    // The steps of update(), in order, and the state one update passes between them.
    struct Pass;
    void queue_indexed(Pass& pass);  ///< re-estimate through the index, queue faces to refine
    void queue_sweep(Pass& pass);    ///< the same by a round-robin sweep over every face
    void refine(Pass& pass);
    void split_towards(Pass& pass, OpenMesh::FaceHandle f0);
    OpenMesh::EdgeHandle terminal_edge(OpenMesh::FaceHandle f, OpenMesh::EdgeHandle e) const;
    void coarsen(Pass& pass);
    void continue_fades(UpdateStats& stats);
    void end_index(bool indexed);
    bool garbage_over_ratio() const;

    Mesh mesh_;
    Surface surface_;
    AdaptiveSettings settings_;
    std::size_t base_vertices_ = 0;
    const Frame<float>* frame_ = nullptr;
    // Per vertex: displayed colour and the eye/sun it was computed for; per face: estimate and
    // the eye/sun of it.
    struct Vec3 {  // initialised, unlike glm's, so that copies of the mesh are well defined
        glm::vec3 v{0.0f};
    };
    OpenMesh::VPropHandleT<Vec3> colour_;
    OpenMesh::VPropHandleT<Vec3> colour_eye_;
    OpenMesh::VPropHandleT<Vec3> colour_sun_;
    OpenMesh::FPropHandleT<float> error_;
    OpenMesh::FPropHandleT<Vec3> error_eye_;
    OpenMesh::FPropHandleT<Vec3> error_sun_;
    OpenMesh::FPropHandleT<float>
        error_radius_sq_;  ///< eye moves beyond this (squared) re-estimate
    std::size_t live_vertices_ = 0;
    std::size_t live_faces_ = 0;
    std::vector<OpenMesh::VertexHandle> touched_;  ///< vertices of faces estimated this update
    float estimated_max_ = 0.0f;  ///< largest estimate at or below split_lsb made this update
    OpenMesh::VPropHandleT<int> record_;  ///< index into splits_, -1 for base vertices
    std::vector<Split> splits_;
    std::size_t cursor_ = 0;   ///< where the last time-sliced re-estimation stopped
    double updates_ = 0.0;     ///< updates so far (the morph clock)
    std::vector<int> fading_;  ///< records whose vertex fades out before its bisection is undone

    // Index of the estimates (settings.indexed_sweep) so that the sweep visits only faces
    // that can be stale. Faces stamped in one update share its eye and sun, so they form a group
    // sorted by radius: the eye-stale ones are a prefix, and all of them when the sun turned.
    struct StampGroup {
        std::uint64_t id = 0;
        glm::vec3 eye{0.0f}, sun{0.0f};
        std::vector<std::pair<float, int>> faces;  ///< (radius squared, face), sorted at the end
        std::size_t head = 0;                      ///< entries before it have been re-estimated
    };
    void rebuild_index();
    /// Returns false when `out_of_time` stopped it (the rest is visited by the next update).
    bool sweep_indexed(UpdateStats& stats, const std::function<bool()>& out_of_time);
    std::vector<StampGroup> groups_;
    std::vector<std::uint64_t> face_group_;     ///< per face: id of the group of its last stamp
    std::vector<int> above_;                    ///< faces whose estimate may exceed split_lsb
    std::vector<char> in_above_;                ///< per face: listed in above_
    std::vector<std::pair<float, int>> below_;  ///< max-heap of (estimate <= split_lsb, face)
    std::uint64_t next_group_ = 1;
    bool index_valid_ = false;
    bool recording_ = false;  ///< stamp() records into groups_.back()
};

// ---- Offline decimation -----------------------------------------------------------------------

struct DecimateOptions {
    ColourOptions colour;
    float max_lsb = 1.0f;          ///< no collapse leaves a triangle above this error, > 0
    std::size_t min_vertices = 0;  ///< stop at this many vertices
    bool lock_boundary = true;     ///< boundary vertices are never removed
};

/// Halfedge collapses (no vertex moves) ordered by the colour error they leave, through
/// OpenMesh's Decimater and a colour-error module; refuses collapses that flip a face. Returns the
/// compacted mesh.
Result<Mesh> decimate(const Mesh& mesh, const Frame<float>& frame, const DecimateOptions& options);

// ---- Run time near the decimated count ---------------------------------------------------------

/// DecimatingMesh: the run-time adaptive mesh, started from a decimated mesh instead of a coarse
/// one, and started again from a new decimated mesh when the sun or the eye has moved on.
///
/// A rebuild refines `start` to fine_split_lsb for the rebuild's frame (AdaptiveMesh), decimates
/// that to decimate_lsb (decimate()), and starts an AdaptiveMesh with `adaptive` from the result;
/// between rebuilds that adaptive mesh refines where the moving light needs it (split_lsb) and
/// coarsens its own splits again. Decimation collapses freely where bisection cannot (long
/// triangles along the horizon and around the sun), so right after a rebuild the mesh has the
/// decimated mesh's vertices. A rebuild takes seconds of CPU for a sky dome (most of it the
/// decimation); with `background` it runs on a thread of its own and update() keeps drawing the
/// current mesh until it is done (the switch changes the mesh at once: no morphing across it).
struct DecimatingSettings {
    /// The refinement between rebuilds; its colour options are the rebuilds' too.
    AdaptiveSettings adaptive;
    float fine_split_lsb = 0.55f;  ///< a rebuild first refines to this, > 0
    float decimate_lsb = 0.8f;     ///< then decimates to this bound, in [fine_split_lsb, split]
    /// A rebuild starts when the sun has turned by more than this (rad) since the current mesh's
    /// rebuild, or the eye has moved by more than rebuild_eye_m (0: the eye never triggers one).
    double rebuild_sun_rad = 0.0044;  ///< 0.25 degrees (a minute of the real sun)
    double rebuild_eye_m = 0.0;
    bool background = true;  ///< rebuild on a thread of its own; false: inside update()
};

std::optional<Error> validate(const DecimatingSettings& settings);

struct DecimatingStats {
    std::size_t rebuilds = 0;      ///< rebuilds switched to, the first one included
    bool rebuilding = false;       ///< a rebuild is running on its thread
    bool switched = false;         ///< the last update switched to a rebuilt mesh
    double last_rebuild_ms = 0.0;  ///< the last finished rebuild's time on its thread (wall)
    double rebuild_ms = 0.0;       ///< every finished rebuild's time, summed
};

class DecimatingMesh {
  public:
    /// Validates `start` (validate_mesh), the surface and the settings.
    static Result<DecimatingMesh> create(Mesh start, Surface surface, DecimatingSettings settings);
    DecimatingMesh(DecimatingMesh&&) noexcept;
    DecimatingMesh& operator=(DecimatingMesh&&) noexcept;
    ~DecimatingMesh();  ///< waits for a running rebuild

    /// The first update rebuilds at once (inside it); later ones switch to a finished rebuild,
    /// start one when the view has moved on, and update the current adaptive mesh. Errors of a
    /// rebuild (a decimation that fails) are returned by the update that would switch to it.
    Result<UpdateStats> update(const Frame<float>& frame);

    const Mesh& mesh() const;  ///< the current adaptive mesh's (empty before the first update)
    const DecimatingStats& stats() const;

  private:
    struct Impl;
    explicit DecimatingMesh(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace aerial::mesh
