// Internal: JSON text and files read with the library's error rules, for the atmosphere JSON
// (core/atmosphere_json.cpp) and the scene file (scene/scene_file_json.cpp).
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "aerial/error.hpp"
#include "error_text.hpp"

namespace aerial::detail {

/// Parses JSON text for `function`. The error (field "json") gives nlohmann's message without
/// its "[json.exception.parse_error.101] " prefix: "aerial::FUNCTION(): json: parse error at line
/// 1, column 2: ..." (numbers beyond double raise out_of_range.406 "number overflow parsing ...").
inline Result<nlohmann::json> parse_json(std::string_view function, std::string_view text) {
    try {
        return nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::exception& e) {
        std::string message = e.what();
        const auto bracket = message.find("] ");
        if (bracket != std::string::npos) message = message.substr(bracket + 2);
        return error(function, "json", message);
    }
}

/// The whole file as text, for `function`. Errors (field: the path): "aerial::FUNCTION(): PATH:
/// cannot open the KIND", "...: cannot read the KIND".
inline Result<std::string> read_text_file(std::string_view function, const std::string& path,
                                          const std::string& kind) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return error(function, path, "cannot open the " + kind);
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) return error(function, path, "cannot read the " + kind);
    return text.str();
}

}  // namespace aerial::detail
