// The GL grading of aerial-tess: a mesh drawn by the library's renderer (one node of
// aerial::scene::SceneRenderer, cpu backend, the frame's model, OSMesa) against the per-pixel
// reference, in 8-bit steps, the metrics of aerial-compare.
//
// How to use this:
//   1. `auto grader = aerial::tess::GlGrader::create(256);` (an OSMesa context of 256 x 256
//      pixels; it is current on this thread).
//   2. `grader->grade(mesh, frame, colour, options)` renders the six 90-degree faces of a cube
//      around the eye (frame.view.eye) and compares every covered pixel.
//
// The rendered pixel: the vertex colours the renderer computes (F_ex and display(L_in) as
// RGBA8), drawn with a 1 x 1 texture of the texel colour, L_in added by the fixed-function path
// it chooses, interpolated by the rasteriser. The reference pixel: the model
// evaluated in float at the surface point under the pixel centre, texel x F_ex + display(L_in)
// with the 8-bit rule (the perpixel backend of aerial-render): on a dome the point of the sphere
// in the pixel's view direction, on terrain the point reconstructed from the depth buffer.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"
#include "common/image_metrics.hpp"

namespace aerial::tess {

struct GlGradeOptions {
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
    /// not cover are black in the reference.
    struct Images {
        int width = 0, height = 0;
        std::vector<std::uint8_t> drawn, reference;
    };
    Images* images = nullptr;
};

class GlGrader {
  public:
    /// An OSMesa context with square faces of `face_pixels` (16 .. 2048). Errors name
    /// "face_pixels" or the context step that failed.
    static Result<GlGrader> create(int face_pixels);
    GlGrader(GlGrader&&) noexcept;
    GlGrader& operator=(GlGrader&&) noexcept;
    ~GlGrader();

    /// The differences over every covered pixel of the six faces. Errors: bad options (field
    /// "near_m" / "far_m"), shading or drawing failed, a GL error.
    Result<tools::LsbDifferences> grade(const mesh::Mesh& mesh, const Frame<float>& frame,
                                        const mesh::ColourOptions& colour,
                                        const GlGradeOptions& options);

  private:
    struct Impl;
    explicit GlGrader(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace aerial::tess
