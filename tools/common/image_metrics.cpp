#include "common/image_metrics.hpp"

#include <lcms2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

namespace aerial::tools {
namespace {

/// Mean CIEDE2000 of the pixels, both images taken as sRGB.
double mean_de2000(const Rgb8Image& a, const Rgb8Image& b) {
    using ProfilePtr = std::unique_ptr<void, cmsBool (*)(cmsHPROFILE)>;
    const ProfilePtr srgb(cmsCreate_sRGBProfile(), &cmsCloseProfile);
    const ProfilePtr lab(cmsCreateLab4Profile(nullptr), &cmsCloseProfile);
    const std::unique_ptr<void, void (*)(cmsHTRANSFORM)> transform(
        cmsCreateTransform(srgb.get(), TYPE_RGB_8, lab.get(), TYPE_Lab_DBL,
                           INTENT_RELATIVE_COLORIMETRIC, cmsFLAGS_NOCACHE),
        &cmsDeleteTransform);
    const std::size_t pixels = a.rgb.size() / 3;
    std::vector<cmsCIELab> lab_a(pixels), lab_b(pixels);
    cmsDoTransform(transform.get(), a.rgb.data(), lab_a.data(), cmsUInt32Number(pixels));
    cmsDoTransform(transform.get(), b.rgb.data(), lab_b.data(), cmsUInt32Number(pixels));
    double sum = 0.0;
    for (std::size_t i = 0; i < pixels; ++i) {
        sum += cmsCIE2000DeltaE(&lab_a[i], &lab_b[i], 1.0, 1.0, 1.0);
    }
    return pixels ? sum / double(pixels) : 0.0;
}

}  // namespace

std::array<std::uint8_t, 3> diff_colour(int lsb, const std::uint8_t* a) {
    if (lsb == 0) {
        const auto grey = std::uint8_t((int(a[0]) * 54 + int(a[1]) * 183 + int(a[2]) * 19) / 1024);
        return {grey, grey, grey};
    }
    if (lsb == 1) return {0, 90, 255};
    if (lsb == 2) return {0, 200, 0};
    if (lsb <= 4) return {255, 230, 0};
    if (lsb <= 8) return {255, 128, 0};
    return {255, 0, 0};
}

ImageDifferences compare_images(const Rgb8Image& a, const Rgb8Image& b, Rgb8Image* diff) {
    const std::size_t pixels = a.rgb.size() / 3;
    LsbHistogram histogram;
    if (diff) *diff = {a.width, a.height, std::vector<std::uint8_t>(a.rgb.size())};
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::uint8_t* pa = &a.rgb[3 * i];
        const int lsb = histogram.add(pa, &b.rgb[3 * i]);
        if (diff) {
            const auto colour = diff_colour(lsb, pa);
            std::copy(colour.begin(), colour.end(), &diff->rgb[3 * i]);
        }
    }
    ImageDifferences d;
    static_cast<LsbDifferences&>(d) = histogram.differences();
    d.de2000_mean = mean_de2000(a, b);
    return d;
}

namespace {

std::string fraction_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

}  // namespace

std::string LsbTolerance::violations(const LsbDifferences& d) const {
    std::string out;
    const auto add = [&](const std::string& text) { out += (out.empty() ? "" : ", ") + text; };
    if (max_lsb && d.max_lsb > *max_lsb) {
        add("max_lsb " + std::to_string(d.max_lsb) + " > " + std::to_string(*max_lsb));
    }
    if (p99_lsb && d.p99_lsb > *p99_lsb) {
        add("p99_lsb " + std::to_string(d.p99_lsb) + " > " + std::to_string(*p99_lsb));
    }
    if (min_p99_lsb && d.p99_lsb < *min_p99_lsb) {
        add("p99_lsb " + std::to_string(d.p99_lsb) + " < " + std::to_string(*min_p99_lsb));
    }
    if (max_over1 && d.over1 > *max_over1) {
        add("over1 " + fraction_text(d.over1) + " > " + fraction_text(*max_over1));
    }
    if (max_over2 && d.over2 > *max_over2) {
        add("over2 " + fraction_text(d.over2) + " > " + fraction_text(*max_over2));
    }
    return out;
}

std::string LsbTolerance::text() const {
    std::string out;
    const auto add = [&](const char* name, const std::string& value) {
        out += (out.empty() ? "" : " ") + std::string(name) + value;
    };
    if (max_lsb) add("max_lsb<=", std::to_string(*max_lsb));
    if (p99_lsb) add("p99_lsb<=", std::to_string(*p99_lsb));
    if (min_p99_lsb) add("min_p99_lsb>=", std::to_string(*min_p99_lsb));
    if (max_over1) add("max_over1<=", fraction_text(*max_over1));
    if (max_over2) add("max_over2<=", fraction_text(*max_over2));
    return out;
}

}  // namespace aerial::tools
