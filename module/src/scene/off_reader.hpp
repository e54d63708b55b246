// The module's own strict reader of ASCII OFF files (internal to aerial::scene).
//
// OpenMesh's OFF reader reserves whatever counts it believes the header declares, and it reads a
// malformed header (a vertical tab, a stray word) as counts of billions: a 12-byte file made it
// ask for 14 GB (found by fuzz_mesh_io). This reader reads one element per line, checks every
// count against what the file holds, and hands vertices and faces to OpenMesh's importer, so the
// mesh it builds is the one OpenMesh's reader builds from a valid file (the same triangulation of
// polygons, the same handling of non-manifold faces).
#pragma once

#include <istream>
#include <optional>
#include <string>

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

namespace aerial::scene::detail {

/// What read_off found in the header: per-vertex normals (N) and texture coordinates (ST).
struct OffContents {
    bool normals = false;
    bool texcoords = false;
};

/// Reads ASCII OFF: the header word [ST][C][N]OFF, then "vertices faces [edges]" (on the same
/// line or the next one), one vertex per line (x y z [nx ny nz] [r g b [a]] [s t]) and one face
/// per line (n i_1 .. i_n [r g b [a]]), indices from 0. '#' starts a comment; blank lines are
/// skipped. Colours are read and dropped. Returns the first problem ("line N: ..."), or nothing
/// when every element went to `importer`. 4OFF, nOFF and binary OFF are refused.
std::optional<std::string> read_off(std::istream& in, OpenMesh::IO::BaseImporter& importer,
                                    OffContents& contents);

}  // namespace aerial::scene::detail
