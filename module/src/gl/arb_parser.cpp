// Parser of ARB vertex programs: the subset generate_arb_program emits plus the other scalar
// instructions. A tokenizer and a parser that resolves every name to a register slot while
// loading (as GL does). The generator counts its programs' resources with it; the CPU executor
// of the parsed instructions is aerial::validation's (validation/src/arb_executor.cpp).
#include "arb_parser.hpp"
#include "arb_tokenizer.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <system_error>

#include "../common/error_text.hpp"

namespace aerial::detail {
namespace {

constexpr OpcodeInfo kOpcodes[] = {
    {"MOV", Opcode::mov, Form::vector1, 0},
    {"ADD", Opcode::add, Form::vector2, 0},
    {"SUB", Opcode::sub, Form::vector2, 0},
    {"MUL", Opcode::mul, Form::vector2, 0},
    {"MAD", Opcode::mad, Form::vector3, 0},
    {"DP3", Opcode::dp3, Form::vector2, 0},
    {"DP4", Opcode::dp4, Form::vector2, 0},
    {"DPH", Opcode::dph, Form::vector2, 0},
    {"MIN", Opcode::min, Form::vector2, 0},
    {"MAX", Opcode::max, Form::vector2, 0},
    {"SGE", Opcode::sge, Form::vector2, 0},
    {"SLT", Opcode::slt, Form::vector2, 0},
    {"SWZ", Opcode::swz, Form::swizzle, 0},
    {"EX2", Opcode::ex2, Form::scalar1, kArbApproxBitEx2},
    {"LG2", Opcode::lg2, Form::scalar1, kArbApproxBitLg2},
    {"EXP", Opcode::exp, Form::scalar1, kArbApproxBitExp},
    {"LOG", Opcode::log, Form::scalar1, kArbApproxBitLog},
    {"RCP", Opcode::rcp, Form::scalar1, kArbApproxBitRcp},
    {"RSQ", Opcode::rsq, Form::scalar1, kArbApproxBitRsq},
    {"POW", Opcode::pow, Form::scalar2, kArbApproxBitPow},
    {"FLR", Opcode::flr, Form::vector1, 0},
    {"FRC", Opcode::frc, Form::vector1, 0},
    {"ARL", Opcode::arl, Form::address, 0},
};

/// Keywords of the language (spec section 2.14.2) that may not name a variable.
constexpr const char* kReserved[] = {
    "ABS", "ADD", "ADDRESS", "ALIAS",  "ARL",    "ATTRIB",  "DP3",    "DP4",   "DPH",    "DST",
    "END", "EX2", "EXP",     "FLR",    "FRC",    "LG2",     "LIT",    "LOG",   "MAD",    "MAX",
    "MIN", "MOV", "MUL",     "OPTION", "OUTPUT", "PARAM",   "POW",    "RCP",   "RSQ",    "SGE",
    "SLT", "SUB", "SWZ",     "TEMP",   "XPD",    "program", "result", "state", "vertex",
};

using Token = ArbToken;

/// Bindings of the same state or the same constant vector count once (section 2.14.3.7).
bool same_binding(const ParamBinding& a, const ParamBinding& b) {
    return a.kind == b.kind &&
           (a.kind == ParamBinding::Kind::constant ? a.value == b.value : a.index == b.index);
}

class Parser {
  public:
    Parser(std::string_view function, std::string_view text) : function_(function), text_(text) {}

    Result<ParsedArbProgram> parse();

  private:
    struct Symbol {
        enum class Kind { temp, attrib, param, param_array, output, address } kind = Kind::temp;
        int index = 0;  ///< slot (param: first binding of the array)
        int size = 1;
    };

    // Tokenizer.
    std::optional<Error> tokenize();
    const Token& peek(std::size_t ahead = 0) const {
        return tokens_[std::min(pos_ + ahead, tokens_.size() - 1)];
    }
    const Token& next() {
        const Token& t = peek();
        if (pos_ < tokens_.size() - 1) ++pos_;
        return t;
    }
    bool accept(std::string_view text) {
        if (peek().kind != Token::Kind::end && peek().text == text) {
            next();
            return true;
        }
        return false;
    }
    /// An optional sign: true after "-", false after "+" or none.
    bool accept_sign() {
        if (accept("-")) return true;
        accept("+");
        return false;
    }
    /// True when a constant (a vector, or a scalar with or without a sign) comes next.
    bool at_constant() const {
        return peek().text == "{" || peek().kind == Token::Kind::number || peek().text == "-" ||
               peek().text == "+";
    }

