// Grading a mesh of your own with the installed package (the validation component): the scenes
// of a JSON file (aerial/validation/tess_scenes.hpp), each mesh file (OBJ, OFF or PLY) graded on
// the scenes of its kind by the library's renderer against the per-pixel reference
// (aerial/validation/mesh_grader.hpp). Prints one line a graded mesh, as aerial-tess's tess.csv
// writes its columns scene, vertices .. pixels:
//   SCENE,FILE,VERTICES,TRIANGLES,MAX,P99,RMSE,OVER1,OVER2,PIXELS
// Usage: consumer_grade SCENES.json FACE_PIXELS MESH...
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <aerial/scene.hpp>
#include <aerial/validation/mesh_grader.hpp>
#include <aerial/validation/tess_scenes.hpp>

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: consumer_grade SCENES.json FACE_PIXELS MESH...\n");
        return 2;
    }
    std::ifstream in(argv[1]);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto specs = aerial::validation::read_tess_scenes(text);
    if (!specs) {
        std::fprintf(stderr, "%s\n", specs.error().message.c_str());
        return 1;
    }
    auto grader = aerial::validation::MeshGrader::create(std::atoi(argv[2]));
    if (!grader) {
        std::fprintf(stderr, "%s\n", grader.error().message.c_str());
        return 1;
    }
    aerial::validation::MeshGrader& mesh_grader = grader.value();
    int graded = 0;
    for (const auto& spec : *specs) {
        const auto scene = aerial::validation::make_tess_scene(spec);
        if (!scene) {
            std::fprintf(stderr, "%s\n", scene.error().message.c_str());
            return 1;
        }
        for (int i = 3; i < argc; ++i) {
            const auto data = aerial::scene::load_mesh_file(argv[i]);
            if (!data) {
                std::fprintf(stderr, "%s\n", data.error().message.c_str());
                return 1;
            }
            if (!aerial::validation::tess_scene_fits(*scene, *data)) continue;
            const auto g = mesh_grader.grade(scene->setting, *data);
            if (!g) {
                std::fprintf(stderr, "%s\n", g.error().message.c_str());
                return 1;
            }
            std::printf("%s,%s,%zu,%zu,%d,%d,%.4f,%.8f,%.8f,%zu\n", scene->name.c_str(), argv[i],
                        data->vertex_count(), data->indices.size() / 3, g->max_lsb, g->p99_lsb,
                        g->rmse_lsb, g->over1, g->over2, g->count);
            ++graded;
        }
    }
    return graded > 0 ? 0 : 1;
}
