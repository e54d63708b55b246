// Offline decimation: OpenMesh's Decimater with a module that scores each halfedge collapse by
// the colour error of the faces it leaves.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModBaseT.hh>
#include <glm/geometric.hpp>

#include "../common/error_text.hpp"
#include "aerial/mesh.hpp"
#include "mesh_internal.hpp"

namespace aerial::mesh {
namespace {

// The Decimater constructs modules from the mesh alone; the frame and the options come through
// set_parameters() after add().
template <class MeshT>
class ModColourErrorT : public OpenMesh::Decimater::ModBaseT<MeshT> {
  public:
    DECIMATING_MODULE(ModColourErrorT, MeshT, ColourError);

    explicit ModColourErrorT(MeshT& mesh) : Base(mesh, false) {}

    void set_parameters(const Frame<float>* frame, const DecimateOptions* options) {
        frame_ = frame;
        options_ = options;
    }

    void initialize() override {
        colour_.assign(this->mesh().n_vertices(), glm::vec3(0.0f));
        for (auto v : this->mesh().vertices())
            colour_[v.idx()] =
                display_colour(*frame_, options_->colour, to_glm(this->mesh().point(v)));
    }

    float collapse_priority(const CollapseInfo& ci) override {
        MeshT& m = this->mesh();
        if (options_->lock_boundary && m.is_boundary(ci.v0)) return float(Base::ILLEGAL_COLLAPSE);
        float worst = 0.0f;
        const bool no_skip[3] = {false, false, false};
        for (auto f : m.vf_range(ci.v0)) {
            if (f == ci.fl || f == ci.fr) continue;
            glm::dvec3 before[3], after[3];
            glm::vec3 c[3];
            int k = 0;
            for (auto v : m.fv_range(f)) {
                before[k] = to_glm(m.point(v));
                const auto w = v == ci.v0 ? ci.v1 : v;
                after[k] = to_glm(m.point(w));
                c[k] = colour_[w.idx()];
                ++k;
            }
            const glm::dvec3 n0 = glm::cross(before[1] - before[0], before[2] - before[0]);
            const glm::dvec3 n1 = glm::cross(after[1] - after[0], after[2] - after[0]);
            // No flips, and no face turned by more than 60 degrees (a fan of horizon vertices
            // would otherwise close the dome with a flat floor).
            if (!(glm::dot(n0, n1) > 0.5 * glm::length(n0) * glm::length(n1)))
                return float(Base::ILLEGAL_COLLAPSE);
            worst = std::max(worst,
                             colour_error_skipping(*frame_, options_->colour, after, c, no_skip));
            if (worst > options_->max_lsb) return float(Base::ILLEGAL_COLLAPSE);
        }
        return worst;
    }

  private:
    const Frame<float>* frame_ = nullptr;
    const DecimateOptions* options_ = nullptr;
    std::vector<glm::vec3> colour_;
};

}  // namespace

Result<Mesh> decimate(const Mesh& mesh, const Frame<float>& frame, const DecimateOptions& options) {
    constexpr const char* kFunction = "mesh::decimate";
    if (auto e = validate(options.colour)) return aerial::detail::from(kFunction, *e);
    if (auto e = validate_mesh(mesh)) return aerial::detail::from(kFunction, *e);
    if (!(options.max_lsb > 0.0f) || !std::isfinite(options.max_lsb)) {
        return aerial::detail::invalid(kFunction, "max_lsb", "a finite value > 0",
                                       aerial::detail::number(options.max_lsb));
    }
    Mesh out = mesh;
    out.garbage_collection();
    OpenMesh::Decimater::DecimaterT<Mesh> decimater(out);
    typename ModColourErrorT<Mesh>::Handle handle;
    decimater.add(handle);
    decimater.module(handle).set_parameters(&frame, &options);
    if (!decimater.initialize())
        return aerial::detail::error(kFunction, "mesh", "the decimater did not initialise");
    if (options.min_vertices > 0)
        decimater.decimate_to(options.min_vertices);
    else
        decimater.decimate();
    out.garbage_collection();
    return out;
}

}  // namespace aerial::mesh