    // Errors carry the line and column of the offending token.
    Error error_at(std::size_t offset, const std::string& what) const;
    Error error(const std::string& what) const { return error_at(peek().offset, what); }
    std::optional<Error> expect(std::string_view text);
    std::optional<Error> expect_identifier(std::string& out);
    std::optional<Error> expect_integer(int& out);
    std::optional<Error> parse_signed_float(float& out);
    std::optional<Error> parse_constant_vector(Vec4& out);
    /// A constant binding: "{ ... }", or a signed scalar in all four components.
    std::optional<Error> parse_constant(ParamBinding& b);

    // Declarations.
    std::optional<Error> declare(const std::string& name, std::size_t offset, Symbol symbol);
    std::optional<Error> parse_attrib_binding(int& slot);
    std::optional<Error> parse_texcoord_unit(const char* binding, std::size_t at, int& unit);
    std::optional<Error> parse_result_binding(int& slot);
    std::optional<Error> parse_param_single(int& binding);
    std::optional<Error> parse_param_multiple(std::vector<int>& bindings);
    int add_param(const ParamBinding& b);
    /// Adds the bindings of `kind` with indices first .. last.
    void add_params(ParamBinding::Kind kind, int first, int last, std::vector<int>& bindings);

    // Statements.
    std::optional<Error> parse_statement();
    std::optional<Error> parse_instruction(const OpcodeInfo& info);
    std::optional<Error> parse_dest(Dest& dst);
    std::optional<Error> parse_register(Source& src);
    std::optional<Error> parse_source(Source& src, bool scalar);
    std::optional<Error> parse_swz_source(Source& src);

    std::string_view function_;  ///< the public function the errors are attributed to
    std::string_view text_;
    std::vector<Token> tokens_;
    std::size_t pos_ = 0;
    std::map<std::string, Symbol, std::less<>> symbols_;
    std::set<int> attributes_;
    bool position_invariant_ = false;
    ArbCpuProgramData data_;
};

Error Parser::error_at(std::size_t offset, const std::string& what) const {
    int line = 1;
    std::size_t line_start = 0;
    for (std::size_t i = 0; i < offset && i < text_.size(); ++i) {
        if (text_[i] == '\n') {
            ++line;
            line_start = i + 1;
        }
    }
    return detail::error(function_, "line " + std::to_string(line),
                         "column " + std::to_string(offset - line_start + 1) + ": " + what);
}

std::optional<Error> Parser::tokenize() {
    if (auto e = tokenize_arb_program(text_, tokens_)) return error_at(e->offset, e->what);
    return std::nullopt;
}

std::optional<Error> Parser::expect(std::string_view text) {
    if (accept(text)) return std::nullopt;
    const std::string got = peek().kind == Token::Kind::end ? "the end of the program"
                                                            : "'" + std::string(peek().text) + "'";
    return error("expected '" + std::string(text) + "', got " + got);
}

std::optional<Error> Parser::expect_identifier(std::string& out) {
    if (peek().kind != Token::Kind::identifier) {
        return error("expected a name, got '" + std::string(peek().text) + "'");
    }
    out = std::string(next().text);
    return std::nullopt;
}

std::optional<Error> Parser::expect_integer(int& out) {
    const Token& t = peek();
    if (t.kind != Token::Kind::number ||
        t.text.find_first_not_of("0123456789") != std::string_view::npos) {
        return error("expected an integer, got '" + std::string(t.text) + "'");
    }
    const auto [ptr, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), out);
    if (ec != std::errc() || ptr != t.text.data() + t.text.size()) {
        return error("integer '" + std::string(t.text) + "' is out of range");
    }
    next();
    return std::nullopt;
}

std::optional<Error> Parser::parse_signed_float(float& out) {
    const bool negative = accept_sign();
    const Token& t = peek();
    if (t.kind != Token::Kind::number) {
        return error("expected a number, got '" + std::string(t.text) + "'");
    }
    float value = 0.0f;
    const auto [ptr, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), value);
    if (ec != std::errc() || ptr != t.text.data() + t.text.size()) {
        return error("'" + std::string(t.text) + "' is not a valid number");
    }
    next();
    out = negative ? -value : value;
    return std::nullopt;
}

