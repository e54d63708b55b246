// Shared by the batch tests and the fuzz targets that shade: batch outputs into arrays they own.
#pragma once

#include <cstdint>
#include <vector>

#include "aerial/batch.hpp"

namespace aerial_test {

/// Outputs writing F_ex, L_in and E_sun as floats and F_ex and L_in as RGBA8 codes into the given
/// arrays (3 floats and 4 bytes a vertex); no lit colours.
inline aerial::BatchOutputs floats_and_codes(std::vector<float>& fex, std::vector<float>& lin,
                                             std::vector<float>& esun,
                                             std::vector<std::uint8_t>& fex8,
                                             std::vector<std::uint8_t>& lin8) {
    aerial::BatchOutputs out;
    out.extinction_rgb = fex.data();
    out.in_scattering_rgb = lin.data();
    out.sun_irradiance_rgb = esun.data();
    out.extinction_rgba8 = fex8.data();
    out.in_scattering_rgba8 = lin8.data();
    return out;
}

}  // namespace aerial_test
