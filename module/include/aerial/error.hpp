// aerial/error.hpp — errors as values.
//
// How to use this:
//   1. Functions that can reject their input return `std::optional<aerial::Error>` (nullopt
//      means "fine") or `aerial::Result<T>` (a value, or the first error found).
//   2. `Error::field` names the offending field ("mie_g", "rayleigh_scattering[2]", "eye");
//      `Error::message` is one line for a person, in one style everywhere:
//          aerial::FUNCTION(): FIELD: expected EXPECTED, got GOT
//      e.g. "aerial::validate(): mie_g: expected |g| < 1 (g > 0 scatters forwards), got 1.5".
//      FUNCTION is the public function you called (an error of a function it called is
//      reported as its own); where there is no value to compare, a short clause follows FIELD
//      ("aerial::scene::load_mesh_file(): PATH: cannot open the file (missing or unreadable)");
//      an error in a file's content ends with " (in PATH)". The C interface's messages read
//      the same with the C function's name: "aerial_validate_atmosphere(): mie_g: expected
//      ..., got 1.5".
//   3. `Error::kind` tells a wrong input from a context that lacks what the call needs (an
//      extension, a compatibility profile, a headless platform): regression suites report the
//      second as "not supported", not as a failure.
//   4. Nothing in the core throws for bad input; exceptions are reserved for allocation failure.
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace aerial {

/// Why a call could not do its work.
enum class ErrorKind {
    invalid_input,  ///< the caller's input is wrong (a NaN, a negative coefficient, a bad file)
    not_supported,  ///< the GL context or platform lacks what the call needs; the input is fine
};

/// The first problem found in an input.
struct Error {
    std::string field;    ///< the offending field, flag or line ("mie_g", "--eye", "line 3")
    std::string message;  ///< one line: "aerial::FUNCTION(): FIELD: expected ..., got ..."
    ErrorKind kind = ErrorKind::invalid_input;
};

/// An error of kind not_supported: `field` names what is missing ("GL_ARB_vertex_program",
/// "profile", "libEGL"). `message` is kept as given (for a caller's own errors; the library
/// builds its errors in the style above).
inline Error not_supported(std::string field, std::string message) {
    return Error{std::move(field), std::move(message), ErrorKind::not_supported};
}

/// A value or the first error that prevented computing it.
template <class T>
class Result {
  public:
    Result(T value) : value_(std::move(value)) {}      // NOLINT(google-explicit-constructor)
    Result(Error error) : error_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

    bool ok() const { return value_.has_value(); }
    explicit operator bool() const { return ok(); }

    /// The value; only valid when ok().
    const T& value() const& { return *value_; }
    T& value() & { return *value_; }
    T&& value() && { return std::move(*value_); }
    const T& operator*() const& { return *value_; }
    const T* operator->() const { return &*value_; }

    /// The error; only meaningful when !ok().
    const Error& error() const { return error_; }

  private:
    std::optional<T> value_;
    Error error_;
};

}  // namespace aerial
