// libFuzzer target: the scene files (aerial::scene::scene_file_from_json). An accepted
// scene must give a valid view, finite geometry with indices in range, a texture of the size it
// asked for, finite fog parameters and finite shading of its vertices (what aerial-render does,
// without GL).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "aerial/batch.hpp"
#include "aerial/scattering.hpp"
#include "aerial/scene_file.hpp"
#include "aerial/validation/scene_render.hpp"
#include "batch_outputs.hpp"
#include "fuzz_check.hpp"

namespace {

/// Without the higher orders' table: a fuzzed atmosphere can take minutes to tabulate
/// (aerial::FrameOptions); the term's math is fuzzed through the stability sweeps.
const aerial::FrameOptions kNoTables{false};

using aerial::fuzz::check;

// Geometry and textures above these sizes are valid but slow to build on every input.
constexpr double kMaxVertices = 20000;
constexpr int kMaxTextureSize = 256;

double vertex_estimate(const aerial::scene::SceneFile& scene) {
    double count = 0;
    if (scene.terrain) count += std::pow(scene.terrain->resolution + 1.0, 2.0);
    for (const auto& box : scene.boxes) count += 6.0 * std::pow(box.subdivisions + 1.0, 2.0);
    return count;
}

void check_geometry(const aerial::scene::SceneFile& scene, const aerial::Frame<float>& frame) {
    const auto mesh = aerial::scene::scene_geometry(scene);
    check(mesh.positions.size() % 3 == 0 && mesh.texcoords.size() / 2 == mesh.vertex_count(),
          "geometry arrays of different lengths");
    check(mesh.indices.size() % 3 == 0, "geometry indices are not triangles");
    for (float v : mesh.positions) check(std::isfinite(v), "non-finite geometry position");
    for (float v : mesh.texcoords) check(std::isfinite(v), "non-finite texture coordinate");
    for (std::uint32_t i : mesh.indices) check(i < mesh.vertex_count(), "index out of range");
    if (mesh.vertex_count() == 0) return;

    const std::size_t n = mesh.vertex_count();
    std::vector<float> fex(3 * n), lin(3 * n), esun(3 * n);
    std::vector<std::uint8_t> fex8(4 * n), lin8(4 * n);
    aerial::BatchOutputs out = aerial_test::floats_and_codes(fex, lin, esun, fex8, lin8);
    aerial::BatchSettings settings;
    settings.display = scene.display;
    settings.threads = 1;
    const auto stats =
        aerial::shade_into(frame, aerial::Positions::aos(mesh.positions.data(), n), out, settings);
    check(stats.ok(), "shade_into rejected the geometry of an accepted scene");
    for (std::size_t i = 0; i < 3 * n; ++i) {
        check(std::isfinite(fex[i]) && std::isfinite(lin[i]) && std::isfinite(esun[i]),
              "non-finite shading of an accepted scene");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto scene = aerial::scene::scene_file_from_json(text);
    if (!scene) {
        check(!scene.error().message.empty(), "an error without a message");
        return 0;
    }
    check(!aerial::validate(scene->view()), "an accepted scene whose view is invalid");
    check(!aerial::validate(scene->atmosphere), "an accepted scene whose atmosphere is invalid");
    if (scene->texture.size <= kMaxTextureSize) {
        const auto texture = aerial::scene::scene_texture(scene->texture);
        check(texture.width == scene->texture.size && texture.height == scene->texture.size &&
                  !aerial::scene::validate(texture),
              "a texture of the wrong size");
        const auto levels = aerial::scene::mipmap_levels(texture);
        check(levels.back().size() == 3, "a mipmap chain that does not end at 1x1");
    }
    auto frame =
        aerial::prepare_frame<float>(scene->atmosphere, scene->view(), scene->model, kNoTables);
    if (!frame) return 0;
    const auto fog = aerial::validation::fog_parameters(*frame, scene->display);
    check(std::isfinite(fog.density) && std::isfinite(fog.colour[0]) &&
              std::isfinite(fog.colour[1]) && std::isfinite(fog.colour[2]),
          "non-finite fog parameters");
    if (vertex_estimate(*scene) <= kMaxVertices) check_geometry(*scene, *frame);
    return 0;
}
