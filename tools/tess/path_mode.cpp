// aerial-tess --path: see path_mode.hpp.
#include "path_mode.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <map>
#include <memory>

#include "aerial/adaptive_scene.hpp"
#include "support/cli.hpp"
#include "tess/methods.hpp"

namespace aerial::tess {
namespace {

constexpr const char* kTool = "aerial-tess";
using Clock = std::chrono::steady_clock;
using validation::MeshGradeOptions;
using validation::TessScene;

/// The mesh one method shows at a frame, and what making it cost.
struct Followed {
    const mesh::Mesh* mesh = nullptr;
    double ms = 0.0, cpu_ms = 0.0;  ///< wall clock and this process's CPU time
};

/// A method followed along a path: `follow` gives its mesh for each frame's scene in turn.
struct Follower {
    std::string method, level;
    std::function<Result<Followed>(const TessScene&)> follow;
    MeshGradeOptions::Images previous;  ///< the last frame's images (popping)
};

struct PathRow {
    std::string scene, method, level;
    int frame = 0;
    std::size_t vertices = 0, triangles = 0;
    validation::MeshGrade error;
    double update_ms = 0.0, update_cpu_ms = 0.0;
    int popping_lsb = 0;
    double pop_over1 = 0.0;
};

/// How much more the drawn pixels changed between two frames than their references did.
void popping(const MeshGradeOptions::Images& before, const MeshGradeOptions::Images& now,
             PathRow& row) {
    std::size_t both = 0, over1 = 0;
    for (std::size_t i = 0; i < now.covered.size(); ++i) {
        if (!now.covered[i] || !before.covered[i]) continue;
        ++both;
        int excess = 0;
        for (std::size_t c = 3 * i; c < 3 * i + 3; ++c) {
            const int drawn = std::abs(int(now.drawn[c]) - int(before.drawn[c]));
            const int reference = std::abs(int(now.reference[c]) - int(before.reference[c]));
            excess = std::max(excess, drawn - reference);
        }
        row.popping_lsb = std::max(row.popping_lsb, excess);
        over1 += excess > 1;
    }
    row.pop_over1 = both ? double(over1) / double(both) : 0.0;
}

/// Times `make` (wall clock and process CPU time).
template <class Make>
Followed timed(const mesh::Mesh* mesh, Make&& make) {
    const auto start = Clock::now();
    const std::clock_t cpu_start = std::clock();
    make();
    Followed f;
    f.mesh = mesh;
    f.cpu_ms = 1000.0 * double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    f.ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return f;
}

/// A run-time adaptive mesh: updated for every frame (the first update refines from the base).
Follower adaptive_follower(const TessScene& first, const char* method, bool relocate) {
    mesh::AdaptiveSettings a = adaptive_settings(first, 1.0, true);
    a.relocate = relocate;
    auto state = std::make_shared<std::optional<mesh::AdaptiveMesh>>();
    auto made = mesh::AdaptiveMesh::create(adaptive_base(first), adaptive_surface(first), a);
    if (made) state->emplace(std::move(made).value());
    const std::string error = made ? "" : made.error().message;
    Follower f;
    f.method = method;
    f.level = "1";
    f.follow = [state, error](const TessScene& scene) -> Result<Followed> {
        if (!*state) return Error{"adaptive", error};
        mesh::AdaptiveMesh& m = **state;
        return timed(&m.mesh(), [&] { m.update(scene.setting.frame); });
    };
    return f;
}

/// The run-time adaptive-decimating dome: rebuilt inside the update (not on a thread of its own,
/// so that the path's figures do not depend on timing); the update time of a rebuild's frame
/// includes it.
Follower decimating_follower(const TessScene& first, double rebuild_sun_deg) {
    mesh::DecimatingSettings d = decimating_settings(first, 1.0, 0.55, true);
    d.background = false;
    d.rebuild_sun_rad = rebuild_sun_deg * 3.14159265358979323846 / 180.0;
    auto state = std::make_shared<std::optional<mesh::DecimatingMesh>>();
    auto made = mesh::DecimatingMesh::create(adaptive_base(first), adaptive_surface(first), d);
    if (made) state->emplace(std::move(made).value());
    const std::string error = made ? "" : made.error().message;
    Follower f;
    f.method = "adaptive-decimating";
    f.level = "1";
    f.follow = [state, error](const TessScene& scene) -> Result<Followed> {
        if (!*state) return Error{"adaptive-decimating", error};
        mesh::DecimatingMesh& m = **state;
        std::optional<Error> failed;
        Followed followed = timed(&m.mesh(), [&] {
            auto stats = m.update(scene.setting.frame);
            if (!stats) failed = stats.error();
        });
        if (failed) return *failed;
        followed.mesh = &m.mesh();
        return followed;
    };
    return f;
}

/// A mesh made once (at frame 0) and shown as it is at every frame.
Follower static_follower(const std::string& method, const std::string& level, mesh::Mesh mesh) {
    auto kept = std::make_shared<mesh::Mesh>(std::move(mesh));
    Follower f;
    f.method = method;
    f.level = level;
    f.follow = [kept](const TessScene&) -> Result<Followed> { return Followed{kept.get()}; };
    return f;
}

/// The distance LOD rebuilt around the eye at every frame.
Follower lod_follower(int cells) {
    auto kept = std::make_shared<mesh::Mesh>();
    Follower f;
    f.method = "uniform-distance-lod";
    f.level = std::to_string(cells);
    f.follow = [kept, cells](const TessScene& scene) -> Result<Followed> {
        const glm::dvec2 eye{scene.setting.frame.view.eye.x, scene.setting.frame.view.eye.y};
        std::optional<Error> failed;
        Followed followed = timed(kept.get(), [&] {
            auto m = mesh::terrain_distance_lod(scene.field, cells, eye, 2.0);
            if (m)
                *kept = std::move(m).value();
            else
                failed = m.error();
        });
        if (failed) return *failed;
        return followed;
    };
    return f;
}

Result<std::vector<Follower>> followers(const TessScene& first, const PathOptions& options) {
    std::vector<Follower> out;
    if (options.builtin && first.dome) {
        out.push_back(adaptive_follower(first, "adaptive", false));
        out.push_back(adaptive_follower(first, "adaptive-relocate", true));
        out.push_back(decimating_follower(first, options.rebuild_sun_deg));
        auto geodesic = mesh::geodesic_dome(options.geodesic_frequency, first.dome_options);
        if (!geodesic) return geodesic.error();
        out.push_back(static_follower("uniform-geodesic",
                                      std::to_string(options.geodesic_frequency),
                                      std::move(geodesic).value()));
        // Offline: refined to 0.55 steps at frame 0, decimated back to 0.8.
        auto made = mesh::AdaptiveMesh::create(adaptive_base(first), adaptive_surface(first),
                                               adaptive_settings(first, 0.55, true));
        if (!made) return made.error();
        mesh::AdaptiveMesh fine = std::move(made).value();
        fine.update(first.setting.frame);
        auto decimated =
            mesh::decimate(fine.mesh(), first.setting.frame, decimate_options(first, 0.8, true));
        if (!decimated) return decimated.error();
        out.push_back(static_follower("decimated", "0.8", std::move(decimated).value()));
    } else if (options.builtin) {
        out.push_back(adaptive_follower(first, "adaptive", false));
        out.push_back(lod_follower(options.lod_cells));
    }
    for (const auto& [stem, data] : options.own_meshes) {
        if (!validation::tess_scene_fits(first, data)) continue;
        auto m = validation::mesh_from_data(data);
        if (!m) return m.error();
        out.push_back(static_follower(options.own_method, stem, std::move(m).value()));
    }
    return out;
}

/// One scene's path: every frame, every method. Appends its rows.
std::optional<Error> run_path(const validation::TessSceneSpec& spec, validation::MeshGrader& grader,
                              const PathOptions& options, std::vector<PathRow>& rows) {
    auto first = validation::make_tess_scene(spec, 0);
    if (!first) return first.error();
    auto made = followers(*first, options);
    if (!made) return made.error();
    std::vector<Follower> methods = std::move(made).value();
    for (int frame = 0; frame < spec.path.frames; ++frame) {
        auto scene = validation::make_tess_scene(spec, frame);
        if (!scene) return scene.error();
        for (Follower& f : methods) {
            auto followed = f.follow(*scene);
            if (!followed) return followed.error();
            PathRow row;
            row.scene = scene->name;
            row.method = f.method;
            row.level = f.level;
            row.frame = frame;
            row.vertices = mesh::live_vertices(*followed->mesh);
            row.triangles = mesh::live_faces(*followed->mesh);
            row.update_ms = followed->ms;
            row.update_cpu_ms = followed->cpu_ms;
            validation::GradeSetting setting = scene->setting;
            MeshGradeOptions::Images images;
            setting.options.images = &images;
            auto graded = grader.grade(setting, *followed->mesh);
            if (!graded) return graded.error();
            row.error = *graded;
            if (frame > 0) popping(f.previous, images, row);
            f.previous = std::move(images);
            rows.push_back(row);
        }
        std::fprintf(stderr, "  %s frame %d/%d\n", first->name.c_str(), frame + 1,
                     spec.path.frames);
    }
    return std::nullopt;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// Per scene and method: frames, mean vertices, worst max, frames within 1 step, frames meeting
/// the robust criterion, largest popping, median and largest update time.
std::string path_summary(const std::vector<PathRow>& rows, int face_pixels) {
    char line[512];
    std::snprintf(
        line, sizeof line,
        "Paths: every frame graded, GL images against the per-pixel reference, six cube "
        "faces of %d x %d pixels a mesh\n%-24s %-22s %6s %9s %7s %9s %9s %7s %9s %9s %9s\n",
        face_pixels, face_pixels, "scene", "method", "frames", "vertices", "max", "max<=1",
        "over1<=e-4", "pop", "pop>1", "upd_med", "upd_max");
    std::string text = line;
    std::vector<std::pair<std::string, std::string>> keys;
    for (const PathRow& r : rows)
        if (std::find(keys.begin(), keys.end(), std::make_pair(r.scene, r.method)) == keys.end())
            keys.emplace_back(r.scene, r.method);
    for (const auto& [scene, method] : keys) {
        int frames = 0, max_lsb = 0, within = 0, robust = 0, pop = 0;
        double vertices = 0.0, pop_over1 = 0.0;
        std::vector<double> cpu;
        for (const PathRow& r : rows) {
            if (r.scene != scene || r.method != method) continue;
            ++frames;
            vertices += double(r.vertices);
            max_lsb = std::max(max_lsb, r.error.max_lsb);
            within += r.error.max_lsb <= 1;
            robust += r.error.over1 <= 1e-4;
            pop = std::max(pop, r.popping_lsb);
            pop_over1 = std::max(pop_over1, r.pop_over1);
            if (r.frame > 0) cpu.push_back(r.update_cpu_ms);
        }
        std::snprintf(
            line, sizeof line, "%-24s %-22s %6d %9.0f %7d %9d %9d %7d %9.2g %9.3f %9.3f\n",
            scene.c_str(), method.c_str(), frames, vertices / frames, max_lsb, within, robust, pop,
            pop_over1, median(cpu), cpu.empty() ? 0.0 : *std::max_element(cpu.begin(), cpu.end()));
        text += line;
    }
    text +=
        "(vertices: mean over the frames; max: the worst frame's max_lsb; max<=1 and "
        "over1<=e-4: frames meeting each criterion; pop: the largest popping_lsb; pop>1: the "
        "largest fraction of pixels popping by more than 1 step; upd_med, upd_max: CPU ms to "
        "follow a frame after the first, median and largest)\n";
    return text;
}

}  // namespace

int run_path_mode(const std::vector<validation::TessSceneSpec>& specs,
                  validation::MeshGrader& grader, const PathOptions& options,
                  const std::string& out_dir) {
    const auto start = Clock::now();
    std::vector<PathRow> rows;
    for (const auto& spec : specs) {
        if (spec.path.frames < 2) continue;
        if (auto e = run_path(spec, grader, options, rows))
            return tools::fail(kTool, "--path: " + e->message);
    }
    if (rows.empty())
        return tools::fail(kTool,
                           "--path: no scene with a path (\"path\": {\"frames\": N, ...}) "
                           "and a method to grade on it");
    std::system(("mkdir -p '" + out_dir + "'").c_str());
    const std::string csv_path = out_dir + "/path.csv";
    std::ofstream csv(csv_path);
    if (!csv) return tools::fail(kTool, "--out: cannot write " + csv_path);
    csv << "scene,frame,method,level,vertices,triangles,max_lsb,p99_lsb,rmse_lsb,over1,over2,"
           "pixels,face_pixels,update_ms,update_cpu_ms,popping_lsb,pop_over1\n";
    for (const PathRow& r : rows) {
        char line[512];
        std::snprintf(line, sizeof line,
                      "%s,%d,%s,%s,%zu,%zu,%d,%d,%.4f,%.8f,%.8f,%zu,%d,%.3f,%.3f,%d,%.8f\n",
                      r.scene.c_str(), r.frame, r.method.c_str(), r.level.c_str(), r.vertices,
                      r.triangles, r.error.max_lsb, r.error.p99_lsb, r.error.rmse_lsb,
                      r.error.over1, r.error.over2, r.error.count, grader.face_pixels(),
                      r.update_ms, r.update_cpu_ms, r.popping_lsb, r.pop_over1);
        csv << line;
    }
    const std::string summary = path_summary(rows, grader.face_pixels());
    std::fputs(summary.c_str(), stdout);
    std::ofstream(out_dir + "/path_summary.txt") << summary;
    std::printf("total %.1f s; wrote %s and %s/path_summary.txt\n",
                std::chrono::duration<double>(Clock::now() - start).count(), csv_path.c_str(),
                out_dir.c_str());
    return 0;
}

}  // namespace aerial::tess
