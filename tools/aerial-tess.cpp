// aerial-tess: how many vertices each tessellation needs for the per-vertex colour to be within
// one 8-bit step of the exact per-pixel colour, on sky domes and terrain (issue 6).
//
// Every mesh is graded by the same independent dense measure, never by the refinement's own
// estimate: the image its per-vertex colours give through the module's fixed-function GL path
// (OSMesa) against the per-pixel reference, on the six faces of a cube around the eye
// (tess/gl_grade.hpp), with aerial-compare's metrics. Writes DIR/tess.csv and DIR/tess.png (through
// tools/plot_tess.py), prints per scene the vertices each method needs for max <= 1 LSB.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>

#include "aerial/adaptive_scene.hpp"
#include "aerial/aerial.hpp"
#include "aerial/mesh.hpp"
#include "aerial/validation/mesh_grader.hpp"
#include "aerial/validation/tess_scenes.hpp"
#include "common/image_metrics.hpp"
#include "support/cli.hpp"
#include "support/png.hpp"
#include "tess/bench_update.hpp"
#include "tess/mesh_files.hpp"
#include "tess/methods.hpp"
#include "tess/path_mode.hpp"
#include "tess/summary.hpp"

namespace {

constexpr const char* kTool = "aerial-tess";
constexpr double kPi = 3.14159265358979323846;
using Clock = std::chrono::steady_clock;
using aerial::mesh::Mesh;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

using Scene = aerial::validation::TessScene;
using Row = aerial::tess::GradedRow;

struct Settings {
    bool quick = false;
    int face_pixels = 128;  ///< per cube face: 90 deg / 128 = 0.012 rad per pixel
    double lod_exponent = 2.0;
    bool quantized_estimate = true;  ///< adaptive domes: 8-bit vertex colours, sphere samples
    /// Adaptive meshes: AdaptiveSettings::colour_edge (-1: the library's default, 0 off, 1 on)
    /// and its angle bound (< 0: the default).
    int colour_edge = -1;
    double colour_edge_angle = -1.0;
    int relocate = -1;  ///< AdaptiveSettings::relocate (-1: the library's default, 0 off, 1 on)
    aerial::validation::MeshGrader* grader = nullptr;
    std::string export_dir;            ///< --export-meshes: every graded mesh written here as OBJ
    std::string images_dir;            ///< --save-images: drawn, reference and difference PNGs here
    std::vector<std::string> methods;  ///< --methods: the built-in methods to sweep (empty: all)
};

// PREFIX-drawn.png, PREFIX-reference.png and PREFIX-diff.png (aerial-compare's difference
// image: equal pixels dimmed grey, others coloured by their steps) of a grading's images.
std::optional<std::string> save_images(const aerial::validation::MeshGradeOptions::Images& images,
                                       const std::string& prefix) {
    aerial::tools::Rgb8Image drawn, reference, diff;
    drawn.width = reference.width = images.width;
    drawn.height = reference.height = images.height;
    drawn.rgb = images.drawn;
    reference.rgb = images.reference;
    aerial::tools::compare_images(drawn, reference, &diff);
    for (const auto& [suffix, image] :
         {std::pair<const char*, const aerial::tools::Rgb8Image*>{"-drawn.png", &drawn},
          {"-reference.png", &reference},
          {"-diff.png", &diff}}) {
        if (auto e = aerial::tools::write_png(prefix + suffix, *image)) return e;
    }
    return std::nullopt;
}

Row grade(const Scene& scene, const std::string& method, const std::string& level, const Mesh& mesh,
          double build_ms, const Settings& settings) {
    Row row;
    row.scene = scene.name;
    row.method = method;
    row.level = level;
    row.vertices = aerial::mesh::live_vertices(mesh);
    row.triangles = aerial::mesh::live_faces(mesh);
    row.build_ms = build_ms;
    if (!settings.export_dir.empty()) {
        const std::string path =
            settings.export_dir + "/" + scene.name + "/" + method + "-" + level + ".obj";
        if (auto e = aerial::tess::write_obj(path, aerial::scene::mesh_data_from(mesh))) {
            std::fprintf(stderr, "%s: %s: %s\n", kTool, e->field.c_str(), e->message.c_str());
            std::exit(1);
        }
    }
    aerial::validation::GradeSetting setting = scene.setting;
    aerial::validation::MeshGradeOptions::Images images;
    if (!settings.images_dir.empty()) setting.options.images = &images;
    const auto start = Clock::now();
    auto graded = settings.grader->grade(setting, mesh);
    row.grade_ms = ms_since(start);
    if (graded && setting.options.images) {
        if (auto e = save_images(
                images, settings.images_dir + "/" + scene.name + "/" + method + "-" + level)) {
            std::fprintf(stderr, "%s: --save-images: %s\n", kTool, e->c_str());
            std::exit(1);
        }
    }
    if (!graded) {
        std::fprintf(stderr, "%s: grading %s %s: %s\n", kTool, scene.name.c_str(), method.c_str(),
                     graded.error().message.c_str());
        std::exit(1);
    }
    row.error = *graded;
    std::fprintf(stderr, "  %-24s %-20s %7zu vertices  max %d LSB\n", scene.name.c_str(),
                 method.c_str(), row.vertices, row.error.max_lsb);
    return row;
}

// Runs `levels` (coarse to fine) in order until the dense max is <= 1 LSB (that level included).
// Then, when `between` is given, runs the levels it gives strictly between the last level that
// failed by 3 steps or more and the first passing level (those not run yet), coarse to fine,
// until one passes: the error is not monotone in the level (a geodesic dome of frequency 49 can
// pass where 48 fails by 2 steps), and the table takes the fewest vertices that pass, so no
// method's count is overstated by the spacing of its coarse levels.
void sweep(const Scene& scene, const std::string& method, const std::vector<double>& levels,
           const std::function<Mesh(double, double&)>& build, const Settings& settings,
           std::vector<Row>& rows,
           const std::function<std::vector<double>(double, double)>& between = {}) {
    if (!settings.methods.empty() && std::find(settings.methods.begin(), settings.methods.end(),
                                               method) == settings.methods.end())
        return;
    auto run = [&](double level) {
        double build_ms = 0.0;
        const Mesh mesh = build(level, build_ms);
        char text[32];
        std::snprintf(text, sizeof text, "%g", level);
        rows.push_back(grade(scene, method, text, mesh, build_ms, settings));
        return rows.back().error.max_lsb;
    };
    std::size_t clearly_failing = 0;  // index of the last level with max >= 3 steps
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const int max_lsb = run(levels[i]);
        if (max_lsb >= 3) clearly_failing = i;
        if (max_lsb > 1) continue;
        if (i > 0 && between && !settings.quick)
            for (double level : between(levels[clearly_failing], levels[i])) {
                const bool graded =
                    std::any_of(levels.begin() + clearly_failing, levels.begin() + i,
                                [&](double l) { return std::abs(l - level) < 1e-9; });
                if (!graded && run(level) <= 1) break;
            }
        break;
    }
}

