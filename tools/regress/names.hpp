// One table per enum of the runner (value <-> name): the names of statuses, tiers and case kinds
// are spelled once, for the reports, the suite file and the baselines.
#pragma once

#include <optional>
#include <string_view>
#include <utility>

namespace aerial::regress {

template <class E, std::size_t N>
using Names = std::pair<E, const char*>[N];

template <class E, std::size_t N>
const char* name_in(const Names<E, N>& table, E value) {
    for (const auto& [v, name] : table) {
        if (v == value) return name;
    }
    return "unknown";
}

template <class E, std::size_t N>
std::optional<E> value_in(const Names<E, N>& table, std::string_view name) {
    for (const auto& [v, n] : table) {
        if (name == n) return v;
    }
    return std::nullopt;
}

}  // namespace aerial::regress
