// Internal: the one way to build an aerial::Error. Every message of the module reads
//
//     aerial::FUNCTION(): FIELD: TEXT
//
//   FUNCTION  the public function the user called, as written after "aerial::" ("validate",
//             "scene::load_scene_file", "scene::SceneRenderer::render"); an internal helper that
//             several public functions share takes it as a parameter, or its caller re-attributes
//             the error with from().
//   FIELD     Error::field: the offending field, flag, file or line ("mie_g", "camera.eye").
//   TEXT      "expected EXPECTED, got GOT" (invalid()), or a short clause where there is no value
//             to show (error(), unsupported()). Values in TEXT are printed with number() and
//             vector(), so that every number reads one way.
//
//     return detail::invalid("validate", "mie_g", "|g| < 1", detail::number(a.mie_g));
//         -> {"mie_g", "aerial::validate(): mie_g: expected |g| < 1, got 1.5"}
//     return detail::error("scene::load_mesh_file", path, "cannot open the file");
//         -> {path, "aerial::scene::load_mesh_file(): PATH: cannot open the file"}
//     return detail::unsupported("gl::load_api", "profile", "the context is core-profile");
//         -> the same, of kind ErrorKind::not_supported
//     if (auto e = validate(atmosphere)) return detail::from("prepare_frame", *e);
//         -> validate()'s field, TEXT and kind, attributed to prepare_frame
//     if (!a) return detail::from("scene::scene_file_from_json", a.error(), "atmosphere.");
//         -> field "atmosphere.mie_g": "aerial::scene::scene_file_from_json(): atmosphere.mie_g:
//         ..."
//     if (!scene) return detail::from_file("scene::load_scene_file", path, scene.error());
//         -> "aerial::scene::load_scene_file(): camera.eye[0]: expected ..., got ... (in PATH)"
//
// Converting an old site: `Error{"f", "f: must be > 0, got " + std::to_string(x)}` becomes
// `detail::invalid(FUNCTION, "f", "a value > 0", detail::number(x))`; `not_supported("f", "f:
// TEXT")` becomes `detail::unsupported(FUNCTION, "f", "TEXT")`; `return e;` of a called public
// function becomes `return detail::from(FUNCTION, *e);`. Inside a namespace that has its own
// `detail` (aerial::gl, aerial::scene) write `aerial::detail::`. Keep Error::field as it was:
// callers and the C interface read it. Tests pin whole messages (EXPECT_EQ on .message).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "aerial/error.hpp"

namespace aerial::detail {

// ---- Values ------------------------------------------------------------------------------------

/// A number as a message shows it: integers in full; floating-point values in the fewest digits
/// (6 to 17) that read back as the same value ("0.1", "5.802e-06", "1234567"); "nan", "inf" and
/// "-inf" for the values that are not finite.
template <class T>
std::string number(T value) {
    static_assert(std::is_arithmetic_v<T>);
    if constexpr (std::is_integral_v<T>) {
        return std::to_string(value);
    } else {
        if (std::isnan(value)) return "nan";
        if (std::isinf(value)) return value < 0 ? "-inf" : "inf";
        char buffer[32];
        for (int digits = 6; digits <= 17; ++digits) {
            std::snprintf(buffer, sizeof buffer, "%.*g", digits, double(value));
            if (T(std::strtod(buffer, nullptr)) == value) break;
        }
        return buffer;
    }
}

/// A vector (glm::dvec3, std::array<float, 4>, ...) as "(x, y, z)", each coordinate a number().
template <class Vector>
std::string vector(const Vector& v) {
    const auto* coordinate = &v[0];  // contiguous in glm's vectors and in std::array
    std::string text = "(";
    for (std::size_t i = 0; i < sizeof v / sizeof v[0]; ++i)
        text += (i ? ", " : "") + number(coordinate[i]);
    return text + ")";
}

/// A name as a message shows it: in single quotes ("'venus'").
inline std::string quoted(std::string_view name) { return "'" + std::string(name) + "'"; }

// ---- Errors ------------------------------------------------------------------------------------

/// "FUNCTION(): FIELD: TEXT" with FUNCTION exactly as given ("FUNCTION(): TEXT" without a field).
/// For names that are not aerial::'s C++ functions (the C interface's "aerial_context_set_view");
/// everything else goes through error().
inline std::string styled(std::string_view function, std::string_view field,
                          std::string_view text) {
    std::string message = std::string(function) + "(): ";
    if (!field.empty()) message += std::string(field) + ": ";
    return message + std::string(text);
}

/// {field, "aerial::FUNCTION(): FIELD: TEXT"}.
inline Error error(std::string_view function, std::string field, std::string_view text) {
    std::string message = styled("aerial::" + std::string(function), field, text);
    return Error{std::move(field), std::move(message)};
}

/// {field, "aerial::FUNCTION(): FIELD: expected EXPECTED, got GOT"}: the input is wrong.
inline Error invalid(std::string_view function, std::string field, std::string_view expected,
                     std::string_view got) {
    return error(function, std::move(field),
                 "expected " + std::string(expected) + ", got " + std::string(got));
}

/// error() of kind ErrorKind::not_supported: the context or platform lacks what the call needs
/// (FIELD names it: "GL_ARB_vertex_program", "profile", "libEGL").
inline Error unsupported(std::string_view function, std::string field, std::string_view text) {
    Error e = error(function, std::move(field), text);
    e.kind = ErrorKind::not_supported;
    return e;
}

/// TEXT of an error's message: what follows "aerial::FUNCTION(): " and "FIELD: ".
inline std::string_view text_of(const Error& e) {
    std::string_view text = e.message;
    if (text.substr(0, 8) == "aerial::") {
        const auto end = text.find("(): ");
        if (end != std::string_view::npos) text.remove_prefix(end + 4);
    }
    if (!e.field.empty() && text.substr(0, e.field.size()) == e.field &&
        text.substr(e.field.size(), 2) == ": ") {
        text.remove_prefix(e.field.size() + 2);
    }
    return text;
}

/// `inner` (an error of a function this one called) as this FUNCTION's: the same TEXT and kind,
/// the field prefixed by `field_prefix` ("atmosphere." + "mie_g").
inline Error from(std::string_view function, const Error& inner,
                  std::string_view field_prefix = {}) {
    Error e = error(function, std::string(field_prefix) + inner.field, text_of(inner));
    e.kind = inner.kind;
    return e;
}

/// from() for an error in the content of the file `path`: TEXT ends with " (in PATH)", so that a
/// message shown alone still names the file. An error already about the file itself (its field
/// is the path: "cannot open ...") is only re-attributed.
inline Error from_file(std::string_view function, const std::string& path, const Error& inner,
                       std::string_view field_prefix = {}) {
    if (inner.field == path) return from(function, inner);
    Error e = from(function, inner, field_prefix);
    e.message += " (in " + path + ")";
    return e;
}

}  // namespace aerial::detail