// Every integer strictly between two integer levels (geodesic frequencies, rings, cells).
std::vector<double> integers_between(double coarse, double fine) {
    std::vector<double> out;
    for (int l = int(coarse) + 1; l < int(fine); ++l) out.push_back(l);
    return out;
}

// Split thresholds strictly between two, in steps of 0.05 LSB from the coarser (larger) one.
std::vector<double> thresholds_between(double coarse, double fine) {
    std::vector<double> out;
    for (int k = 1;; ++k) {
        const double t = coarse - 0.05 * k;
        if (t <= fine + 1e-9) break;
        out.push_back(t);
    }
    return out;
}

// `relocate`: AdaptiveSettings::relocate (-1: --relocate, else the library's default).
Mesh adaptive_mesh(const Scene& scene, const Mesh& base, const aerial::mesh::Surface& surface,
                   double split_lsb, bool quantized, const Settings& settings, double& build_ms,
                   int relocate = -1) {
    aerial::mesh::AdaptiveSettings a = aerial::tess::adaptive_settings(scene, split_lsb, quantized);
    if (settings.colour_edge >= 0) a.colour_edge = settings.colour_edge == 1;
    if (settings.colour_edge_angle >= 0.0)
        a.colour_edge_min_angle_deg = float(settings.colour_edge_angle);
    if (relocate < 0) relocate = settings.relocate;
    if (relocate >= 0) a.relocate = relocate == 1;
    const auto start = Clock::now();
    auto made = aerial::mesh::AdaptiveMesh::create(base, surface, a);
    aerial::mesh::AdaptiveMesh adaptive = std::move(made).value();
    adaptive.update(scene.setting.frame);
    adaptive.compact();
    build_ms = ms_since(start);
    return adaptive.mesh();
}

