// Internal: the tokens of ARB vertex program text, for the parser (arb_parser.cpp).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace aerial::detail {

struct ArbToken {
    enum class Kind { identifier, number, punct, end } kind = Kind::end;
    std::string_view text;  ///< a view into the program text
    std::size_t offset = 0;
};

/// Where the text cannot be cut into tokens, and why.
struct ArbTokenError {
    std::size_t offset = 0;
    std::string what;
};

/// Appends the tokens after the "!!ARBvp1.0" header (identifiers, numbers, the punctuation
/// ";,.[]{}=-+" and ".."; comments and white space dropped), then an `end` token.
std::optional<ArbTokenError> tokenize_arb_program(std::string_view text,
                                                  std::vector<ArbToken>& tokens);

}  // namespace aerial::detail
