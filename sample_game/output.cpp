#include "output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "common/png.hpp"

namespace sample {
namespace {

/// sRGB transfer curve (IEC 61966-2-1) of a linear value in [0, 1].
double srgb_encode(double linear) {
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

const char* surface_name(Surface surface) {
    switch (surface) {
        case Surface::sky:
            return "sky";
        case Surface::ground:
            return "ground";
        case Surface::water:
            return "water";
    }
    return "unknown";
}

}  // namespace

std::vector<std::uint8_t> encode_srgb8(const Image& image, double exposure) {
    std::vector<std::uint8_t> rgb(image.pixels.size() * 3);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const double x = std::max(0.0, double(image.pixels[i].radiance[c]));
            const double display = srgb_encode(1.0 - std::exp(-exposure * x));
            rgb[3 * i + size_t(c)] =
                static_cast<std::uint8_t>(std::lround(std::clamp(display, 0.0, 1.0) * 255.0));
        }
    }
    return rgb;
}

std::optional<std::string> write_csv(const std::string& path, const Image& image,
                                     int columns_per_row) {
    if (auto error = aerial::tools::make_parent_directories(path)) return error;
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "w"),
                                                               &std::fclose);
    if (!file) return path + ": cannot open for writing";
    std::FILE* out = file.get();
    std::fprintf(out,
                 "x,y,surface,distance_m,fex_r,fex_g,fex_b,lin_r,lin_g,lin_b,esun_r,esun_g,"
                 "esun_b\n");
    const int columns = std::clamp(columns_per_row, 1, image.width);
    for (int y = 0; y < image.height; ++y) {
        for (int i = 0; i < columns; ++i) {
            const int x = int((i + 0.5) * image.width / columns);
            const Pixel& p = image.pixels[size_t(y) * image.width + x];
            const aerial::Scattering<float>& s = p.scattering;
            std::fprintf(out, "%d,%d,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", x, y,
                         surface_name(p.surface), p.distance_m, s.extinction.x, s.extinction.y,
                         s.extinction.z, s.in_scattering.x, s.in_scattering.y, s.in_scattering.z,
                         s.sun_irradiance.x, s.sun_irradiance.y, s.sun_irradiance.z);
        }
    }
    if (std::fflush(out) != 0 || std::ferror(out) != 0) return path + ": cannot write";
    return std::nullopt;
}

}  // namespace sample