std::optional<Error> Parser::parse_constant_vector(Vec4& out) {
    // "{" x [, y [, z [, w]]] "}"; missing components are 0, 0, 1 (spec section 2.14.3.2).
    if (auto e = expect("{")) return e;
    out = {0.0f, 0.0f, 0.0f, 1.0f};
    for (int i = 0; i < 4; ++i) {
        if (auto e = parse_signed_float(out[i])) return e;
        if (!accept(",")) break;
        if (i == 3) return error("a constant vector has at most four components");
    }
    return expect("}");
}

std::optional<Error> Parser::parse_constant(ParamBinding& b) {
    if (peek().text == "{") return parse_constant_vector(b.value);
    float x = 0.0f;
    if (auto e = parse_signed_float(x)) return e;
    b.value = {x, x, x, x};
    return std::nullopt;
}

std::optional<Error> Parser::declare(const std::string& name, std::size_t offset, Symbol symbol) {
    for (const char* r : kReserved) {
        if (name == r) return error_at(offset, "'" + name + "' is a reserved word");
    }
    if (!symbols_.emplace(name, symbol).second) {
        return error_at(offset, "'" + name + "' is already declared");
    }
    return std::nullopt;
}

int Parser::add_param(const ParamBinding& b) {
    for (std::size_t i = 0; i < data_.params.size(); ++i) {
        if (same_binding(data_.params[i], b)) return static_cast<int>(i);
    }
    data_.params.push_back(b);
    return static_cast<int>(data_.params.size() - 1);
}

void Parser::add_params(ParamBinding::Kind kind, int first, int last, std::vector<int>& bindings) {
    for (int i = first; i <= last; ++i) {
        ParamBinding b;
        b.kind = kind;
        b.index = i;
        bindings.push_back(add_param(b));
    }
}

std::optional<Error> Parser::parse_attrib_binding(int& slot) {
    // "vertex" already consumed.
    if (auto e = expect(".")) return e;
    const std::size_t at = peek().offset;
    std::string item;
    if (auto e = expect_identifier(item)) return e;
    if (item == "position") {
        slot = kAttribPosition;
    } else if (item == "texcoord") {
        int unit = 0;
        if (auto e = parse_texcoord_unit("vertex", at, unit)) return e;
        slot = kAttribTexcoord0 + unit;
    } else {
        return error_at(at, "vertex." + item + " is not supported by this interpreter");
    }
    attributes_.insert(slot);
    return std::nullopt;
}

/// The optional "[unit]" after "<binding>.texcoord" (unit 0 when absent), within the units the
/// interpreter models.
std::optional<Error> Parser::parse_texcoord_unit(const char* binding, std::size_t at, int& unit) {
    unit = 0;
    if (accept("[")) {
        if (auto e = expect_integer(unit)) return e;
        if (auto e = expect("]")) return e;
    }
    if (unit >= kArbMaxTexcoordUnits) {
        return error_at(at, std::string(binding) + ".texcoord[" + std::to_string(unit) +
                                "]: at most " + std::to_string(kArbMaxTexcoordUnits) + " units");
    }
    return std::nullopt;
}

std::optional<Error> Parser::parse_result_binding(int& slot) {
    // "result" already consumed.
    if (auto e = expect(".")) return e;
    const std::size_t at = peek().offset;
    std::string item;
    if (auto e = expect_identifier(item)) return e;
    if (item == "position") {
        if (position_invariant_) {
            return error_at(at,
                            "result.position cannot be written by a program with OPTION "
                            "ARB_position_invariant");
        }
        slot = kOutPosition;
    } else if (item == "color") {
        slot = kOutPrimary;
        // ".primary" / ".secondary" follow; a write mask would be ".x" etc., left for the caller.
        if (peek().text == "." && (peek(1).text == "primary" || peek(1).text == "secondary")) {
            next();
            slot = next().text == "primary" ? kOutPrimary : kOutSecondary;
        } else if (peek().text == "." && (peek(1).text == "front" || peek(1).text == "back")) {
            return error("result.color." + std::string(peek(1).text) +
                         " is not supported by this interpreter");
        }
    } else if (item == "fogcoord") {
        slot = kOutFog;
    } else if (item == "texcoord") {
        int unit = 0;
        if (auto e = parse_texcoord_unit("result", at, unit)) return e;
        slot = kOutTexcoord0 + unit;
    } else {
        return error_at(at, "result." + item + " is not supported by this interpreter");
    }
    return std::nullopt;
}

