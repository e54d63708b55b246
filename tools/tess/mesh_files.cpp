// aerial-tess's mesh files: see mesh_files.hpp.
#include "mesh_files.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace aerial::tess {
namespace fs = std::filesystem;

std::optional<Error> write_obj(const std::string& path, const scene::MeshData& data) {
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    std::ofstream out(path);
    if (!out) return Error{"--export-meshes", path + ": cannot write"};
    char line[128];
    for (std::size_t i = 0; i < data.vertex_count(); ++i) {
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", double(data.positions[3 * i]),
                      double(data.positions[3 * i + 1]), double(data.positions[3 * i + 2]));
        out << line;
    }
    for (std::size_t t = 0; t + 2 < data.indices.size(); t += 3) {
        out << "f " << data.indices[t] + 1 << ' ' << data.indices[t + 1] + 1 << ' '
            << data.indices[t + 2] + 1 << '\n';
    }
    if (!out) return Error{"--export-meshes", path + ": cannot write"};
    return std::nullopt;
}

Result<std::vector<std::string>> mesh_files(const std::string& path) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) return std::vector<std::string>{path};
    if (!fs::is_directory(path, ec)) return Error{"--mesh", path + ": no such file or directory"};
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(path, ec)) {
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        if (entry.is_regular_file() && (ext == ".obj" || ext == ".off" || ext == ".ply"))
            files.push_back(entry.path().string());
    }
    if (files.empty())
        return Error{"--mesh", path + ": a directory without .obj, .off or .ply files"};
    std::sort(files.begin(), files.end());
    return files;
}

std::string mesh_file_stem(const std::string& path) { return fs::path(path).stem().string(); }

}  // namespace aerial::tess
