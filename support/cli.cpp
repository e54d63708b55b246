#include "cli.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include <glm/geometric.hpp>

namespace aerial::tools {
namespace {

std::string_view trim(std::string_view s) {
    const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

/// Splits "a,b,c" into exactly three numbers.
std::optional<glm::dvec3> parse_triple(std::string_view text) {
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i) {
        const size_t comma = text.find(',');
        if ((i < 2) != (comma != std::string_view::npos)) return std::nullopt;
        const auto value = parse_number(text.substr(0, comma));
        if (!value) return std::nullopt;
        v[i] = *value;
        text = i < 2 ? text.substr(comma + 1) : std::string_view{};
    }
    return v;
}

}  // namespace

std::optional<double> parse_number(std::string_view text) {
    const std::string s(trim(text));
    if (s.empty()) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(s.c_str(), &end);
    if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(value))
        return std::nullopt;
    return value;
}

Result<glm::dvec3> parse_vec3(std::string_view text, const std::string& flag) {
    if (auto v = parse_triple(text)) return *v;
    return Error{flag,
                 flag + ": expected three finite numbers X,Y,Z, got '" + std::string(text) + "'"};
}

Result<glm::dvec3> parse_direction(std::string_view text, const std::string& flag) {
    auto v = parse_vec3(text, flag);
    if (!v) return v;
    const double length = glm::length(*v);
    if (!(length > 1e-12) || !std::isfinite(length)) {
        return Error{flag,
                     flag + ": expected a non-zero direction, got '" + std::string(text) + "'"};
    }
    return *v / length;
}

Result<std::pair<int, int>> parse_size(std::string_view text, const std::string& flag,
                                       int max_side) {
    const size_t x = text.find('x');
    const auto side = [&](std::string_view part) -> int {
        if (part.empty() || part.size() > 6) return 0;
        int v = 0;
        for (char c : part) {
            if (c < '0' || c > '9') return 0;
            v = v * 10 + (c - '0');
        }
        return v;
    };
    const int w = x == std::string_view::npos ? 0 : side(text.substr(0, x));
    const int h = x == std::string_view::npos ? 0 : side(text.substr(x + 1));
    if (w < 1 || h < 1 || w > max_side || h > max_side) {
        return Error{flag, flag + ": expected WxH with W and H in 1.." + std::to_string(max_side) +
                               ", got '" + std::string(text) + "'"};
    }
    return std::pair<int, int>{w, h};
}

Result<std::vector<glm::dvec3>> parse_points(std::string_view text, const std::string& source) {
    std::vector<glm::dvec3> points;
    size_t line_number = 0;
    while (!text.empty()) {
        ++line_number;
        const size_t newline = text.find('\n');
        std::string_view line = text.substr(0, newline);
        text = newline == std::string_view::npos ? std::string_view{} : text.substr(newline + 1);
        const size_t hash = line.find('#');
        if (hash != std::string_view::npos) line = line.substr(0, hash);
        line = trim(line);
        if (line.empty()) continue;
        const auto p = parse_triple(line);
        if (!p) {
            const std::string where = source + " line " + std::to_string(line_number);
            return Error{where, where + ": expected a point x,y,z of three finite numbers, got '" +
                                    std::string(line) + "'"};
        }
        points.push_back(*p);
    }
    return points;
}

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv, std::string_view tool) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        return 0;
    } catch (const CLI::ParseError& e) {
        // CLI11 checks required options before unknown arguments: name an unknown one first
        // (`--bogus` alone is about --bogus, not about a missing --scene).
        if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && !app.remaining().empty()) {
            return fail(tool, "The following argument was not expected: " +
                                  app.remaining().front() + " (see --help)");
        }
        std::string what = e.what();
        if (what.empty()) what = e.get_name();
        return fail(tool, what + " (see --help)");
    }
    return std::nullopt;
}

int fail(std::string_view tool, std::string_view message) {
    std::cerr << tool << ": " << message << '\n';
    return kExitBadInput;
}

}  // namespace aerial::tools