std::optional<Error> Parser::parse_param_single(int& binding) {
    // program.local[i] | program.env[i] | state.matrix.mvp.row[i] | constant.
    if (at_constant()) {
        ParamBinding b;
        if (auto e = parse_constant(b)) return e;
        binding = add_param(b);
        return std::nullopt;
    }
    std::vector<int> bindings;
    const std::size_t at = peek().offset;
    if (auto e = parse_param_multiple(bindings)) return e;
    if (bindings.size() != 1) return error_at(at, "expected a single parameter, got a matrix");
    binding = bindings[0];
    return std::nullopt;
}

std::optional<Error> Parser::parse_param_multiple(std::vector<int>& bindings) {
    // One item of an array initializer: a constant, program.local[a] or [a..b], program.env[...],
    // state.matrix.mvp (4 rows) or state.matrix.mvp.row[i] / .row[a..b].
    if (at_constant()) {
        int b = 0;
        if (auto e = parse_param_single(b)) return e;
        bindings.push_back(b);
        return std::nullopt;
    }
    const std::size_t at = peek().offset;
    std::string root;
    if (auto e = expect_identifier(root)) return e;
    auto parse_range = [&](int& first, int& last) -> std::optional<Error> {
        if (auto e = expect("[")) return e;
        if (auto e = expect_integer(first)) return e;
        last = first;
        if (accept("..")) {
            if (auto e = expect_integer(last)) return e;
        }
        if (last < first) return error("a range [a..b] needs a <= b");
        return expect("]");
    };
    if (root == "program") {
        if (auto e = expect(".")) return e;
        std::string space;
        if (auto e = expect_identifier(space)) return e;
        if (space != "local" && space != "env") {
            return error_at(at, "program." + space + " is not a parameter (local or env)");
        }
        int first = 0, last = 0;
        if (auto e = parse_range(first, last)) return e;
        add_params(space == "local" ? ParamBinding::Kind::local : ParamBinding::Kind::env, first,
                   last, bindings);
        return std::nullopt;
    }
    if (root == "state") {
        std::string matrix, name;
        if (auto e = expect(".")) return e;
        if (auto e = expect_identifier(matrix)) return e;
        if (auto e = expect(".")) return e;
        if (auto e = expect_identifier(name)) return e;
        if (matrix != "matrix" || name != "mvp") {
            return error_at(at, "state." + matrix + "." + name +
                                    " is not supported by this interpreter (only "
                                    "state.matrix.mvp)");
        }
        int first = 0, last = 3;
        if (peek().text == "." && peek(1).text == "row") {
            next();
            next();
            if (auto e = parse_range(first, last)) return e;
            if (last > 3) return error_at(at, "a matrix has rows 0 to 3");
        } else if (peek().text == "." && peek(1).kind == Token::Kind::identifier &&
                   peek(1).text.find_first_not_of("xyzw") != std::string_view::npos) {
            return error_at(at, "state.matrix.mvp." + std::string(peek(1).text) +
                                    " is not supported by this interpreter");
        }
        add_params(ParamBinding::Kind::mvp_row, first, last, bindings);
        return std::nullopt;
    }
    return error_at(at,
                    "expected a parameter binding (program.local, program.env, state.matrix "
                    "or a constant), got '" +
                        root + "'");
}

std::optional<Error> Parser::parse_dest(Dest& dst) {
    const std::size_t at = peek().offset;
    std::string name;
    if (auto e = expect_identifier(name)) return e;
    if (name == "result") {
        int slot = 0;
        if (auto e = parse_result_binding(slot)) return e;
        dst.file = File::output;
        dst.index = slot;
    } else {
        auto it = symbols_.find(name);
        if (it == symbols_.end()) return error_at(at, "'" + name + "' is not declared");
        if (it->second.kind == Symbol::Kind::temp) {
            dst.file = File::temp;
        } else if (it->second.kind == Symbol::Kind::address) {
            dst.file = File::address;
        } else if (it->second.kind == Symbol::Kind::output) {
            dst.file = File::output;
        } else {
            return error_at(at, "'" + name + "' is read-only (only TEMP and OUTPUT are written)");
        }
        dst.index = it->second.index;
    }
    dst.mask = 0xf;
    if (accept(".")) {
        const std::size_t mask_at = peek().offset;
        const std::string_view m = peek().text;
        if (peek().kind != Token::Kind::identifier) return error("expected a write mask");
        next();
        // Components in xyzw order, each at most once.
        dst.mask = 0;
        int last = -1;
        for (char c : m) {
            const auto p = std::string_view("xyzw").find(c);
            if (p == std::string_view::npos || static_cast<int>(p) <= last) {
                return error_at(mask_at, "invalid write mask '." + std::string(m) +
                                             "' (components of xyzw, in that order)");
            }
            last = static_cast<int>(p);
            dst.mask |= 1u << p;
        }
    }
    return std::nullopt;
}

