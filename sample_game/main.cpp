// aerial-sample: renders a hazy landscape headless with the physics core (public API only) and
// writes a PNG, optionally with CSV of the raw values the core returned.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>

#include "aerial/aerial.hpp"
#include "common/png.hpp"
#include "output.hpp"
#include "render.hpp"

namespace {

constexpr const char* kTool = "aerial-sample";

constexpr const char* kDescription =
    "Renders a procedural landscape seen from 300 m above the ground, with aerial perspective\n"
    "from the aerial physics core: per pixel, F_ex and L_in of the segment from the eye to the\n"
    "terrain (or to a sky point 200 km away), colour = lit albedo * F_ex + L_in, then exposure\n"
    "1 - exp(-k x) and sRGB. Writes a PNG and prints one summary line.\n"
    "Exit status: 0 on success, 2 on bad input.";

/// Largest accepted image side, pixels.
constexpr int kMaxSide = 16384;
/// Pixels per image row written to the CSV.
constexpr int kCsvColumnsPerRow = 16;

int fail(const std::string& message) {
    std::cerr << kTool << ": " << message << '\n';
    return 2;
}

/// Parses "WxH" with both sides in 1..kMaxSide.
bool parse_size(const std::string& text, int& width, int& height) {
    unsigned long w = 0, h = 0;
    int consumed = 0;
    if (std::sscanf(text.c_str(), "%lux%lu%n", &w, &h, &consumed) != 2 ||
        size_t(consumed) != text.size() || text[0] == '-' || w < 1 || h < 1 || w > kMaxSide ||
        h > kMaxSide) {
        return false;
    }
    width = int(w);
    height = int(h);
    return true;
}

std::string format_number(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", v);
    return buffer;
}

std::string format_rgb(const glm::dvec3& v) {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "%.4g,%.4g,%.4g", v.x, v.y, v.z);
    return buffer;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{kDescription, kTool};
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    std::string out = "build/out/sample.png", size = "640x360", preset = "earth",
                model_text = "height", csv;
    double sun_elevation_deg = 12.0, sun_azimuth_deg = 28.0, exposure = sample::kDefaultExposure;
    app.add_option("--out", out, "PNG file to write (parent directories are created)")
        ->capture_default_str();
    app.add_option("--size", size, "Image size WxH in pixels")->capture_default_str();
    app.add_option("--preset", preset, "Atmosphere preset: earth, hp2002, hazy, foggy, mars")
        ->capture_default_str();
    app.add_option("--model", model_text,
                   "hoffman-preetham, height or reference (reference is slow: minutes at 640x360)")
        ->capture_default_str();
    app.add_option("--sun-elevation-deg", sun_elevation_deg,
                   "Sun elevation above the horizon, degrees, -90..90")
        ->capture_default_str();
    app.add_option("--sun-azimuth-deg", sun_azimuth_deg,
                   "Sun azimuth, degrees clockwise from the view direction (north)")
        ->capture_default_str();
    app.add_option("--exposure", exposure, "Exposure k of 1 - exp(-k x), > 0")
        ->capture_default_str();
    app.add_option("--csv", csv,
                   "Also write CSV: 16 pixels per row, x,y,surface,distance_m,fex_*,lin_*,esun_*");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return 0;
    } catch (const CLI::ParseError& e) {
        std::string what = e.what();
        if (what.empty()) what = e.get_name();
        return fail(what + " (see --help)");
    }

    sample::RenderSettings settings;
    if (!parse_size(size, settings.width, settings.height)) {
        return fail("--size: expected WxH with W and H in 1.." + std::to_string(kMaxSide) +
                    ", got '" + size + "'");
    }
    auto atmosphere = aerial::atmosphere_preset(preset);
    if (!atmosphere) return fail("--preset: " + atmosphere.error().message);
    settings.atmosphere = *atmosphere;
    auto model = aerial::parse_model(model_text);
    if (!model) return fail("--model: " + model.error().message);
    settings.model = *model;
    if (!(std::abs(sun_elevation_deg) <= 90.0)) {
        return fail("--sun-elevation-deg: expected a value in -90..90, got " +
                    format_number(sun_elevation_deg));
    }
    if (!std::isfinite(sun_azimuth_deg)) {
        return fail("--sun-azimuth-deg: expected a finite number of degrees");
    }
    if (!(exposure > 0.0) || !std::isfinite(exposure)) {
        return fail("--exposure: expected a finite value > 0, got " + format_number(exposure));
    }
    if (out.empty()) return fail("--out: expected a file name");

    const double elevation = sun_elevation_deg * aerial::kPi / 180.0;
    const double azimuth = sun_azimuth_deg * aerial::kPi / 180.0;
    settings.sun_dir = {std::cos(elevation) * std::sin(azimuth),
                        std::cos(elevation) * std::cos(azimuth), std::sin(elevation)};
    settings.threads = int(std::max(1u, std::thread::hardware_concurrency()));
    if (settings.model == aerial::Model::reference) {
        std::cerr << kTool
                  << ": warning: --model reference integrates every pixel numerically; expect "
                     "minutes at 640x360 (try --size 160x90)\n";
    }

    auto image = sample::render(settings);
    if (!image) return fail(image.error().message);

    const aerial::tools::Rgb8Image png{image->width, image->height,
                                       sample::encode_srgb8(*image, exposure)};
    if (auto error = aerial::tools::write_png(out, png)) {
        return fail("--out " + *error);
    }
    if (!csv.empty()) {
        if (auto error = sample::write_csv(csv, *image, kCsvColumnsPerRow)) {
            return fail("--csv " + *error);
        }
    }

    glm::dvec3 sum_extinction{0.0}, sum_in_scattering{0.0};
    for (const sample::Pixel& p : image->pixels) {
        sum_extinction += glm::dvec3(p.scattering.extinction);
        sum_in_scattering += glm::dvec3(p.scattering.in_scattering);
    }
    const double n = double(image->pixels.size());
    std::printf(
        "%s: %dx%d preset=%s model=%s threads=%d time=%.2fs mean_fex=%s mean_lin=%s -> %s\n", kTool,
        image->width, image->height, preset.c_str(), model_text.c_str(), settings.threads,
        image->seconds, format_rgb(sum_extinction / n).c_str(),
        format_rgb(sum_in_scattering / n).c_str(), out.c_str());
    return 0;
}
