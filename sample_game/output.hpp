// sample_game/output.hpp — from raw linear radiance to files: exposure, sRGB, PNG, CSV.
//
// How to use this:
//   1. `encode_srgb8(image, exposure)` maps each pixel's radiance through 1 - exp(-k x) into
//      [0, 1] (k = exposure), then the sRGB transfer curve, to 8-bit RGB.
//   2. `aerial::tools::write_png` (tools/common/png.hpp) and `write_csv(path, image,
//      columns_per_row)` write the results; both return an error message, or nothing on success.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render.hpp"

namespace sample {

/// Exposure constant k of 1 - exp(-k x) that makes a sunny earth landscape read well.
inline constexpr double kDefaultExposure = 10.0;

/// 8-bit sRGB, 3 bytes per pixel, row-major, top row first.
std::vector<std::uint8_t> encode_srgb8(const Image& image, double exposure);

/// Writes, for every image row, `columns_per_row` evenly spaced pixels as CSV with the header
/// x,y,surface,distance_m,fex_r,fex_g,fex_b,lin_r,lin_g,lin_b,esun_r,esun_g,esun_b
/// (raw linear values, like aerial-eval). Creates missing parent directories.
std::optional<std::string> write_csv(const std::string& path, const Image& image,
                                     int columns_per_row);

}  // namespace sample