std::optional<Error> Parser::parse_register(Source& src) {
    const std::size_t at = peek().offset;
    if (peek().text == "{" || peek().kind == Token::Kind::number) {
        // Implicit constant; a bare scalar has no sign here (section 2.14.3.2).
        ParamBinding b;
        if (auto e = parse_constant(b)) return e;
        src.file = File::param;
        src.index = add_param(b);
        return std::nullopt;
    }
    std::string name;
    if (auto e = expect_identifier(name)) return e;
    if (name == "vertex") {
        src.file = File::attrib;
        return parse_attrib_binding(src.index);
    }
    if (name == "program" || name == "state") {
        --pos_;  // let the binding parser see the root word
        std::vector<int> bindings;
        if (auto e = parse_param_multiple(bindings)) return e;
        if (bindings.size() != 1) return error_at(at, "expected one parameter, got several");
        src.file = File::param;
        src.index = bindings[0];
        return std::nullopt;
    }
    if (name == "result") return error_at(at, "result registers are write-only");
    auto it = symbols_.find(name);
    if (it == symbols_.end()) return error_at(at, "'" + name + "' is not declared");
    const Symbol& s = it->second;
    switch (s.kind) {
        case Symbol::Kind::temp:
            src.file = File::temp;
            src.index = s.index;
            break;
        case Symbol::Kind::attrib:
            src.file = File::attrib;
            src.index = s.index;
            break;
        case Symbol::Kind::param:
            src.file = File::param;
            src.index = s.index;
            break;
        case Symbol::Kind::param_array: {
            int element = 0;
            if (auto e = expect("[")) return e;
            const std::size_t element_at = peek().offset;
            if (peek().kind == Token::Kind::identifier) {
                // Relative: array[A0.x], array[A0.x + n] or array[A0.x - n], n in [-64, 63].
                std::string address;
                if (auto e = expect_identifier(address)) return e;
                auto a = symbols_.find(address);
                if (a == symbols_.end() || a->second.kind != Symbol::Kind::address) {
                    return error_at(element_at, "'" + address + "' is not an ADDRESS register");
                }
                if (auto e = expect(".")) return e;
                if (auto e = expect("x")) return e;
                int offset = 0;
                const bool minus = peek().text == "-";
                if (accept("+") || accept("-")) {
                    if (auto e = expect_integer(offset)) return e;
                    if (minus) offset = -offset;
                }
                if (offset < -64 || offset > 63) {
                    return error_at(element_at, "a relative offset is in [-64, 63], got " +
                                                    std::to_string(offset));
                }
                if (auto e = expect("]")) return e;
                src.file = File::param;
                src.relative = true;
                src.array_first = s.index;
                src.array_size = s.size;
                src.index = s.index + offset;
                break;
            }
            if (auto e = expect_integer(element)) return e;
            if (auto e = expect("]")) return e;
            if (element >= s.size) {
                return error_at(element_at, "'" + name + "[" + std::to_string(element) +
                                                "]' is out of range (size " +
                                                std::to_string(s.size) + ")");
            }
            src.file = File::param;
            src.index = s.index + element;  // the array owns consecutive slots
            break;
        }
        case Symbol::Kind::output:
            return error_at(at, "'" + name + "' is an output: write-only");
        case Symbol::Kind::address:
            return error_at(at, "'" + name + "' is an address register: it only indexes arrays");
    }
    return std::nullopt;
}

