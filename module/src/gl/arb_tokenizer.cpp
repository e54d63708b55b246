// The tokens of ARB vertex program text (see arb_tokenizer.hpp).
#include "arb_tokenizer.hpp"

namespace aerial::detail {
namespace {

bool is_identifier_start(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == '$';
}
bool is_digit(char c) { return c >= '0' && c <= '9'; }

}  // namespace

std::optional<ArbTokenError> tokenize_arb_program(std::string_view text,
                                                  std::vector<ArbToken>& tokens) {
    constexpr std::string_view kHeader = "!!ARBvp1.0";
    if (text.substr(0, kHeader.size()) != kHeader) {
        return ArbTokenError{0, "a vertex program must start with \"!!ARBvp1.0\""};
    }
    std::size_t i = kHeader.size();
    const std::size_t n = text.size();
    while (i < n) {
        const char c = text[i];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
            ++i;
        } else if (c == '#') {
            while (i < n && text[i] != '\n' && text[i] != '\r') ++i;
        } else if (is_identifier_start(c)) {
            const std::size_t start = i;
            while (i < n && (is_identifier_start(text[i]) || is_digit(text[i]))) ++i;
            tokens.push_back({ArbToken::Kind::identifier, text.substr(start, i - start), start});
        } else if (is_digit(c) || (c == '.' && i + 1 < n && is_digit(text[i + 1]))) {
            const std::size_t start = i;
            while (i < n && is_digit(text[i])) ++i;
            // A fraction, but not the ".." of a range nor the "." of a swizzle.
            if (i < n && text[i] == '.' && !(i + 1 < n && text[i + 1] == '.') &&
                !(i + 1 < n && is_identifier_start(text[i + 1]))) {
                ++i;
                while (i < n && is_digit(text[i])) ++i;
            }
            if (i < n && (text[i] == 'e' || text[i] == 'E')) {
                std::size_t j = i + 1;
                if (j < n && (text[j] == '+' || text[j] == '-')) ++j;
                if (j < n && is_digit(text[j])) {
                    i = j;
                    while (i < n && is_digit(text[i])) ++i;
                }
            }
            tokens.push_back({ArbToken::Kind::number, text.substr(start, i - start), start});
        } else if (c == '.' && i + 1 < n && text[i + 1] == '.') {
            tokens.push_back({ArbToken::Kind::punct, text.substr(i, 2), i});
            i += 2;
        } else if (std::string_view(";,.[]{}=-+").find(c) != std::string_view::npos) {
            tokens.push_back({ArbToken::Kind::punct, text.substr(i, 1), i});
            ++i;
        } else {
            return ArbTokenError{i, std::string("unexpected character '") + c + "'"};
        }
    }
    tokens.push_back({ArbToken::Kind::end, std::string_view{}, n});
    return std::nullopt;
}

}  // namespace aerial::detail
