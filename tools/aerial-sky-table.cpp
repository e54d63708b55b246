// aerial-sky-table: each sky method against `reference`, by sun elevation (aerial/sky.hpp). Prints
// one row per method and elevation: the largest relative error over the probe directions, and
// the largest and mean difference in 8-bit steps after the auto exposure and tone curve.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "aerial/aerial.hpp"
#include "aerial/gl_api.hpp"
#include "aerial/headless.hpp"
#include "aerial/sky_gl.hpp"
#include "aerial/validation/sky_measure.hpp"
#include "support/cli.hpp"
#include "support/png.hpp"

namespace {

constexpr const char* kTool = "aerial-sky-table";

struct Row {
    std::string method;
    double elevation_deg;
    aerial::validation::SkyError error;
    bool has_relative;
};

/// The GL sky box of an RGBA8 cubemap against `reference`, pixel by pixel: five 90 deg views
/// (four azimuths at 30 deg elevation, one at the zenith) of size x size pixels, every
/// `stride`-th pixel above the horizon.
aerial::Result<aerial::validation::SkyError> measure_gl_sky_box(
    aerial::headless::Context& context, const aerial::SkyContext& reference, double exposure,
    const std::array<std::vector<std::uint8_t>, 6>& faces, int cubemap_size, int stride) {
    const aerial::gl::Api& api = context.api();
    auto texture = aerial::gl::SkyCubemapTexture::create(api, faces, cubemap_size);
    if (!texture) return texture.error();
    const int size = context.width();
    aerial::validation::SkyError error;
    double sum = 0;
    std::size_t n = 0;
    const double near_plane = 0.5, far_plane = 1000.0;
    for (int view = 0; view < 5; ++view) {
        const double az = view * aerial::kPi / 2, el = view < 4 ? aerial::kPi / 6 : aerial::kPi / 2;
        const glm::dvec3 forward(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az),
                                 std::sin(el));
        const glm::dvec3 helper = view < 4 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
        const glm::dvec3 right = glm::normalize(glm::cross(forward, helper));
        const glm::dvec3 up = glm::cross(right, forward);
        aerial::gl::SkyBoxView v;
        v.projection = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, -1, 0, 0, 0, 0};
        v.projection[10] = float(-(far_plane + near_plane) / (far_plane - near_plane));
        v.projection[14] = float(-2.0 * far_plane * near_plane / (far_plane - near_plane));
        v.view_rotation = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
        for (int c = 0; c < 3; ++c) {
            v.view_rotation[std::size_t(c * 4)] = float(right[c]);
            v.view_rotation[std::size_t(c * 4 + 1)] = float(up[c]);
            v.view_rotation[std::size_t(c * 4 + 2)] = float(-forward[c]);
        }
        api.ClearColor(0, 0, 0, 1);
        api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        if (auto e = aerial::gl::draw_sky_box(api, *texture, v)) return *e;
        const std::vector<std::uint8_t> image = context.read_rgba8();
        for (int row = stride / 2; row < size; row += stride) {
            for (int x = stride / 2; x < size; x += stride) {
                const double nx = 2.0 * (x + 0.5) / size - 1.0;
                const double ny = 2.0 * ((size - 1 - row) + 0.5) / size - 1.0;
                const glm::dvec3 d = glm::normalize(forward + nx * right + ny * up);
                if (d.z < 0) continue;
                const glm::dvec3 want = aerial::tone_map(aerial::sky_radiance(reference, d),
                                                         exposure, aerial::ToneCurve::exponential) *
                                        255.0;
                const std::size_t k = (std::size_t(row) * std::size_t(size) + std::size_t(x)) * 4;
                double worst = 0;
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, std::abs(double(image[k + std::size_t(c)]) - want[c]));
                }
                error.max_lsb = std::max(error.max_lsb, worst);
                sum += worst;
                ++n;
            }
        }
    }
    error.mean_lsb = n > 0 ? sum / double(n) : 0.0;
    return error;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "Each sky method against the reference model, by sun elevation. Per row: method,\n"
        "sun elevation, max relative error (%) and max / mean difference in 8-bit steps after\n"
        "the auto exposure and the exponential tone curve, over directions from the horizon\n"
        "to the zenith. 'dome RxS' is a per-vertex dome shaded by height-chained and\n"
        "interpolated across its triangles; 'cubemap N' is an RGBA8 cubemap of height-chained\n"
        "sampled bilinearly (what the GL sky box shows, within 1 step)."};
    // The default dome is the scene renderer's built-in sky (aerial::kSkyDomeRings x Segments).
    const std::string default_dome =
        std::to_string(aerial::kSkyDomeRings) + "x" + std::to_string(aerial::kSkyDomeSegments);
    std::string preset = "earth", atmosphere_file, dome = default_dome,
                elevations_text = "0,2,10,45,90";
    std::string csv_path, panorama_path, panorama_size = "192x48", gl_backend;
    double eye_altitude_m = 100.0;
    int cubemap_size = 64, elevation_steps = 18, azimuth_steps = 24, gl_stride = 2;
    app.add_option("--preset", preset, "atmosphere preset (earth, hp2002, hazy, foggy, mars)");
    app.add_option("--atmosphere", atmosphere_file, "atmosphere JSON file (instead of --preset)");
    app.add_option("--eye-altitude", eye_altitude_m, "eye altitude, m (default 100)");
    app.add_option(
        "--dome", dome,
        "per-vertex dome rings x segments (default " + default_dome + ", the scene renderer's)");
    app.add_option("--cubemap", cubemap_size, "cubemap face size in texels (default 64)");
    app.add_option("--elevations", elevations_text, "sun elevations, deg (default 0,2,10,45,90)");
    app.add_option("--probe", elevation_steps, "probe rows from horizon to zenith (default 18)");
    app.add_option("--csv", csv_path, "also write the rows as CSV to this file");
    app.add_option("--gl", gl_backend,
                   "also draw the cubemap with the GL sky box on this headless context (osmesa or\n"
                   "egl) and compare 64x64-pixel views with reference every 2nd pixel: row 'gl\n"
                   "cubemap N' (slow: reference per pixel)");
    app.add_option(
        "--panorama", panorama_path,
        "write a PNG of panoramas instead of the table: per sun elevation, strips of\n"
        "reference, height-chained, dome-height, dome-hp, dome-hp-single (azimuth 0..360\n"
        "left to right, elevation 90..0 top to bottom, auto exposure)");
    app.add_option("--panorama-size", panorama_size, "size of one strip WxH (default 192x48)");
    app.add_option("--gl-stride", gl_stride, "--gl compares every Nth pixel (default 2)");
    if (auto status = aerial::tools::parse_command_line(app, argc, argv, kTool)) return *status;
    if (gl_stride < 1 || gl_stride > 64) {
        return aerial::tools::fail(
            kTool, "--gl-stride: must be in 1 .. 64, got " + std::to_string(gl_stride));
    }

    auto atmosphere = atmosphere_file.empty() ? aerial::atmosphere_preset(preset)
                                              : aerial::load_atmosphere_json(atmosphere_file);
    if (!atmosphere) {
        return aerial::tools::fail(kTool,
                                   (atmosphere_file.empty() ? "--preset: " : "--atmosphere: ") +
                                       atmosphere.error().message);
    }
    auto dome_size = aerial::tools::parse_size(dome, "--dome", 1024);
    if (!dome_size) return aerial::tools::fail(kTool, dome_size.error().message);
    auto mesh = aerial::make_sky_dome_mesh(dome_size->first, dome_size->second);
    if (!mesh) return aerial::tools::fail(kTool, "--dome: " + mesh.error().message);
    if (cubemap_size < 1 || cubemap_size > 1024) {
        return aerial::tools::fail(
            kTool, "--cubemap: must be in 1 .. 1024, got " + std::to_string(cubemap_size));
    }
    if (elevation_steps < 1 || elevation_steps > 180) {
        return aerial::tools::fail(
            kTool, "--probe: must be in 1 .. 180, got " + std::to_string(elevation_steps));
    }
    if (!std::isfinite(eye_altitude_m) || eye_altitude_m < 0 || eye_altitude_m > 50000) {
        return aerial::tools::fail(kTool, "--eye-altitude: must be in 0 .. 50000 m");
    }
    std::vector<double> elevations;
    {
        std::stringstream in(elevations_text);
        std::string item;
        while (std::getline(in, item, ',')) {
            auto v = aerial::tools::parse_number(item);
            if (!v || *v < -10.0 || *v > 90.0) {
                return aerial::tools::fail(
                    kTool, "--elevations: '" + item + "' is not a number in -10 .. 90");
            }
            elevations.push_back(*v);
        }
        if (elevations.empty()) return aerial::tools::fail(kTool, "--elevations: empty list");
    }
    if (!panorama_path.empty()) {
        auto strip = aerial::tools::parse_size(panorama_size, "--panorama-size", 2048);
        if (!strip) return aerial::tools::fail(kTool, strip.error().message);
        const int w = strip->first, h = strip->second, gap = 4;
        const std::vector<aerial::SkyMethod> methods{
            aerial::SkyMethod::reference, aerial::SkyMethod::height_chained,
            aerial::SkyMethod::dome_height, aerial::SkyMethod::dome_hp,
            aerial::SkyMethod::dome_hp_single};
        const int strips = int(methods.size() * elevations.size());
        aerial::tools::Rgb8Image image;
        image.width = w;
        image.height = strips * h + (strips - 1) * gap;
        image.rgb.assign(std::size_t(image.width) * std::size_t(image.height) * 3, 255);
        int top = 0;
        for (double elevation_deg : elevations) {
            const double e = elevation_deg * aerial::kPi / 180.0;
            aerial::View view;
            view.eye = {0.0, 0.0, eye_altitude_m};
            view.sun_dir = {0.0, std::cos(e), std::sin(e)};  // due north: centre of the strip
            auto probe = aerial::validation::make_sky_probe(*atmosphere, view, 1, 1);
            if (!probe) return aerial::tools::fail(kTool, probe.error().message);
            for (aerial::SkyMethod m : methods) {
                auto sky = aerial::prepare_sky(*atmosphere, view, m);
                if (!sky) return aerial::tools::fail(kTool, sky.error().message);
                for (int y = 0; y < h; ++y) {
                    const double el = (aerial::kPi / 2) * (1.0 - (y + 0.5) / h);
                    for (int x = 0; x < w; ++x) {
                        // Azimuth from north, clockwise; north (the sun) in the middle.
                        const double az = 2 * aerial::kPi * ((x + 0.5) / w - 0.5);
                        const glm::dvec3 d(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az),
                                           std::sin(el));
                        const glm::dvec3 v =
                            aerial::tone_map(aerial::sky_radiance(*sky, d), probe->exposure,
                                             aerial::ToneCurve::exponential);
                        std::uint8_t* px =
                            &image
                                 .rgb[(std::size_t(top + y) * std::size_t(w) + std::size_t(x)) * 3];
                        for (int c = 0; c < 3; ++c) px[c] = std::uint8_t(std::lround(v[c] * 255.0));
                    }
                }
                top += h + gap;
            }
        }
        if (auto e = aerial::tools::write_png(panorama_path, image)) {
            return aerial::tools::fail(kTool, "--panorama: " + *e);
        }
        std::printf("wrote %s (%d x %d)\n", panorama_path.c_str(), image.width, image.height);
        return 0;
    }
    std::optional<aerial::headless::Context> context;
    if (!gl_backend.empty()) {
        auto backend = aerial::headless::parse_platform(gl_backend);
        if (!backend) {
            return aerial::tools::fail(kTool,
                                       "--gl: expected osmesa or egl, got '" + gl_backend + "'");
        }
        auto created = aerial::headless::Context::create({*backend, 64, 64});
        if (!created) return aerial::tools::fail(kTool, "--gl: " + created.error().message);
        context.emplace(std::move(created).value());
        if (!aerial::gl::cube_maps_supported(context->api())) {
            return aerial::tools::fail(kTool, "--gl: the context has no cube maps");
        }
    }
    std::ofstream csv;
    if (!csv_path.empty()) {
        csv.open(csv_path);
        if (!csv) return aerial::tools::fail(kTool, "--csv: cannot write '" + csv_path + "'");
        csv << "method,sun_elevation_deg,max_relative,max_lsb,mean_lsb\n";
    }

    std::printf("%-16s %8s %10s %8s %8s\n", "method", "sun_deg", "max_rel_%", "max_lsb",
                "mean_lsb");
    const auto start = std::chrono::steady_clock::now();
    for (double elevation_deg : elevations) {
        const double e = elevation_deg * aerial::kPi / 180.0;
        aerial::View view;
        view.eye = {0.0, 0.0, eye_altitude_m};
        view.sun_dir = {std::cos(e) * 0.8, std::cos(e) * 0.6, std::sin(e)};
        auto probe =
            aerial::validation::make_sky_probe(*atmosphere, view, elevation_steps, azimuth_steps);
        if (!probe) return aerial::tools::fail(kTool, probe.error().message);
        std::vector<Row> rows;
        for (aerial::SkyMethod m : aerial::all_sky_methods()) {
            if (m == aerial::SkyMethod::reference) continue;
            auto sky = aerial::prepare_sky(*atmosphere, view, m);
            if (!sky) return aerial::tools::fail(kTool, sky.error().message);
            rows.push_back({std::string(aerial::sky_method_name(m)), elevation_deg,
                            aerial::validation::measure_sky_method(*probe, *sky), true});
        }
        auto chained = aerial::prepare_sky(*atmosphere, view, aerial::SkyMethod::height_chained);
        rows.push_back({"dome " + dome, elevation_deg,
                        aerial::validation::measure_sky_dome(*probe, *chained, *mesh), true});
        auto cubemap = aerial::compute_sky_cubemap(*chained, cubemap_size);
        if (!cubemap) return aerial::tools::fail(kTool, cubemap.error().message);
        const auto faces =
            aerial::cubemap_to_rgba8(*cubemap, probe->exposure, aerial::ToneCurve::exponential);
        rows.push_back({"cubemap " + std::to_string(cubemap_size), elevation_deg,
                        aerial::validation::measure_sky_cubemap(*probe, faces, cubemap_size),
                        false});
        if (context) {
            auto reference = aerial::prepare_sky(*atmosphere, view, aerial::SkyMethod::reference);
            auto gl_error = measure_gl_sky_box(*context, *reference, probe->exposure, faces,
                                               cubemap_size, gl_stride);
            if (!gl_error) return aerial::tools::fail(kTool, "--gl: " + gl_error.error().message);
            rows.push_back(
                {"gl cubemap " + std::to_string(cubemap_size), elevation_deg, *gl_error, false});
        }
        for (const Row& r : rows) {
            char rel[32];
            if (r.has_relative) {
                std::snprintf(rel, sizeof rel, "%.2f", 100.0 * r.error.max_relative);
            } else {
                std::snprintf(rel, sizeof rel, "-");
            }
            std::printf("%-16s %8.1f %10s %8.0f %8.2f\n", r.method.c_str(), r.elevation_deg, rel,
                        r.error.max_lsb, r.error.mean_lsb);
            if (csv) {
                csv << r.method << ',' << r.elevation_deg << ','
                    << (r.has_relative ? std::to_string(r.error.max_relative) : "") << ','
                    << r.error.max_lsb << ',' << r.error.mean_lsb << '\n';
            }
        }
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("# %s, eye %.0f m, probe %d x %d directions, %.1f s\n",
                atmosphere_file.empty() ? preset.c_str() : atmosphere_file.c_str(), eye_altitude_m,
                elevation_steps + 1, azimuth_steps, seconds);
    return 0;
}
