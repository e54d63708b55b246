// The scalar block kernel: a plain loop over scatter<float>, the reference for the SIMD kernel.
#include <cmath>

#include <glm/geometric.hpp>

#include "batch_kernels.hpp"

namespace aerial::detail {

std::size_t shade_block_scalar(const Frame<float>& frame, const KernelBlock& block) {
    std::size_t invalid = 0;
    for (std::size_t i = 0; i < block.count; ++i) {
        const glm::vec3 p(block.x[i], block.y[i], block.z[i]);
        const float distance = glm::length(p * frame.meters_per_unit - frame.eye_m);
        if (!(distance <= float(kMaxDistanceM))) ++invalid;
        const Scattering<float> s = scatter(frame, p);
        for (int c = 0; c < 3; ++c) {
            if (block.extinction[c]) block.extinction[c][i] = s.extinction[c];
            if (block.in_scattering[c]) block.in_scattering[c][i] = s.in_scattering[c];
            if (block.sun_irradiance[c]) block.sun_irradiance[c][i] = s.sun_irradiance[c];
        }
    }
    return invalid;
}

}  // namespace aerial::detail
