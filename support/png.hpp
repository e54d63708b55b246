// Shared PNG reading and writing (libpng's simplified API) for the tools and the sample game:
// 8-bit RGB images, top row first, one helper instead of a copy per program.
//
// How to use this:
//   1. `write_png(path, image)` writes an 8-bit RGB PNG, creating missing parent directories.
//   2. `read_png(path)` reads any PNG libpng understands and converts it to 8-bit RGB (alpha is
//      composited on black, 16-bit and palette images are reduced to 8-bit RGB).
// Both return errors as values: the message starts with the path and says what went wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "aerial/error.hpp"

namespace aerial::tools {

/// An 8-bit RGB image: width × height × 3 bytes, row-major, top row first.
struct Rgb8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;

    const std::uint8_t* pixel(int x, int y) const {
        return rgb.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
    }
};

/// The RGB part of an RGBA8 buffer (width × height × 4 bytes, top row first).
Rgb8Image rgb_from_rgba8(int width, int height, const std::vector<std::uint8_t>& rgba);

/// Creates the parent directories of `path`; the error names the path and the directory.
std::optional<std::string> make_parent_directories(const std::string& path);

/// Writes an 8-bit RGB PNG; creates missing parent directories.
std::optional<std::string> write_png(const std::string& path, const Rgb8Image& image);

/// Reads a PNG as 8-bit RGB. Error field: the path.
Result<Rgb8Image> read_png(const std::string& path);

}  // namespace aerial::tools