std::optional<Error> Parser::parse_source(Source& src, bool scalar) {
    src.negate = accept_sign();
    if (auto e = parse_register(src)) return e;
    const std::size_t at = peek().offset;
    if (!accept(".")) {
        if (scalar) return error_at(at, "a scalar operand needs a component suffix (.x, .y, ...)");
        return std::nullopt;  // .xyzw
    }
    const std::string_view s = peek().text;
    if (peek().kind != Token::Kind::identifier || (s.size() != 1 && s.size() != 4) ||
        (scalar && s.size() != 1) || s.find_first_not_of("xyzw") != std::string_view::npos) {
        return error_at(at, scalar ? "expected a scalar suffix .x, .y, .z or .w"
                                   : "expected a swizzle of 1 or 4 components of xyzw");
    }
    next();
    for (int i = 0; i < 4; ++i) {
        const char c = s[s.size() == 1 ? 0 : static_cast<std::size_t>(i)];
        src.select[static_cast<std::size_t>(i)] =
            static_cast<std::uint8_t>(std::string_view("xyzw").find(c));
    }
    return std::nullopt;
}

std::optional<Error> Parser::parse_swz_source(Source& src) {
    // SWZ dst, register, c, c, c, c with c = [-] (0 | 1 | x | y | z | w).
    if (auto e = parse_register(src)) return e;
    for (int i = 0; i < 4; ++i) {
        if (auto e = expect(",")) return e;
        const bool negate = accept_sign();
        const std::string_view c = peek().text;
        std::uint8_t select = 0;
        if (c == "0") {
            select = kSelectZero;
        } else if (c == "1") {
            select = kSelectOne;
        } else if (c.size() == 1 && std::string_view("xyzw").find(c[0]) != std::string_view::npos) {
            select = static_cast<std::uint8_t>(std::string_view("xyzw").find(c[0]));
        } else {
            return error("an extended swizzle component is 0, 1, x, y, z or w, got '" +
                         std::string(c) + "'");
        }
        next();
        src.select[static_cast<std::size_t>(i)] = select;
        src.negate_component[static_cast<std::size_t>(i)] = negate;
    }
    return std::nullopt;
}

std::optional<Error> Parser::parse_instruction(const OpcodeInfo& info) {
    Instruction ins;
    ins.info = &info;
    if (auto e = parse_dest(ins.dst)) return e;
    int sources = 0;
    switch (info.form) {
        case Form::vector1:
        case Form::scalar1:
        case Form::swizzle:
        case Form::address:
            sources = 1;
            break;
        case Form::vector2:
        case Form::scalar2:
            sources = 2;
            break;
        case Form::vector3:
            sources = 3;
            break;
    }
    if ((info.form == Form::address) != (ins.dst.file == File::address) ||
        (ins.dst.file == File::address && ins.dst.mask != 1u)) {
        return error(info.form == Form::address
                         ? "ARL writes the x component of an ADDRESS register"
                         : "only ARL writes an ADDRESS register");
    }
    for (int i = 0; i < sources; ++i) {
        if (auto e = expect(",")) return e;
        Source& src = ins.src[static_cast<std::size_t>(i)];
        if (info.form == Form::swizzle) {
            if (auto e = parse_swz_source(src)) return e;
        } else {
            const bool scalar = info.form == Form::scalar1 || info.form == Form::scalar2 ||
                                info.form == Form::address;
            if (auto e = parse_source(src, scalar)) return e;
        }
    }
    data_.instructions.push_back(ins);
    return expect(";");
}

