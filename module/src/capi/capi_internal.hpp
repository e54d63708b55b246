// The C interface's shared machinery: the per-entry-point guard that turns every failure (and
// every exception) into a status and a message, and the conversions between the C structs and
// the C++ ones. Used by capi_core.cpp (aerial::core) and capi_gl.cpp (aerial::gl).
#pragma once

#include <cstddef>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "aerial/aerial.h"
#include "aerial/atmosphere.hpp"
#include "aerial/batch.hpp"
#include "aerial/error.hpp"
#include "aerial/scattering.hpp"
#include "aerial/sun.hpp"

struct aerial_context {
    aerial::Atmosphere atmosphere;
    aerial::Model model = aerial::Model::height;
    std::optional<aerial::View> view;
    std::optional<aerial::Frame<float>> frame;
    std::string last_error;
};

namespace aerial::capi {

/// Thrown inside an entry point to leave it with a status; never leaves the guard.
struct Failure {
    aerial_status status;
    std::string field;
    std::string text;  ///< the TEXT of "FUNCTION(): FIELD: TEXT" (the guard adds the rest)
};

/// Leaves the entry point with `status`; its message is "aerial_FUNCTION(): FIELD: TEXT", the
/// library's one style (common/error_text.hpp) with the C function's name.
[[noreturn]] void fail(aerial_status status, std::string field, std::string text);
/// A C++ Error as a failure with `status`: its field and TEXT, under the C function's name.
[[noreturn]] void fail(aerial_status status, const Error& error);
/// Fails with AERIAL_ERROR_NULL_ARGUMENT naming `name` ("name: expected a pointer, got NULL").
[[noreturn]] void fail_null(const char* name);
/// Fails with AERIAL_ERROR_NULL_ARGUMENT naming `name` when `pointer` is null.
void require(const void* pointer, const char* name);
/// The same for a function pointer (a callback), which does not convert to const void*.
template <class Return, class... Arguments>
void require(Return (*function)(Arguments...), const char* name) {
    if (function == nullptr) fail_null(name);
}

/// Where a call records its message for `object->last_error` (null when there is no object).
/// The last error is mutable state behind a const handle: recording it changes no result.
template <class Object>
std::string* last_error_of(const Object* object) {
    return object ? &const_cast<Object*>(object)->last_error : nullptr;
}

/// One value of a C enum and the C++ value it stands for.
template <class Cpp>
struct EnumValue {
    int c;
    Cpp cpp;
};

/// The int a C caller stored in an enum field. Read as an int, not as the enum: a value outside
/// the enum's values (a caller's mistake the C API reports) is undefined behaviour to load as the
/// enum type in C++ (UBSan's invalid enum load).
template <class CEnum>
int c_enum_value(const CEnum& field) {
    static_assert(std::is_enum_v<CEnum> && sizeof(CEnum) == sizeof(int));
    int value = 0;
    std::memcpy(&value, &field, sizeof value);
    return value;
}

/// The C++ value of the C enum value `value`, or AERIAL_ERROR_INVALID_ARGUMENT naming `field`:
/// "expected <expected>, got <value>".
template <class Cpp, std::size_t N>
Cpp to_cpp_enum(int value, const EnumValue<Cpp> (&values)[N], const char* field,
                const char* expected) {
    for (const EnumValue<Cpp>& v : values) {
        if (v.c == value) return v.cpp;
    }
    fail(AERIAL_ERROR_INVALID_ARGUMENT, field,
         std::string("expected ") + expected + ", got " + std::to_string(value));
}

/// The value of a C++ result, or a failure with `status` and the result's error.
template <class T>
T value_or_fail(Result<T> result, aerial_status status) {
    if (!result) fail(status, result.error());
    return std::move(result).value();
}

/// Records the outcome of one call for aerial_last_error_*() (and for the object, if any): the
/// message "FUNCTION(): FIELD: TEXT" ("FUNCTION(): TEXT" without a field).
void record(aerial_status status, const char* function, const std::string& field,
            const std::string& text, std::string* object_error);

/// Test hook (capi_testing.hpp): throws the armed exception inside the next guarded call.
void throw_if_armed();

/// Runs `body` (which returns nothing, or fails) and turns the outcome into a status. No
/// exception leaves it.
template <class Body>
aerial_status guard(const char* function, std::string* object_error, Body&& body) noexcept {
    try {
        try {
            throw_if_armed();
            std::forward<Body>(body)();
            record(AERIAL_OK, function, {}, {}, object_error);
            return AERIAL_OK;
        } catch (const Failure& failure) {
            record(failure.status, function, failure.field, failure.text, object_error);
            return failure.status;
        } catch (const std::bad_alloc&) {
            record(AERIAL_ERROR_OUT_OF_MEMORY, function, {}, "out of memory", object_error);
            return AERIAL_ERROR_OUT_OF_MEMORY;
        } catch (const std::exception& e) {
            record(AERIAL_ERROR_INTERNAL, function, {},
                   std::string("internal error (exception: ") + e.what() + ")", object_error);
            return AERIAL_ERROR_INTERNAL;
        } catch (...) {
            record(AERIAL_ERROR_INTERNAL, function, {}, "internal error (unknown exception)",
                   object_error);
            return AERIAL_ERROR_INTERNAL;
        }
    } catch (...) {  // recording itself failed (allocating the message)
        return AERIAL_ERROR_OUT_OF_MEMORY;
    }
}

/// The C atmosphere with its defaults applied (null: all defaults).
Atmosphere to_cpp(const aerial_atmosphere* atmosphere);
/// The C form of a C++ atmosphere: every field explicit, zero_fields where a field is 0.
aerial_atmosphere to_c(const Atmosphere& atmosphere);
View to_cpp(const aerial_view& view);
Display to_cpp(const aerial_display* display);
/// The model, or AERIAL_ERROR_INVALID_ARGUMENT naming `field`.
Model to_cpp_model(int model, const char* field);
/// The exposure options with their defaults applied (null: all defaults), or
/// AERIAL_ERROR_INVALID_ARGUMENT naming the bad field.
ExposureOptions exposure_options(const aerial_exposure_options* options);

/// The C positions (model matrix included), or AERIAL_ERROR_INVALID_BATCH.
Positions to_cpp_positions(const aerial_positions& positions);
/// The colour format, or AERIAL_ERROR_INVALID_ARGUMENT naming `field`.
ColourFormat to_cpp_format(int format, const char* field);

/// The context's current frame, or AERIAL_ERROR_NO_VIEW.
const Frame<float>& current_frame(const aerial_context& context);

}  // namespace aerial::capi