void run_scene(const Scene& scene, const Settings& settings, bool decimated,
               std::vector<Row>& rows) {
    // The quick run stops the uniform sweeps at about 10k vertices (the table then says ">N").
    auto capped = [&](std::vector<double> levels, double quick_limit) {
        if (settings.quick)
            levels.erase(std::remove_if(levels.begin(), levels.end(),
                                        [&](double l) { return l > quick_limit; }),
                         levels.end());
        return levels;
    };
    // Split thresholds; with 8-bit vertex colours in the estimate they must stay above half a step.
    const std::vector<double> splits =
        settings.quantized_estimate && scene.dome
            ? std::vector<double>{2.0, 1.5, 1.2, 1.0, 0.9, 0.8, 0.7, 0.6, 0.55}
            : std::vector<double>{2.0, 1.5, 1.0, 0.8, 0.65, 0.5, 0.4, 0.3, 0.2};
    // The runtime mesh refined from `base` at each split threshold (relocate: -1 the settings',
    // 1 on).
    const auto adaptive_sweep = [&](const char* method, const Mesh& base,
                                    const aerial::mesh::Surface& surface, int relocate) {
        sweep(
            scene, method, splits,
            [&](double split, double& ms) {
                return adaptive_mesh(scene, base, surface, split, settings.quantized_estimate,
                                     settings, ms, relocate);
            },
            settings, rows, thresholds_between);
    };
    // Decimation bounds (coarse to fine) and the split threshold the mesh is refined to first.
    const bool q = settings.quantized_estimate && scene.dome;
    const std::vector<double> bounds = q ? std::vector<double>{1.0, 0.9, 0.8, 0.7}
                                         : std::vector<double>{1.0, 0.8, 0.65, 0.5, 0.4, 0.3};
    const double fine_split = q ? 0.55 : 0.2;
    // Offline `decimated` (an adaptive mesh refined to fine_split, decimated back to the bound)
    // and the run-time `adaptive-decimating` (DecimatingMesh: the same made by its first update,
    // then refined at the bound between rebuilds); both cost seconds a mesh, so the quick run
    // grades them on its first scene only (`decimated`).
    const auto decimation_sweeps = [&](const Mesh& base, const aerial::mesh::Surface& surface) {
        if (decimated) {
            double ms = 0.0;
            const Mesh fine = adaptive_mesh(scene, base, surface, fine_split, q, settings, ms);
            sweep(
                scene, "decimated", bounds,
                [&](double bound, double& build_ms) {
                    const auto d = aerial::tess::decimate_options(scene, bound, q);
                    const auto start = Clock::now();
                    Mesh m = aerial::mesh::decimate(fine, scene.setting.frame, d).value();
                    build_ms = ms + ms_since(start);
                    return m;
                },
                settings, rows);
        }
        if (!decimated) return;
        sweep(
            scene, "adaptive-decimating", bounds,
            [&](double bound, double& build_ms) {
                const auto start = Clock::now();
                auto m = aerial::mesh::DecimatingMesh::create(
                             base, surface,
                             aerial::tess::decimating_settings(scene, bound, fine_split, q))
                             .value();
                (void)m.update(scene.setting.frame).value();
                build_ms = ms_since(start);
                return m.mesh();
            },
            settings, rows);
    };
    if (scene.dome) {
        const auto surface = aerial::tess::adaptive_surface(scene);
        const Mesh base = aerial::tess::adaptive_base(scene);
        adaptive_sweep("adaptive", base, surface, -1);
        // The same runtime mesh with AdaptiveSettings::relocate (off by default).
        adaptive_sweep("adaptive-relocate", base, surface, 1);
        sweep(
            scene, "uniform-geodesic", capped({4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128}, 64),
            [&](double f, double& ms) {
                const auto start = Clock::now();
                Mesh m = aerial::mesh::geodesic_dome(int(f), scene.dome_options).value();
                ms = ms_since(start);
                return m;
            },
            settings, rows, integers_between);
        sweep(
            scene, "uniform-latlong", capped({4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128}, 48),
            [&](double r, double& ms) {
                const auto start = Clock::now();
                Mesh m = aerial::mesh::latlong_dome(int(r), 4 * int(r), scene.dome_options).value();
                ms = ms_since(start);
                return m;
            },
            settings, rows);
        decimation_sweeps(base, surface);
    } else {
        const auto surface = aerial::tess::adaptive_surface(scene);
        const Mesh base = aerial::tess::adaptive_base(scene);
        adaptive_sweep("adaptive", base, surface, -1);
        sweep(
            scene, "uniform-grid", capped({8, 16, 32, 64, 128, 256}, 128),
            [&](double cells, double& ms) {
                const auto start = Clock::now();
                Mesh m = aerial::mesh::terrain_grid(scene.field, int(cells), int(cells)).value();
                ms = ms_since(start);
                return m;
            },
            settings, rows);
        const glm::dvec2 eye{scene.setting.frame.view.eye.x, scene.setting.frame.view.eye.y};
        sweep(
            scene, "uniform-distance-lod", capped({8, 16, 32, 64, 128, 256}, 128),
            [&](double cells, double& ms) {
                const auto start = Clock::now();
                Mesh m = aerial::mesh::terrain_distance_lod(scene.field, int(cells), eye,
                                                            settings.lod_exponent)
                             .value();
                ms = ms_since(start);
                return m;
            },
            settings, rows, integers_between);
        decimation_sweeps(base, surface);
    }
}

