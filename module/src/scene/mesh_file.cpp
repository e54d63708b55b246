// Mesh files through OpenMesh (OBJ, PLY) and the module's OFF reader: triangulated, with normals
// and texcoords.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "../common/error_text.hpp"
#include "aerial/scene.hpp"
#include "off_reader.hpp"

namespace aerial::scene {
namespace {

struct FileTraits : OpenMesh::DefaultTraits {
    VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::TexCoord2D);
    FaceAttributes(OpenMesh::Attributes::Normal);
};
using FileMesh = OpenMesh::TriMesh_ArrayKernelT<FileTraits>;

std::string lower_extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

/// OpenMesh's OBJ reader writes texture coordinates through face indices it has not checked (an
/// index past the vertices read corrupts the heap; found by fuzz_mesh_io): every index of every
/// face must name a vertex, texture coordinate or normal defined before it.
std::optional<std::string> bad_obj_index(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    std::string line;
    long long counts[3] = {0, 0, 0};  // v, vt, vn so far
    for (long long number = 1; std::getline(file, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (!line.empty() && line.back() == '\\') {
            return "line " + std::to_string(number) + ": line continuations are not supported";
        }
        // Control characters make OpenMesh's count of vertex lines differ from any we could
        // make (a heap overflow again, found by fuzz_mesh_io): refused.
        for (const char c : line) {
            if ((unsigned char)c < 0x20 && c != '\t') {
                return "line " + std::to_string(number) + ": a control character (byte " +
                       std::to_string(int((unsigned char)c)) + ")";
            }
        }
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        // Vertex, texture coordinate and normal lines must be numbers only, as many as the
        // format allows: then OpenMesh's count of them is ours.
        const auto numbers = [&](int least, int most,
                                 const char* form) -> std::optional<std::string> {
            int n = 0;
            for (std::string word; words >> word; ++n) {
                char* end = nullptr;
                const float value = std::strtof(word.c_str(), &end);
                if (end == word.c_str() || *end != '\0' || !std::isfinite(value) || n == most) {
                    n = -1;
                    break;
                }
            }
            if (n >= least) return std::nullopt;
            return "line " + std::to_string(number) + ": expected '" + form + "'";
        };
        std::optional<std::string> wrong;
        if (keyword == "v" && !(wrong = numbers(3, 7, "v X Y Z [W] or v X Y Z R G B"))) ++counts[0];
        if (keyword == "vt" && !(wrong = numbers(2, 3, "vt U V [W]"))) ++counts[1];
        if (keyword == "vn" && !(wrong = numbers(3, 3, "vn X Y Z"))) ++counts[2];
        if (wrong) return wrong;
        if (keyword != "f") continue;
        for (std::string corner; words >> corner;) {
            std::istringstream parts(corner);
            std::string part;
            for (int k = 0; k < 3 && std::getline(parts, part, '/'); ++k) {
                if (part.empty() && k > 0) continue;  // "1//3": no texture coordinate
                char* end = nullptr;
                const long long index = std::strtoll(part.c_str(), &end, 10);
                if (end == part.c_str() || *end != '\0' || index == 0 ||
                    (index > 0 ? index > counts[k] : index < -counts[k])) {
                    return "line " + std::to_string(number) + ": face index '" +
                           corner.substr(0, 40) + "' names nothing defined before it";
                }
            }
        }
    }
    return std::nullopt;
}

/// One element of a PLY header: its count and, per property, whether it is a list.
struct PlyElement {
    long long count = 0;
    std::vector<bool> lists;
};

/// An ASCII PLY value that is not one number: OpenMesh's reader would stop inside it and take
/// the rest ("1+5555...") as the next value, a list's count among them (3 GB asked for, found by
/// fuzz_mesh_io).
std::optional<std::string> not_a_number(const std::string& token) {
    char* end = nullptr;
    std::strtold(token.c_str(), &end);
    if (end != token.c_str() && *end == '\0') return std::nullopt;
    return "the value '" + token.substr(0, 40) + "' is not a number";
}

/// ASCII PLY: OpenMesh's reader takes a list's count from the file and reserves that many
/// entries whatever follows (a face of 10^33 indices asked for gigabytes, found by
/// fuzz_mesh_io). Every entry takes at least one byte, so a count above the file's size is a lie.
std::optional<std::string> bad_ascii_ply_list(std::istream& body,
                                              const std::vector<PlyElement>& elements,
                                              long long size) {
    std::string token;
    for (const PlyElement& element : elements) {
        for (long long i = 0; i < element.count; ++i) {
            for (const bool list : element.lists) {
                if (!(body >> token)) return std::nullopt;  // short: OpenMesh says so
                if (!list) {
                    if (auto wrong = not_a_number(token)) return wrong;
                    continue;
                }
                char* end = nullptr;
                const long double n = std::strtold(token.c_str(), &end);
                if (end == token.c_str() || *end != '\0' || !(n >= 0) || n > (long double)size ||
                    n != std::floor(n)) {
                    return "a list of '" + token.substr(0, 40) + "' entries in a file of " +
                           std::to_string(size) + " bytes";
                }
                for (long long k = 0; k < (long long)n; ++k) {
                    if (!(body >> token)) return std::nullopt;
                    if (auto wrong = not_a_number(token)) return wrong;
                }
            }
        }
    }
    return std::nullopt;
}

/// What would make OpenMesh misread the file, or nothing. PLY headers declare element counts, and
/// OpenMesh reserves memory for them before it reads an element: a 100-byte file declaring 10^8
/// vertices makes it allocate gigabytes. Every element takes at least one byte of the file, so a
/// count above the file's size is a lie. OBJ: see bad_obj_index. OFF never reaches OpenMesh's
/// reader (see off_reader.hpp).
std::optional<std::string> check_before_openmesh(const std::string& path, const std::string& ext) {
    if (ext == "obj") return bad_obj_index(path);
    if (ext != "ply") return std::nullopt;
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    const auto size = static_cast<long long>(file.tellg());
    file.seekg(0);
    std::string head(std::size_t(std::min<long long>(std::max<long long>(size, 0), 65536)), '\0');
    file.read(head.data(), std::streamsize(head.size()));
    head.resize(std::size_t(std::max<std::streamsize>(file.gcount(), 0)));
    std::istringstream lines(head);
    std::string line;
    auto too_many = [&](long double count) { return count < 0 || count > (long double)size; };
    {
        // OpenMesh's PLY reader also loops forever on some malformed headers (found by
        // fuzz_mesh_io): only a header of known lines that ends in end_header goes to it.
        int number = 0;
        bool element_seen = false, ascii = false, format_seen = false;
        static const char* const kEnd = "expected 'end_header' alone on its line";
        std::vector<PlyElement> elements;
        while (std::getline(lines, line)) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            std::istringstream words(line);
            std::string keyword, name;
            words >> keyword;
            if (number++ == 0) {
                if (keyword != "ply") return std::string("it does not start with the line 'ply'");
                continue;
            }
            if (keyword == "end_header") {
                // OpenMesh's reader loops forever on a header that ends before its format line or
                // on an end_header line with more words (found by fuzz_mesh_io).
                std::string extra;
                if (words >> extra) return "header line " + std::to_string(number) + ": " + kEnd;
                if (!format_seen) return std::string("its header has no 'format' line");
                if (!ascii) return std::nullopt;
                std::ifstream body(path, std::ios::binary);
                body.seekg(lines.tellg());
                return bad_ascii_ply_list(body, elements, size);
            }
            if (keyword != "format" && keyword != "comment" && keyword != "obj_info" &&
                keyword != "element" && keyword != "property") {
                return "header line " + std::to_string(number) + " starts with '" +
                       keyword.substr(0, 40) + "', not a PLY keyword";
            }
            // OpenMesh's reader trusts these lines: each must have exactly its fields.
            const auto bad = [&](const char* what) {
                return "header line " + std::to_string(number) + ": " + what;
            };
            const auto type = [](const std::string& t) {
                static const char* const known[] = {
                    "char", "uchar", "short", "ushort", "int",   "uint",   "float",   "double",
                    "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
                return std::find(std::begin(known), std::end(known), t) != std::end(known);
            };
            std::string extra;
            if (keyword == "format") {
                std::string encoding, version;
                if (!(words >> encoding >> version) || words >> extra || version != "1.0" ||
                    (encoding != "ascii" && encoding != "binary_little_endian" &&
                     encoding != "binary_big_endian")) {
                    return bad(
                        "expected 'format ascii|binary_little_endian|binary_big_endian "
                        "1.0'");
                }
                ascii = encoding == "ascii";
                format_seen = true;
            }
            if (keyword == "property") {
                // OpenMesh's reader writes a property into its current element: before any
                // element line there is none (a write through a wild pointer, found by
                // fuzz_mesh_io).
                if (!element_seen) return bad("a property before any 'element' line");
                std::string first, second, third;
                words >> first;
                const bool list = first == "list";
                if (list ? !(words >> second >> third) || !type(second) || !type(third)
                         : !type(first)) {
                    return bad("a property of an unknown type");
                }
                std::string property_name;
                if (!(words >> property_name) || words >> extra) {
                    return bad("expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
                }
                elements.back().lists.push_back(list);
            }
            long double count = 0;
            element_seen = element_seen || keyword == "element";
            // OpenMesh reads the count into an unsigned int: anything but decimal digits (".0",
            // "+3", "-1") fails that read, and its header loop then appends elements until memory
            // runs out (found by fuzz_mesh_io).
            std::string digits;
            const auto decimal = [](const std::string& text) {
                return !text.empty() && std::all_of(text.begin(), text.end(),
                                                    [](char c) { return c >= '0' && c <= '9'; });
            };
            if (keyword == "element" &&
                (!(words >> name >> digits) || words >> extra || !decimal(digits))) {
                return bad("expected 'element NAME COUNT' with COUNT a decimal integer");
            }
            // (stold throws past its range: a count of 30 digits is a lie in any file anyway.)
            if (keyword == "element") count = digits.size() > 30 ? 1e30L : std::stold(digits);
            if (keyword == "element" && too_many(count)) {
                // (long long) of a count past its range is undefined (found by fuzz_mesh_io).
                const std::string shown =
                    count < 1e18L ? std::to_string((long long)count) : std::string("over 10^18");
                return "its header declares " + shown + " " + name.substr(0, 40) +
                       " elements in a file of " + std::to_string(size) + " bytes";
            }
            if (keyword == "element") elements.push_back({(long long)count, {}});
        }
        return std::string("its header has no end_header line in its first 64 KiB");
    }
    return std::nullopt;
}

}  // namespace

Result<MeshData> load_mesh_file(const std::string& path) {
    constexpr const char* kFunction = "scene::load_mesh_file";
    const auto bad = [&](const std::string& text) {
        return aerial::detail::error(kFunction, path, text);
    };
    const std::string ext = lower_extension(path);
    if (ext != "obj" && ext != "off" && ext != "ply") {
        return aerial::detail::invalid(kFunction, path, "a .obj, .off or .ply file",
                                       "unknown mesh format '." + ext + "'");
    }
    if (!std::ifstream(path).good()) return bad("cannot open the file (missing or unreadable)");
    FileMesh mesh;
    mesh.request_vertex_normals();
    mesh.request_vertex_texcoords2D();
    mesh.request_face_normals();
    OpenMesh::IO::Options options;
    options += OpenMesh::IO::Options::VertexNormal;
    options += OpenMesh::IO::Options::VertexTexCoord;
    if (auto lie = check_before_openmesh(path, ext)) {
        return bad("not a valid ." + ext + " file: " + *lie);
    }
    // OpenMesh reports problems on its own error stream; the Result says what failed.
    struct QuietOpenMesh {
        QuietOpenMesh() { omerr().disable(); }
        ~QuietOpenMesh() { omerr().enable(); }
    } quiet;
    bool read = false;
    try {
        if (ext == "off") {
            // The module's reader builds the mesh through OpenMesh's importer (off_reader.hpp).
            std::ifstream file(path, std::ios::binary);
            OpenMesh::IO::ImporterT<FileMesh> importer(mesh);
            detail::OffContents contents;
            if (auto problem = detail::read_off(file, importer, contents)) {
                return bad("not a valid .off file: " + *problem);
            }
            options = OpenMesh::IO::Options();
            if (contents.normals) options += OpenMesh::IO::Options::VertexNormal;
            if (contents.texcoords) options += OpenMesh::IO::Options::VertexTexCoord;
            read = true;
        } else {
            read = OpenMesh::IO::read_mesh(mesh, path, options);
        }
    } catch (const std::bad_alloc&) {
        return bad("out of memory while reading it");
    } catch (const std::exception& e) {
        return bad(std::string("OpenMesh failed reading it: ") + e.what());
    }
    if (!read) return bad("OpenMesh could not read it as ." + ext);
    if (mesh.n_faces() == 0) return bad("the file has no faces");
    if (!options.check(OpenMesh::IO::Options::VertexNormal)) {
        mesh.update_face_normals();
        mesh.update_vertex_normals();
    }
    const bool has_texcoords = options.check(OpenMesh::IO::Options::VertexTexCoord);

    MeshData out;
    out.positions.reserve(mesh.n_vertices() * 3);
    out.normals.reserve(mesh.n_vertices() * 3);
    for (const auto vh : mesh.vertices()) {
        const auto p = mesh.point(vh);
        auto n = mesh.normal(vh);
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (length > 0.0f && std::isfinite(length)) {
            n /= length;
        } else {
            n = FileMesh::Normal(0.0f, 0.0f, 1.0f);  // isolated vertex: any unit vector
        }
        out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
        out.normals.insert(out.normals.end(), {n[0], n[1], n[2]});
        if (has_texcoords) {
            const auto t = mesh.texcoord2D(vh);
            out.texcoords.insert(out.texcoords.end(), {t[0], t[1]});
        }
    }
    out.indices.reserve(mesh.n_faces() * 3);
    for (const auto fh : mesh.faces()) {
        for (const auto vh : mesh.fv_range(fh)) out.indices.push_back(std::uint32_t(vh.idx()));
    }
    if (auto e = validate(out)) {
        return bad("the mesh read is not valid: " + e->field + ": " +
                   std::string(aerial::detail::text_of(*e)));
    }
    return out;
}

}  // namespace aerial::scene
