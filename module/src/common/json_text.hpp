// Internal: JSON text and files read with the library's error rules, for the atmosphere JSON
// (core/atmosphere_json.cpp) and the scene file (scene/scene_file_json.cpp).
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "aerial/error.hpp"

namespace aerial::detail {

/// Parses JSON text. The error (field "json") is "WHAT: " and nlohmann's message without its
/// "[json.exception.parse_error.101] " prefix ("parse error at line 1, column 2: ..."; numbers
/// beyond double raise out_of_range.406 "number overflow parsing ...").
inline Result<nlohmann::json> parse_json(std::string_view text, const std::string& what) {
    try {
        return nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::exception& e) {
        std::string message = e.what();
        const auto bracket = message.find("] ");
        if (bracket != std::string::npos) message = message.substr(bracket + 2);
        return Error{"json", what + ": " + message};
    }
}

/// The whole file as text. Errors (field: the path): "PATH: cannot open KIND", "PATH: cannot
/// read KIND".
inline Result<std::string> read_text_file(const std::string& path, const std::string& kind) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return Error{path, path + ": cannot open " + kind};
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) return Error{path, path + ": cannot read " + kind};
    return text.str();
}

}  // namespace aerial::detail