// --where: the pixels an adaptive dome mesh (split threshold `split_lsb`) draws 2 or more steps
// off, with the face under each (found by casting the pixel's ray) and what the estimate says of
// it: where the estimate under-reports. One line a pixel: elevation and azimuth (deg, the sun at
// azimuth 0), drawn and reference red, the face's estimate and its longest edge (deg), the
// pixel's barycentric weights, the interpolated 8-bit vertex colours and the exact colour there
// (red, in steps).
int where(const Scene& scene, double split_lsb, const Settings& settings) {
    if (!scene.dome) return aerial::tools::fail(kTool, "--where: only dome scenes");
    double ms = 0.0;
    const Mesh mesh =
        adaptive_mesh(scene, aerial::tess::adaptive_base(scene),
                      aerial::tess::adaptive_surface(scene), split_lsb, true, settings, ms);
    std::vector<aerial::validation::MeshGradeOptions::Pixel> pixels;
    aerial::validation::GradeSetting setting = scene.setting;
    setting.options.report = &pixels;
    auto graded = settings.grader->grade(setting, mesh);
    if (!graded) return aerial::tools::fail(kTool, "--where: " + graded.error().message);
    std::printf("%s split %.2f: %zu vertices, max %d LSB, %zu pixels >= 2 steps\n",
                scene.name.c_str(), split_lsb, aerial::mesh::live_vertices(mesh), graded->max_lsb,
                pixels.size());
    aerial::mesh::ColourOptions colour = scene.setting.colour;
    colour.quantized_vertices = true;
    colour.on_dome_sphere = true;
    colour.dome = scene.dome_options;
    const glm::dvec3 eye = scene.setting.frame.view.eye;
    for (const auto& px : pixels) {
        const glm::dvec3 d = glm::normalize(px.point - eye);
        const double elevation = std::asin(d.z) * 180.0 / kPi;
        const double azimuth = std::atan2(d.y, d.x) * 180.0 / kPi;
        // The face the ray hits (Moller-Trumbore over every face).
        for (auto f : mesh.faces()) {
            glm::dvec3 p[3];
            int k = 0;
            for (auto v : mesh.fv_range(f)) {
                const auto& q = mesh.point(v);
                p[k++] = {q[0], q[1], q[2]};
            }
            const glm::dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0], h = glm::cross(d, e2);
            const double a = glm::dot(e1, h);
            if (std::abs(a) < 1e-12) continue;
            const glm::dvec3 s = eye - p[0];
            const double u = glm::dot(s, h) / a;
            const glm::dvec3 q = glm::cross(s, e1);
            const double v = glm::dot(d, q) / a;
            const double t = glm::dot(e2, q) / a;
            if (u < -1e-9 || v < -1e-9 || u + v > 1 + 1e-9 || t <= 0) continue;
            glm::vec3 c[3];
            for (int i = 0; i < 3; ++i)
                c[i] = aerial::mesh::display_colour(scene.setting.frame, colour, p[i]);
            const float estimate = aerial::mesh::colour_error(scene.setting.frame, colour, p[0],
                                                              p[1], p[2], c[0], c[1], c[2]);
            const double w[3] = {1 - u - v, u, v};
            double interpolated = 0.0;
            for (int i = 0; i < 3; ++i) interpolated += w[i] * std::round(255.0 * c[i].x);
            const double exact =
                255.0 * aerial::mesh::display_colour(scene.setting.frame, colour, px.point).x;
            const double longest =
                std::max({glm::length(e1), glm::length(e2), glm::length(p[2] - p[1])}) /
                scene.dome_options.radius_m * 180.0 / kPi;
            std::printf(
                "el %7.3f az %8.3f drawn %3d ref %3d est %.3f edge %.3f w %.2f %.2f %.2f "
                "interp %.3f exact %.3f\n",
                elevation, azimuth, px.drawn[0], px.reference[0], estimate, longest, w[0], w[1],
                w[2], interpolated, exact);
            break;
        }
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "aerial-tess: vertices needed for per-vertex colour within 1 LSB, adaptive "
        "against uniform tessellations, on sky domes and terrain"};
    std::string out;
    bool quick = false, bench = false, no_chart = false;
    int frames = 120;
    app.add_option("--out", out, "Output directory for tess.csv and tess.png");
    app.add_flag("--quick", quick, "A small subset with a coarser grading grid (< 30 s)");
    app.add_flag("--bench-update", bench,
                 "Print the time of an adaptive update of a 100k-triangle terrain under a flying "
                 "camera (median, mean, p99, max)");
    bool bench_dome = false, decimating = false;
    double sun_rate = 0.25;
    app.add_flag("--bench-dome", bench_dome,
                 "The same for the dome-sun10-g0.90 dome under a sinking sun (--sun-rate)");
    app.add_flag("--decimating", decimating,
                 "With --bench-update or --bench-dome: the adaptive-decimating method "
                 "(DecimatingMesh, rebuilds inside the update)");
    app.add_option("--sun-rate", sun_rate,
                   "With --bench-dome: degrees a minute the sun sinks (default 0.25, real time)");
    app.add_option("--frames", frames,
                   "Frames for --bench-update and --bench-dome, at 60 a second (default 120)");
    app.add_flag("--no-chart", no_chart, "Do not write tess.png");
    bool float_estimate = false;
    app.add_flag("--float-estimate", float_estimate,
                 "Adaptive domes estimate with float vertex colours (not rounded to 8 bits as "
                 "drawn) on the flat triangles");
    int face_pixels = 0;
    std::string only;
    double where_split = 0.0;
    app.add_option(
        "--where", where_split,
        "Print the pixels the adaptive dome of this split threshold draws 2 or more "
        "steps off, and the estimate of the face under each (dome scenes only: pick them "
        "with --scene)");
    int colour_edge = -1;
    double colour_edge_angle = -1.0;
    app.add_option("--colour-edge", colour_edge,
                   "Adaptive meshes start each bisection path from the edge with the largest "
                   "midpoint colour error (1) or the longest edge (0); default: the library's");
    app.add_option("--colour-edge-angle", colour_edge_angle,
                   "The smallest angle (degrees, 0 .. 60) the new triangles of a colour-chosen "
                   "edge must keep; default: the library's");
    int relocate = -1;
    app.add_option("--relocate", relocate,
                   "Adaptive meshes move each new vertex within its one-ring to lower its faces' "
                   "largest colour error (1) or leave it at the edge midpoint (0); default: the "
                   "library's");
    app.add_option("--scene", only, "Run only the scenes whose name contains this text");
    app.add_option("--face-pixels", face_pixels,
                   "Pixels a side of each of the six cube faces the GL grading renders "
                   "(default 128, --quick 64), 16 .. 2048");
    std::vector<std::string> mesh_paths;
    std::string own_method;
    bool no_builtin = false;
    std::string export_dir;
    app.add_option("--mesh", mesh_paths,
                   "Grade your own meshes (OBJ, OFF or PLY files, or directories of them: one "
                   "budget level a file, by name) on the scenes of their kind, like the built-in "
                   "methods; in the scenes' coordinates (see --export-meshes)");
    app.add_option("--method", own_method, "The name of the --mesh method in the CSV and tables");
    app.add_flag("--no-builtin", no_builtin, "With --mesh: grade only those meshes");
    app.add_option("--export-meshes", export_dir,
                   "Write every built-in mesh graded as DIR/SCENE/METHOD-LEVEL.obj");
    std::string scenes_file;
    bool list_scenes = false;
    app.add_option("--scenes", scenes_file,
                   "A JSON file of the scenes to grade in place of the built-in ones (see "
                   "--list-scenes): {\"scenes\": [{\"kind\": \"dome\", \"sun_elevation_deg\": 10, "
                   "\"mie_g\": 0.9}, ...]}");
    app.add_flag("--list-scenes", list_scenes,
                 "Print the built-in scenes (with --quick, the quick run's) as such a file");
    std::string images_dir;
    app.add_option("--save-images", images_dir,
                   "Write the drawn and reference images of every mesh graded, and their "
                   "difference, as DIR/SCENE/METHOD-LEVEL-{drawn,reference,diff}.png (the six "
                   "cube faces side by side)");
    std::vector<std::string> methods;
    app.add_option(
           "--methods", methods,
           "Sweep only these built-in methods (adaptive, adaptive-relocate, "
           "adaptive-decimating, uniform-geodesic, uniform-latlong, decimated, uniform-grid, "
           "uniform-distance-lod)")
        ->delimiter(',');
    bool path = false;
    aerial::tess::PathOptions path_options;
    app.add_flag("--path", path,
                 "Grade every frame of each scene's path (the built-in paths, or the scenes of "
                 "--scenes that have a \"path\"): error, update time and popping per frame, "
                 "into DIR/path.csv and DIR/path_summary.txt");
    app.add_option("--path-geodesic", path_options.geodesic_frequency,
                   "With --path: the uniform dome's frequency (default 48)");
    app.add_option("--path-lod-cells", path_options.lod_cells,
                   "With --path: the distance LOD's cells per side (default 32)");
    app.add_option("--rebuild-deg", path_options.rebuild_sun_deg,
                   "With --path, or --bench-dome --decimating: adaptive-decimating rebuilds when "
                   "the sun has turned this far (degrees, default 0.25)");
    if (auto status = aerial::tools::parse_command_line(app, argc, argv, kTool)) return *status;
    std::vector<aerial::validation::TessSceneSpec> specs =
        path ? aerial::validation::builtin_tess_paths()
             : aerial::validation::builtin_tess_scenes(quick);
    if (!path && (app.count("--path-geodesic") || app.count("--path-lod-cells")))
        return aerial::tools::fail(kTool, "--path-geodesic and --path-lod-cells go with --path");
    if (!(path_options.rebuild_sun_deg > 0.0 && path_options.rebuild_sun_deg <= 180.0))
        return aerial::tools::fail(kTool, "--rebuild-deg: expected (0, 180], got " +
                                              std::to_string(path_options.rebuild_sun_deg));
    if (path_options.geodesic_frequency < 1 || path_options.geodesic_frequency > 256)
        return aerial::tools::fail(kTool, "--path-geodesic: expected 1 .. 256, got " +
                                              std::to_string(path_options.geodesic_frequency));
    if (path_options.lod_cells < 1 || path_options.lod_cells > 1024)
        return aerial::tools::fail(kTool, "--path-lod-cells: expected 1 .. 1024, got " +
                                              std::to_string(path_options.lod_cells));
    if (list_scenes) {
        std::fputs(aerial::validation::write_tess_scenes(specs).c_str(), stdout);
        return 0;
    }
    if (!scenes_file.empty()) {
        std::ifstream in(scenes_file);
        if (!in) return aerial::tools::fail(kTool, "--scenes: cannot read " + scenes_file);
        const std::string text((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        auto read = aerial::validation::read_tess_scenes(text);
        if (!read) return aerial::tools::fail(kTool, "--scenes: " + read.error().message);
        specs = std::move(read).value();
    }
    if (frames < 1 || frames > 100000)
        return aerial::tools::fail(kTool,
                                   "--frames: expected 1 .. 100000, got " + std::to_string(frames));
    if (bench || bench_dome) {
        if (app.count("--relocate") && relocate != 0 && relocate != 1)
            return aerial::tools::fail(
                kTool, "--relocate: expected 0 or 1, got " + std::to_string(relocate));
        if (!(sun_rate >= 0.0 && sun_rate <= 600.0))
            return aerial::tools::fail(
                kTool, "--sun-rate: expected 0 .. 600, got " + std::to_string(sun_rate));
        aerial::tess::BenchUpdateOptions b;
        b.dome = bench_dome;
        b.decimating = decimating;
        b.frames = frames;
        b.relocate = app.count("--relocate") ? relocate : -1;
        b.sun_deg_per_min = sun_rate;
        b.rebuild_sun_deg = path_options.rebuild_sun_deg;
        return aerial::tess::bench_update(b);
    }
    if (decimating || app.count("--sun-rate"))
        return aerial::tools::fail(kTool,
                                   "--decimating and --sun-rate go with --bench-update or "
                                   "--bench-dome");
    if (out.empty() && !app.count("--where"))
        return aerial::tools::fail(kTool, "--out: required (or --bench-update, --where)");

    Settings settings;
    settings.quick = quick;
    settings.quantized_estimate = !float_estimate;
    if (quick) settings.face_pixels = 64;
    if (app.count("--face-pixels")) {
        if (face_pixels < 16 || face_pixels > 2048)
            return aerial::tools::fail(
                kTool, "--face-pixels: expected 16 .. 2048, got " + std::to_string(face_pixels));
        settings.face_pixels = face_pixels;
    }
    if (app.count("--colour-edge")) {
        if (colour_edge != 0 && colour_edge != 1)
            return aerial::tools::fail(
                kTool, "--colour-edge: expected 0 or 1, got " + std::to_string(colour_edge));
        settings.colour_edge = colour_edge;
    }
    if (app.count("--relocate")) {
        if (relocate != 0 && relocate != 1)
            return aerial::tools::fail(
                kTool, "--relocate: expected 0 or 1, got " + std::to_string(relocate));
        settings.relocate = relocate;
    }
    if (app.count("--colour-edge-angle")) {
        if (!(colour_edge_angle >= 0.0 && colour_edge_angle <= 60.0))
            return aerial::tools::fail(kTool, "--colour-edge-angle: expected 0 .. 60, got " +
                                                  std::to_string(colour_edge_angle));
        settings.colour_edge_angle = colour_edge_angle;
    }
    if (!mesh_paths.empty() && own_method.empty())
        return aerial::tools::fail(kTool, "--method: required with --mesh (the name of its rows)");
    if (mesh_paths.empty() && (!own_method.empty() || no_builtin))
        return aerial::tools::fail(kTool, "--method and --no-builtin go with --mesh");
    std::vector<std::pair<std::string, aerial::scene::MeshData>> own_meshes;
    for (const std::string& mesh_path : mesh_paths) {
        auto files = aerial::tess::mesh_files(mesh_path);
        if (!files)
            return aerial::tools::fail(kTool, files.error().field + ": " + files.error().message);
        for (const std::string& file : *files) {
            auto data = aerial::scene::load_mesh_file(file);
            if (!data) return aerial::tools::fail(kTool, "--mesh: " + data.error().message);
            own_meshes.emplace_back(aerial::tess::mesh_file_stem(file), std::move(data).value());
        }
    }
    for (const std::string& m : methods) {
        static const char* const known[] = {
            "adaptive",        "adaptive-relocate", "adaptive-decimating", "uniform-geodesic",
            "uniform-latlong", "decimated",         "uniform-grid",        "uniform-distance-lod"};
        if (std::find(std::begin(known), std::end(known), m) == std::end(known))
            return aerial::tools::fail(kTool, "--methods: unknown method '" + m + "'");
    }
    settings.methods = methods;
    settings.export_dir = export_dir;
    settings.images_dir = images_dir;
    auto grader = aerial::validation::MeshGrader::create(settings.face_pixels);
    if (!grader) return aerial::tools::fail(kTool, "GL grading: " + grader.error().message);
    settings.grader = &grader.value();
    if (!only.empty()) {
        std::vector<aerial::validation::TessSceneSpec> kept;
        for (const auto& spec : specs) {
            auto scene = aerial::validation::make_tess_scene(spec);
            if (!scene) return aerial::tools::fail(kTool, "--scenes: " + scene.error().message);
            if (scene->name.find(only) != std::string::npos) kept.push_back(spec);
        }
        if (kept.empty()) return aerial::tools::fail(kTool, "--scene: no scene matches " + only);
        specs = std::move(kept);
    }
    if (path) {
        path_options.own_meshes = own_meshes;
        path_options.own_method = own_method;
        path_options.builtin = !no_builtin;
        return aerial::tess::run_path_mode(specs, *settings.grader, path_options, out);
    }
    std::vector<Scene> scenes;
    for (const auto& spec : specs) {
        auto scene = aerial::validation::make_tess_scene(spec);
        if (!scene) return aerial::tools::fail(kTool, "--scenes: " + scene.error().message);
        scenes.push_back(std::move(scene).value());
    }
    if (app.count("--where")) {
        if (!(where_split > 0.0))
            return aerial::tools::fail(kTool, "--where: expected a split threshold > 0");
        for (const Scene& s : scenes)
            if (int status = where(s, where_split, settings)) return status;
        return 0;
    }
    std::vector<Row> rows;
    const auto start = Clock::now();
    for (std::size_t i = 0; i < scenes.size() && !no_builtin; ++i)
        run_scene(scenes[i], settings, !quick || i == 0, rows);
    for (const Scene& scene : scenes) {
        for (const auto& [stem, data] : own_meshes) {
            if (!aerial::validation::tess_scene_fits(scene, data)) continue;
            auto mesh = aerial::validation::mesh_from_data(data);
            if (!mesh)
                return aerial::tools::fail(kTool, "--mesh " + stem + ": " + mesh.error().message);
            rows.push_back(grade(scene, own_method, stem, *mesh, 0.0, settings));
        }
    }
    if (rows.empty()) {
        return aerial::tools::fail(kTool,
                                   "--mesh: no mesh fits a selected scene (a dome's vertices "
                                   "lie on its sphere; anything else is graded as terrain)");
    }

    const std::string csv_path = out + "/tess.csv";
    std::system(("mkdir -p '" + out + "'").c_str());
    std::ofstream csv(csv_path);
    if (!csv) return aerial::tools::fail(kTool, "--out: cannot write " + csv_path);
    csv << "scene,method,level,vertices,triangles,max_lsb,p99_lsb,rmse_lsb,over1,over2,pixels,"
           "face_pixels,quick,build_ms,grade_ms\n";
    for (const Row& r : rows) {
        char line[512];
        std::snprintf(
            line, sizeof line, "%s,%s,%s,%zu,%zu,%d,%d,%.4f,%.8f,%.8f,%zu,%d,%d,%.2f,%.2f\n",
            r.scene.c_str(), r.method.c_str(), r.level.c_str(), r.vertices, r.triangles,
            r.error.max_lsb, r.error.p99_lsb, r.error.rmse_lsb, r.error.over1, r.error.over2,
            r.error.count, settings.face_pixels, quick ? 1 : 0, r.build_ms, r.grade_ms);
        csv << line;
    }
    csv.close();

    // The tables: per scene, the fewest vertices of each method meeting each criterion.
    std::vector<std::string> scene_names;
    for (const Scene& scene : scenes) scene_names.push_back(scene.name);
    const std::string summary =
        aerial::tess::summary_tables(scene_names, rows, settings.face_pixels, quick);
    std::fputs(summary.c_str(), stdout);
    std::ofstream(out + "/summary.txt") << summary;
    std::printf("total %.1f s; wrote %s and %s/summary.txt\n", ms_since(start) / 1000.0,
                csv_path.c_str(), out.c_str());
    if (!no_chart) {
        const std::string command = std::string("'") + AERIAL_TESS_PYTHON + "' '" +
                                    AERIAL_TESS_PLOT_SCRIPT + "' '" + csv_path + "' '" + out +
                                    "/tess.png'";
        if (std::system(command.c_str()) != 0)
            return aerial::tools::fail(kTool, "the chart failed: " + command);
        std::printf("wrote %s/tess.png\n", out.c_str());
    }
    return 0;
}
