// The module's strict ASCII OFF reader; see off_reader.hpp.
#include "off_reader.hpp"

#include <cerrno>
#include <cstdlib>
#include <iterator>
#include <regex>
#include <vector>

namespace aerial::scene::detail {
namespace {

/// One line's words (split at spaces and tabs, a '#' comment dropped) and its 1-based number.
struct Line {
    long long number = 0;
    std::vector<std::string> words;
};

std::vector<Line> significant_lines(const std::string& text) {
    std::vector<Line> lines;
    long long number = 0;
    for (std::size_t start = 0; start <= text.size();) {
        auto end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(start, end - start);
        start = end + 1;
        ++number;
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        Line out{number, {}};
        for (std::size_t i = 0; i < line.size();) {
            const auto word_start = line.find_first_not_of(" \t", i);
            if (word_start == std::string::npos) break;
            auto word_end = line.find_first_of(" \t", word_start);
            if (word_end == std::string::npos) word_end = line.size();
            out.words.push_back(line.substr(word_start, word_end - word_start));
            i = word_end;
        }
        if (!out.words.empty()) lines.push_back(std::move(out));
    }
    return lines;
}

/// The word as quoted in an error message: at most 40 bytes.
std::string quoted(const std::string& word) { return "'" + word.substr(0, 40) + "'"; }

bool to_float(const std::string& word, float& value) {
    char* end = nullptr;
    errno = 0;
    value = std::strtof(word.c_str(), &end);
    return end != word.c_str() && *end == '\0';
}

bool to_count(const std::string& word, long long& value) {
    char* end = nullptr;
    errno = 0;
    value = std::strtoll(word.c_str(), &end, 10);
    return end != word.c_str() && *end == '\0' && errno == 0 && value >= 0;
}

}  // namespace

std::optional<std::string> read_off(std::istream& in, OpenMesh::IO::BaseImporter& importer,
                                    OffContents& contents) {
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const std::vector<Line> lines = significant_lines(text);
    const auto at = [](const Line& line, const std::string& what) {
        return "line " + std::to_string(line.number) + ": " + what;
    };
    if (lines.empty()) return std::string("the file is empty (expected an OFF header)");

    // Header word: [ST][C][N][4][n]OFF (Geomview's order, as OpenMesh reads it).
    static const std::regex header_word("(ST)?(C)?(N)?(4)?(n)?OFF");
    std::smatch parts;
    const Line& header = lines[0];
    if (!std::regex_match(header.words[0], parts, header_word)) {
        return at(header, "it does not start with an OFF header word ([ST][C][N]OFF), got " +
                              quoted(header.words[0]));
    }
    if (parts[4].matched || parts[5].matched) {
        return at(header, "4OFF and nOFF (vertices of other than 3 coordinates) are not supported");
    }
    contents.texcoords = parts[1].matched;
    const bool colours = parts[2].matched;
    contents.normals = parts[3].matched;

    // Counts: on the header line after the word, or alone on the next line.
    std::size_t next = 1;
    std::vector<std::string> count_words(header.words.begin() + 1, header.words.end());
    const Line* count_line = &header;
    if (count_words.empty()) {
        if (lines.size() < 2) return at(header, "no vertex and face counts after the header");
        count_line = &lines[1];
        count_words = lines[1].words;
        next = 2;
    }
    if (count_words[0] == "BINARY") return at(*count_line, "binary OFF is not supported");
    long long counts[3] = {0, 0, 0};  // vertices, faces, edges (edges are not used)
    if (count_words.size() < 2 || count_words.size() > 3 || !to_count(count_words[0], counts[0]) ||
        !to_count(count_words[1], counts[1]) ||
        (count_words.size() == 3 && !to_count(count_words[2], counts[2]))) {
        return at(*count_line, "expected the vertex and face counts 'VERTICES FACES [EDGES]'");
    }
    // Every element is one line, so the file bounds the counts before anything is stored.
    const auto available = static_cast<long long>(lines.size() - next);
    if (counts[0] > available || counts[1] > available - counts[0]) {
        return "its header declares " + std::to_string(counts[0]) + " vertices and " +
               std::to_string(counts[1]) + " faces in a file of " + std::to_string(available) +
               " more lines";
    }

    const std::size_t fixed = 3 + (contents.normals ? 3 : 0) + (contents.texcoords ? 2 : 0);
    std::vector<OpenMesh::VertexHandle> vertices;
    vertices.reserve(std::size_t(counts[0]));
    for (long long v = 0; v < counts[0]; ++v) {
        const Line& line = lines[next++];
        const std::size_t n = line.words.size();
        const bool fits = colours ? (n == fixed + 3 || n == fixed + 4) : n == fixed;
        if (!fits) {
            return at(line, "vertex " + std::to_string(v) + " has " + std::to_string(n) +
                                " numbers, expected " + std::to_string(fixed) +
                                (colours ? " plus 3 or 4 colour components" : ""));
        }
        float values[12];
        for (std::size_t i = 0; i < n; ++i) {
            if (!to_float(line.words[i], values[i])) {
                return at(line, "vertex " + std::to_string(v) + ": " + quoted(line.words[i]) +
                                    " is not a number");
            }
        }
        const auto vh = importer.add_vertex(OpenMesh::Vec3f(values[0], values[1], values[2]));
        if (contents.normals) {
            importer.set_normal(vh, OpenMesh::Vec3f(values[3], values[4], values[5]));
        }
        if (contents.texcoords) {
            const std::size_t st = n - 2;
            importer.set_texcoord(vh, OpenMesh::Vec2f(values[st], values[st + 1]));
        }
        vertices.push_back(vh);
    }

    std::vector<OpenMesh::VertexHandle> corners;
    for (long long f = 0; f < counts[1]; ++f) {
        const Line& line = lines[next++];
        const std::string face = "face " + std::to_string(f) + ": ";
        long long n = 0;
        if (!to_count(line.words[0], n) || n < 3) {
            return at(line,
                      face + "expected its vertex count (3 or more), got " + quoted(line.words[0]));
        }
        const auto extra = static_cast<long long>(line.words.size()) - 1 - n;
        if (extra < 0 || extra > 4) {
            return at(line, face + "expected " + std::to_string(n) +
                                " vertex indices and at most 4 colour components, got " +
                                std::to_string(line.words.size() - 1) + " numbers");
        }
        corners.clear();
        for (long long i = 1; i <= n; ++i) {
            long long index = 0;
            if (!to_count(line.words[std::size_t(i)], index) || index >= counts[0]) {
                return at(line, face + "vertex index " + quoted(line.words[std::size_t(i)]) +
                                    " is not one of the " + std::to_string(counts[0]) +
                                    " vertices");
            }
            corners.push_back(vertices[std::size_t(index)]);
        }
        for (std::size_t i = std::size_t(n) + 1; i < line.words.size(); ++i) {
            float colour = 0.0f;
            if (!to_float(line.words[i], colour)) {
                return at(line, face + quoted(line.words[i]) + " is not a colour component");
            }
        }
        importer.add_face(corners);
    }
    if (next < lines.size()) {
        return at(lines[next], "more lines than the header's " + std::to_string(counts[0]) +
                                   " vertices and " + std::to_string(counts[1]) + " faces");
    }
    return std::nullopt;
}

}  // namespace aerial::scene::detail
