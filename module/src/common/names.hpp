// Internal: one table per enum (value <-> name), read by the name and parse functions of every
// library of the module, so that a name is spelled once and every "unknown name" message has one
// form (error_text.hpp's): "aerial::FUNCTION(): FIELD: expected one of a, b, c, got 'NAME'".
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "aerial/error.hpp"
#include "error_text.hpp"

namespace aerial::detail {

template <class E>
struct Named {
    E value;
    const char* name;
};

template <class E, std::size_t N>
using NameTable = std::array<Named<E>, N>;

/// The name of `value`, or `fallback` for a value not in the table.
template <class E, std::size_t N>
constexpr const char* name_in(const NameTable<E, N>& table, E value,
                              const char* fallback = "unknown") {
    for (const auto& entry : table) {
        if (entry.value == value) return entry.name;
    }
    return fallback;
}

/// The value named `name`, if the table has it.
template <class E, std::size_t N>
std::optional<E> find_in(const NameTable<E, N>& table, std::string_view name) {
    for (const auto& entry : table) {
        if (name == entry.name) return entry.value;
    }
    return std::nullopt;
}

/// "a, b, c": the names in table order.
template <class E, std::size_t N>
std::string names_of(const NameTable<E, N>& table) {
    std::string list;
    for (const auto& entry : table) {
        if (!list.empty()) list += ", ";
        list += entry.name;
    }
    return list;
}

/// The error of `function` for a name the table does not have.
template <class E, std::size_t N>
Error unknown_name(std::string_view function, const NameTable<E, N>& table, std::string field,
                   std::string_view name) {
    return invalid(function, std::move(field), "one of " + names_of(table), quoted(name));
}

/// The value named `name`, or unknown_name().
template <class E, std::size_t N>
Result<E> parse_in(std::string_view function, const NameTable<E, N>& table, std::string field,
                   std::string_view name) {
    if (auto value = find_in(table, name)) return *value;
    return unknown_name(function, table, std::move(field), name);
}

}  // namespace aerial::detail