std::optional<Error> Parser::parse_statement() {
    const Token& t = peek();
    const std::size_t at = t.offset;
    if (t.kind != Token::Kind::identifier) {
        return error("expected an instruction or a declaration, got '" + std::string(t.text) + "'");
    }
    const std::string word(t.text);
    next();
    for (const OpcodeInfo& info : kOpcodes) {
        if (word == info.name) return parse_instruction(info);
    }
    if (word == "OPTION") {
        return error_at(at, "OPTION must come before every other statement");
    }
    if (word == "TEMP") {
        do {
            const std::size_t name_at = peek().offset;
            std::string name;
            if (auto e = expect_identifier(name)) return e;
            if (auto e = declare(name, name_at, {Symbol::Kind::temp, data_.temporaries, 1})) {
                return e;
            }
            ++data_.temporaries;
        } while (accept(","));
        return expect(";");
    }
    if (word == "ADDRESS") {
        // One address register (the spec's minimum MAX_PROGRAM_ADDRESS_REGISTERS).
        const std::size_t name_at = peek().offset;
        std::string name;
        if (auto e = expect_identifier(name)) return e;
        for (const auto& entry : symbols_) {
            if (entry.second.kind == Symbol::Kind::address) {
                return error_at(name_at, "this interpreter supports one ADDRESS register");
            }
        }
        if (auto e = declare(name, name_at, {Symbol::Kind::address, 0, 1})) return e;
        return expect(";");
    }
    if (word == "ATTRIB" || word == "OUTPUT" || word == "PARAM") {
        const std::size_t name_at = peek().offset;
        std::string name;
        if (auto e = expect_identifier(name)) return e;
        Symbol symbol;
        if (word == "PARAM" && accept("[")) {
            // PARAM name[n] = { item, item, ... }; n optional but must match.
            int declared = -1;
            if (peek().text != "]") {
                if (auto e = expect_integer(declared)) return e;
            }
            if (auto e = expect("]")) return e;
            if (auto e = expect("=")) return e;
            if (auto e = expect("{")) return e;
            std::vector<int> bindings;
            do {
                if (auto e = parse_param_multiple(bindings)) return e;
            } while (accept(","));
            if (auto e = expect("}")) return e;
            if (declared >= 0 && declared != static_cast<int>(bindings.size())) {
                return error_at(name_at, "'" + name + "' is declared with " +
                                             std::to_string(declared) + " elements but has " +
                                             std::to_string(bindings.size()));
            }
            // Arrays index a contiguous range of slots: append the array's own copies.
            symbol.kind = Symbol::Kind::param_array;
            symbol.size = static_cast<int>(bindings.size());
            symbol.index = static_cast<int>(data_.params.size());
            for (int b : bindings)
                data_.params.push_back(data_.params[static_cast<std::size_t>(b)]);
        } else {
            if (auto e = expect("=")) return e;
            if (word == "PARAM") {
                symbol.kind = Symbol::Kind::param;
                if (auto e = parse_param_single(symbol.index)) return e;
            } else if (word == "ATTRIB") {
                symbol.kind = Symbol::Kind::attrib;
                if (auto e = expect("vertex")) return e;
                if (auto e = parse_attrib_binding(symbol.index)) return e;
            } else {
                symbol.kind = Symbol::Kind::output;
                if (auto e = expect("result")) return e;
                if (auto e = parse_result_binding(symbol.index)) return e;
            }
        }
        if (auto e = declare(name, name_at, symbol)) return e;
        return expect(";");
    }
    return error_at(at, "'" + word +
                            "' is not an instruction or declaration this interpreter "
                            "supports");
}

Result<ParsedArbProgram> Parser::parse() {
    if (auto e = tokenize()) return *e;
    while (peek().text == "OPTION") {
        next();
        const std::size_t at = peek().offset;
        std::string option;
        if (auto e = expect_identifier(option)) return *e;
        if (option != "ARB_position_invariant") {
            return error_at(at, "OPTION " + option + " is not supported by this interpreter");
        }
        position_invariant_ = true;
        if (auto e = expect(";")) return *e;
    }
    while (!(peek().kind == Token::Kind::identifier && peek().text == "END")) {
        if (peek().kind == Token::Kind::end) return error("the program does not end with END");
        if (auto e = parse_statement()) return *e;
    }
    // Text after END is ignored, as GL implementations do.

    // Array parameters were appended as copies; count distinct bindings as the spec does.
    ArbResources r;
    r.instructions = static_cast<int>(data_.instructions.size());
    r.temporaries = data_.temporaries;
    std::vector<ParamBinding> distinct;
    for (const ParamBinding& p : data_.params) {
        const bool seen = std::any_of(distinct.begin(), distinct.end(),
                                      [&](const ParamBinding& q) { return same_binding(q, p); });
        if (!seen) distinct.push_back(p);
    }
    r.parameters = static_cast<int>(distinct.size());
    r.attributes = static_cast<int>(attributes_.size());

    ParsedArbProgram program;
    program.data = std::make_shared<const ArbCpuProgramData>(std::move(data_));
    program.resources = r;
    program.position_invariant = position_invariant_;
    return program;
}

}  // namespace

Result<ParsedArbProgram> parse_arb_text(std::string_view function, std::string_view text) {
    return Parser(function, text).parse();
}

}  // namespace aerial::detail
