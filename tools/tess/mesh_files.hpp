// Meshes in and out of aerial-tess: a researcher's own meshes graded like the built-in ones
// (--mesh), and the built-in ones written out to compare with (--export-meshes).
//
// How to use this:
//   `write_obj(path, data)` writes a scene::MeshData as OBJ whose floats read back exactly;
//   `mesh_files(path)` lists a file, or a directory's OBJ / OFF / PLY files in name order (budget
//   levels). aerial::validation::MeshGrader grades what scene::load_mesh_file reads of them.
#pragma once

#include <string>
#include <vector>

#include "aerial/error.hpp"
#include "aerial/mesh.hpp"
#include "aerial/scene.hpp"

namespace aerial::tess {

/// Writes positions (as "v x y z", 9 significant digits: every float reads back bit for bit)
/// and triangles ("f a b c", 1-based). Creates the parent directories. Errors name the path.
std::optional<Error> write_obj(const std::string& path, const scene::MeshData& data);

/// `path` itself when it is a file; a directory's .obj, .off and .ply files (not recursive),
/// sorted by name. Errors: a missing path, a directory without mesh files.
Result<std::vector<std::string>> mesh_files(const std::string& path);

/// The file's name without its directory and extension ("dome-32" of "a/dome-32.obj").
std::string mesh_file_stem(const std::string& path);

}  // namespace aerial::tess
