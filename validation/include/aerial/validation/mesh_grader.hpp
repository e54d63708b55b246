// aerial/validation/mesh_grader.hpp — how far a mesh's per-vertex colours are from the exact
// per-pixel colour, in 8-bit steps: the grading of aerial-tess, for your own programs.
//
// A mesh drawn by the library's renderer (one node of aerial::scene::SceneRenderer, cpu backend,
// the frame's model, OSMesa) against the per-pixel reference, on the six 90-degree faces of a
// cube around the eye, with aerial-compare's metrics.
//
// How to use this:
//   1. `auto grader = aerial::validation::MeshGrader::create(128);` (an OSMesa context of faces of
//      128 x 128 pixels; it is current on this thread).
//   2. A scene: `auto scene = aerial::validation::make_tess_scene(spec);` (tess_scenes.hpp), or a
//      frame, colour options and MeshGradeOptions of your own.
//   3. `grader->grade(scene->setting, mesh)` for an aerial::mesh::Mesh, or
//      `grader->grade(scene->setting, data)` for a scene::MeshData read with
//      scene::load_mesh_file (OBJ, OFF, PLY): the figures (max, p99, RMSE, share over 1 and 2
//      steps, pixels graded).
//
// The drawn pixel: the vertex colours the renderer computes (F_ex and display(L_in) as RGBA8),
// drawn with a 1 x 1 texture of the texel colour, L_in added by the fixed-function path it
// chooses, interpolated by the rasteriser. The reference pixel: the model evaluated in float at
// the surface point under the pixel centre, texel x F_ex + display(L_in) with the 8-bit rule (the
// perpixel backend of aerial-render): on a dome the point of the sphere in the pixel's view
// direction, on terrain the point reconstructed from the depth buffer. Link aerial::validation
// (installed as the `validation` component: find_package(aerial CONFIG COMPONENTS validation)).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "aerial/error.hpp"
#include "aerial/mesh.hpp"
#include "aerial/scattering.hpp"
#include "aerial/scene.hpp"
#include "aerial/validation/lsb_figures.hpp"

namespace aerial::validation {

/// The figures of one grading: a pixel's difference is the largest of |drawn - reference| over
/// R, G and B; rmse_lsb is over every channel of every pixel; count is the pixels graded.
using MeshGrade = LsbFigures<int>;

struct MeshGradeOptions {
    /// A dome: the reference is evaluated on this sphere, in each pixel's view direction.
    /// Absent: at the point reconstructed from depth (terrain).
    std::optional<mesh::DomeOptions> dome;
    double near_m = 1.0;      ///< near clip plane, > 0 (depth precision on terrain)
    double far_m = 200000.0;  ///< far clip plane, > near_m
    /// Where the image is wrong: when set, every pixel off by at least `report_lsb` steps is
    /// appended here (aerial-tess --where).
    struct Pixel {
        glm::dvec3 point;  ///< the surface point under the pixel centre (the reference's)
        std::uint8_t drawn[3], reference[3];
    };
    std::vector<Pixel>* report = nullptr;
    int report_lsb = 2;
    /// When set, the drawn and the reference images (RGB, top row first), the six faces side by
    /// side (+x, -x, +y, -y, +z, -z): 6 face_pixels wide, face_pixels high; pixels the mesh does
    /// not cover are black in the reference and 0 in `covered` (1 where graded).
    struct Images {
        int width = 0, height = 0;
        std::vector<std::uint8_t> drawn, reference, covered;
    };
    Images* images = nullptr;
};

/// What a mesh is graded under: the frame (atmosphere, eye, sun, model), the vertex colours'
/// texel and display, and where the reference is taken.
struct GradeSetting {
    Frame<float> frame;
    mesh::ColourOptions colour;
    MeshGradeOptions options;
};

class MeshGrader {
  public:
    /// An OSMesa context with square faces of `face_pixels` (16 .. 2048). Errors name
    /// "face_pixels" or the context step that failed.
    static Result<MeshGrader> create(int face_pixels);
    MeshGrader(MeshGrader&&) noexcept;
    MeshGrader& operator=(MeshGrader&&) noexcept;
    ~MeshGrader();

    int face_pixels() const;

    /// The differences over every covered pixel of the six faces. Errors: bad options (field
    /// "near_m" / "far_m"), shading or drawing failed, a GL error, no pixel covered ("mesh").
    Result<MeshGrade> grade(const GradeSetting& setting, const mesh::Mesh& mesh);
    /// The same for triangles read from a file (scene::load_mesh_file): made into a mesh as
    /// mesh_from_data does, so a mesh written out and read back grades bit for bit as itself.
    Result<MeshGrade> grade(const GradeSetting& setting, const scene::MeshData& data);

  private:
    struct Impl;
    explicit MeshGrader(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// The triangles of `data` as the module's mesh (positions widened to double, face normals
/// computed). Errors: a triangle OpenMesh refuses (non-manifold, a repeated vertex), naming its
/// index ("triangles[12]").
Result<mesh::Mesh> mesh_from_data(const scene::MeshData& data);

}  // namespace aerial::validation
