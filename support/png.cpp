#include "support/png.hpp"

#include <filesystem>
#include <system_error>

#include <png.h>

namespace aerial::tools {

Rgb8Image rgb_from_rgba8(int width, int height, const std::vector<std::uint8_t>& rgba) {
    Rgb8Image image;
    image.width = width;
    image.height = height;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    image.rgb.resize(pixels * 3);
    for (std::size_t i = 0; i < pixels && 4 * i + 3 < rgba.size(); ++i) {
        for (std::size_t c = 0; c < 3; ++c) image.rgb[3 * i + c] = rgba[4 * i + c];
    }
    return image;
}

std::optional<std::string> make_parent_directories(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (parent.empty()) return std::nullopt;
    std::error_code error;
    std::filesystem::create_directories(parent, error);
    if (error)
        return path + ": cannot create directory " + parent.string() + ": " + error.message();
    return std::nullopt;
}

std::optional<std::string> write_png(const std::string& path, const Rgb8Image& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.rgb.size() != std::size_t(image.width) * std::size_t(image.height) * 3) {
        return path + ": cannot write PNG: the image is empty or its size does not match";
    }
    if (auto error = make_parent_directories(path)) return error;
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = png_uint_32(image.width);
    png.height = png_uint_32(image.height);
    png.format = PNG_FORMAT_RGB;
    if (png_image_write_to_file(&png, path.c_str(), 0, image.rgb.data(), 0, nullptr) == 0) {
        const std::string message = path + ": cannot write PNG: " + png.message;
        png_image_free(&png);
        return message;
    }
    return std::nullopt;
}

Result<Rgb8Image> read_png(const std::string& path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error)) {
        return Error{path, path + ": cannot read PNG: no such file"};
    }
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
        const std::string message = path + ": cannot read PNG: " + png.message;
        png_image_free(&png);
        return Error{path, message};
    }
    png.format = PNG_FORMAT_RGB;
    Rgb8Image image;
    image.width = int(png.width);
    image.height = int(png.height);
    image.rgb.resize(PNG_IMAGE_SIZE(png));
    png_color black{0, 0, 0};
    if (png_image_finish_read(&png, &black, image.rgb.data(), 0, nullptr) == 0) {
        const std::string message = path + ": cannot read PNG: " + png.message;
        png_image_free(&png);
        return Error{path, message};
    }
    return image;
}

}  // namespace aerial::tools
