// CPU interpreter of ARB vertex programs: the subset generate_arb_program emits plus the other
// scalar instructions. A tokenizer, a parser that resolves every name to a register slot while
// loading (as GL does), and an executor in float that follows the pseudo-code of the spec
// (ARB_vertex_program, section 2.14.5), with optional perturbation of the approximate
// instructions.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <system_error>

#include "aerial/arb_program.hpp"

namespace aerial {

using Vec4 = std::array<float, 4>;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr Vec4 kUndefined{kNaN, kNaN, kNaN, kNaN};

enum class Opcode {
    mov,
    add,
    sub,
    mul,
    mad,
    dp3,
    dp4,
    dph,
    min,
    max,
    sge,
    slt,
    swz,
    ex2,
    lg2,
    exp,
    log,
    rcp,
    rsq,
    pow
};

/// How an instruction's operands are written.
enum class Form {
    vector1,  ///< OP dst, vector
    vector2,  ///< OP dst, vector, vector
    vector3,  ///< OP dst, vector, vector, vector
    scalar1,  ///< OP dst, scalar
    scalar2,  ///< OP dst, scalar, scalar
    swizzle,  ///< SWZ dst, register, c, c, c, c
};

struct OpcodeInfo {
    const char* name;
    Opcode opcode;
    Form form;
    unsigned approx;  ///< ArbApprox bit, 0 for exact instructions
};

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
    {"EX2", Opcode::ex2, Form::scalar1, kArbApproxEx2},
    {"LG2", Opcode::lg2, Form::scalar1, kArbApproxLg2},
    {"EXP", Opcode::exp, Form::scalar1, kArbApproxExp},
    {"LOG", Opcode::log, Form::scalar1, kArbApproxLog},
    {"RCP", Opcode::rcp, Form::scalar1, kArbApproxRcp},
    {"RSQ", Opcode::rsq, Form::scalar1, kArbApproxRsq},
    {"POW", Opcode::pow, Form::scalar2, kArbApproxPow},
};

/// Keywords of the language (spec section 2.14.2) that may not name a variable.
constexpr const char* kReserved[] = {
    "ABS", "ADD", "ADDRESS", "ALIAS",  "ARL",    "ATTRIB",  "DP3",    "DP4",   "DPH",    "DST",
    "END", "EX2", "EXP",     "FLR",    "FRC",    "LG2",     "LIT",    "LOG",   "MAD",    "MAX",
    "MIN", "MOV", "MUL",     "OPTION", "OUTPUT", "PARAM",   "POW",    "RCP",   "RSQ",    "SGE",
    "SLT", "SUB", "SWZ",     "TEMP",   "XPD",    "program", "result", "state", "vertex",
};

enum class File : std::uint8_t { temp, attrib, param, output };

// Attribute slots: 0 = vertex.position, 1 + n = vertex.texcoord[n].
constexpr int kAttribPosition = 0;
constexpr int kAttribTexcoord0 = 1;
// Output slots.
constexpr int kOutPosition = 0;
constexpr int kOutPrimary = 1;
constexpr int kOutSecondary = 2;
constexpr int kOutFog = 3;
constexpr int kOutTexcoord0 = 4;
constexpr int kOutputCount = kOutTexcoord0 + kArbMaxTexcoordUnits;

/// Swizzle selectors of SWZ beyond the four components.
constexpr std::uint8_t kSelectZero = 4;
constexpr std::uint8_t kSelectOne = 5;

struct ParamBinding {
    enum class Kind { local, env, mvp_row, constant } kind = Kind::constant;
    int index = 0;  ///< local/env index or matrix row
    Vec4 value{};   ///< constants
};

struct Source {
    File file = File::temp;
    int index = 0;
    std::array<std::uint8_t, 4> select{0, 1, 2, 3};
    bool negate = false;
    std::array<bool, 4> negate_component{};  ///< SWZ only
};

struct Dest {
    File file = File::temp;
    int index = 0;
    unsigned mask = 0xf;
};

struct Instruction {
    const OpcodeInfo* info = nullptr;
    Dest dst;
    std::array<Source, 3> src;
};

}  // namespace

struct ArbCpuProgramData {
    std::vector<Instruction> instructions;
    std::vector<ParamBinding> params;
    int temporaries = 0;
};

namespace {

// ---- Tokens ----------------------------------------------------------------------------------

struct Token {
    enum class Kind { identifier, number, punct, end } kind = Kind::end;
    std::string_view text;
    std::size_t offset = 0;
};

bool is_identifier_start(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == '$';
}
bool is_digit(char c) { return c >= '0' && c <= '9'; }

class Parser {
  public:
    explicit Parser(std::string_view text) : text_(text) {}

    Result<ArbCpuProgram> parse();

  private:
    struct Symbol {
        enum class Kind { temp, attrib, param, param_array, output } kind = Kind::temp;
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

    // Errors carry the line and column of the offending token.
    Error error_at(std::size_t offset, const std::string& what) const;
    Error error(const std::string& what) const { return error_at(peek().offset, what); }
    std::optional<Error> expect(std::string_view text);
    std::optional<Error> expect_identifier(std::string& out);
    std::optional<Error> expect_integer(int& out);
    std::optional<Error> parse_signed_float(float& out);
    std::optional<Error> parse_constant_vector(Vec4& out);

    // Declarations.
    std::optional<Error> declare(const std::string& name, std::size_t offset, Symbol symbol);
    std::optional<Error> parse_attrib_binding(int& slot);
    std::optional<Error> parse_texcoord_unit(const char* binding, std::size_t at, int& unit);
    std::optional<Error> parse_result_binding(int& slot);
    std::optional<Error> parse_param_single(int& binding);
    std::optional<Error> parse_param_multiple(std::vector<int>& bindings);
    int add_param(const ParamBinding& b);

    // Statements.
    std::optional<Error> parse_statement();
    std::optional<Error> parse_instruction(const OpcodeInfo& info);
    std::optional<Error> parse_dest(Dest& dst);
    std::optional<Error> parse_register(Source& src);
    std::optional<Error> parse_source(Source& src, bool scalar);
    std::optional<Error> parse_swz_source(Source& src);

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
    const std::string field = "line " + std::to_string(line);
    return Error{field,
                 field + ", column " + std::to_string(offset - line_start + 1) + ": " + what};
}

std::optional<Error> Parser::tokenize() {
    constexpr std::string_view kHeader = "!!ARBvp1.0";
    if (text_.substr(0, kHeader.size()) != kHeader) {
        return error_at(0, "a vertex program must start with \"!!ARBvp1.0\"");
    }
    std::size_t i = kHeader.size();
    const std::size_t n = text_.size();
    while (i < n) {
        const char c = text_[i];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
            ++i;
        } else if (c == '#') {
            while (i < n && text_[i] != '\n' && text_[i] != '\r') ++i;
        } else if (is_identifier_start(c)) {
            const std::size_t start = i;
            while (i < n && (is_identifier_start(text_[i]) || is_digit(text_[i]))) ++i;
            tokens_.push_back({Token::Kind::identifier, text_.substr(start, i - start), start});
        } else if (is_digit(c) || (c == '.' && i + 1 < n && is_digit(text_[i + 1]))) {
            const std::size_t start = i;
            while (i < n && is_digit(text_[i])) ++i;
            // A fraction, but not the ".." of a range nor the "." of a swizzle.
            if (i < n && text_[i] == '.' && !(i + 1 < n && text_[i + 1] == '.') &&
                !(i + 1 < n && is_identifier_start(text_[i + 1]))) {
                ++i;
                while (i < n && is_digit(text_[i])) ++i;
            }
            if (i < n && (text_[i] == 'e' || text_[i] == 'E')) {
                std::size_t j = i + 1;
                if (j < n && (text_[j] == '+' || text_[j] == '-')) ++j;
                if (j < n && is_digit(text_[j])) {
                    i = j;
                    while (i < n && is_digit(text_[i])) ++i;
                }
            }
            tokens_.push_back({Token::Kind::number, text_.substr(start, i - start), start});
        } else if (c == '.' && i + 1 < n && text_[i + 1] == '.') {
            tokens_.push_back({Token::Kind::punct, text_.substr(i, 2), i});
            i += 2;
        } else if (std::string_view(";,.[]{}=-+").find(c) != std::string_view::npos) {
            tokens_.push_back({Token::Kind::punct, text_.substr(i, 1), i});
            ++i;
        } else {
            return error_at(i, std::string("unexpected character '") + c + "'");
        }
    }
    tokens_.push_back({Token::Kind::end, std::string_view{}, n});
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
    bool negative = false;
    if (accept("-")) {
        negative = true;
    } else {
        accept("+");
    }
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
    // Bindings of the same state or the same constant vector count once (section 2.14.3.7).
    for (std::size_t i = 0; i < data_.params.size(); ++i) {
        const ParamBinding& p = data_.params[i];
        if (p.kind != b.kind) continue;
        if (b.kind == ParamBinding::Kind::constant ? p.value == b.value : p.index == b.index) {
            return static_cast<int>(i);
        }
    }
    data_.params.push_back(b);
    return static_cast<int>(data_.params.size() - 1);
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
    if (peek().text == "{" || peek().kind == Token::Kind::number || peek().text == "-" ||
        peek().text == "+") {
        ParamBinding b;
        if (peek().text == "{") {
            if (auto e = parse_constant_vector(b.value)) return e;
        } else {
            float x = 0.0f;
            if (auto e = parse_signed_float(x)) return e;
            b.value = {x, x, x, x};
        }
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
    if (peek().text == "{" || peek().kind == Token::Kind::number || peek().text == "-" ||
        peek().text == "+") {
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
        for (int i = first; i <= last; ++i) {
            ParamBinding b;
            b.kind = space == "local" ? ParamBinding::Kind::local : ParamBinding::Kind::env;
            b.index = i;
            bindings.push_back(add_param(b));
        }
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
        for (int r = first; r <= last; ++r) {
            ParamBinding b;
            b.kind = ParamBinding::Kind::mvp_row;
            b.index = r;
            bindings.push_back(add_param(b));
        }
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
        if (peek().text == "{") {
            if (auto e = parse_constant_vector(b.value)) return e;
        } else {
            float x = 0.0f;
            if (auto e = parse_signed_float(x)) return e;
            b.value = {x, x, x, x};
        }
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
    }
    return std::nullopt;
}

std::optional<Error> Parser::parse_source(Source& src, bool scalar) {
    if (accept("-")) {
        src.negate = true;
    } else {
        accept("+");
    }
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
        bool negate = false;
        if (accept("-")) {
            negate = true;
        } else {
            accept("+");
        }
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
    for (int i = 0; i < sources; ++i) {
        if (auto e = expect(",")) return e;
        Source& src = ins.src[static_cast<std::size_t>(i)];
        if (info.form == Form::swizzle) {
            if (auto e = parse_swz_source(src)) return e;
        } else {
            const bool scalar = info.form == Form::scalar1 || info.form == Form::scalar2;
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

Result<ArbCpuProgram> Parser::parse() {
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
        const bool seen = std::any_of(distinct.begin(), distinct.end(), [&](const ParamBinding& q) {
            return q.kind == p.kind &&
                   (p.kind == ParamBinding::Kind::constant ? q.value == p.value
                                                           : q.index == p.index);
        });
        if (!seen) distinct.push_back(p);
    }
    r.parameters = static_cast<int>(distinct.size());
    r.attributes = static_cast<int>(attributes_.size());

    ArbCpuProgram program;
    program.data = std::make_shared<const ArbCpuProgramData>(std::move(data_));
    program.resources = r;
    program.position_invariant = position_invariant_;
    return program;
}

// ---- Execution -------------------------------------------------------------------------------

struct Machine {
    std::vector<Vec4> temps;
    std::vector<Vec4> params;
    std::array<Vec4, 1 + kArbMaxTexcoordUnits> attribs;
    std::array<ArbOutput, kOutputCount> outputs;
};

const Vec4& fetch(const Machine& m, File file, int index) {
    switch (file) {
        case File::temp:
            return m.temps[static_cast<std::size_t>(index)];
        case File::attrib:
            return m.attribs[static_cast<std::size_t>(index)];
        case File::param:
            return m.params[static_cast<std::size_t>(index)];
        case File::output:
            break;
    }
    return kUndefined;  // outputs are write-only; the parser never produces this
}

Vec4 vector_load(const Machine& m, const Source& s) {
    const Vec4& r = fetch(m, s.file, s.index);
    Vec4 v;
    for (std::size_t i = 0; i < 4; ++i) {
        const float x = r[s.select[i]];
        v[i] = s.negate ? -x : x;
    }
    return v;
}

float scalar_load(const Machine& m, const Source& s) {
    const float x = fetch(m, s.file, s.index)[s.select[0]];
    return s.negate ? -x : x;
}

Vec4 splat(float x) { return {x, x, x, x}; }

}  // namespace

Result<ArbCpuProgram> parse_arb_program(std::string_view text) { return Parser(text).parse(); }

int count_approximate_instructions(const ArbCpuProgram& program, unsigned perturbed) {
    if (!program.data) return 0;
    int n = 0;
    for (const Instruction& ins : program.data->instructions) {
        if (ins.info->approx & perturbed) ++n;
    }
    return n;
}

ArbResults run_arb_program(const ArbCpuProgram& program, const ArbMachine& machine,
                           const ArbVertex& vertex, const ArbInterpreterOptions& options) {
    ArbResults results;
    const auto undefined_output = [] {
        ArbOutput o;
        o.value = kUndefined;
        return o;
    };
    if (!program.data) {
        results.position = results.color_primary = results.color_secondary = results.fogcoord =
            undefined_output();
        results.texcoord.fill(undefined_output());
        return results;
    }
    const ArbCpuProgramData& d = *program.data;
    Machine m;
    m.temps.assign(static_cast<std::size_t>(d.temporaries), kUndefined);
    m.params.resize(d.params.size());
    for (std::size_t i = 0; i < d.params.size(); ++i) {
        const ParamBinding& p = d.params[i];
        const auto from = [&](const std::vector<Vec4>& v) {
            return p.index >= 0 && static_cast<std::size_t>(p.index) < v.size()
                       ? v[static_cast<std::size_t>(p.index)]
                       : kUndefined;
        };
        switch (p.kind) {
            case ParamBinding::Kind::local:
                m.params[i] = from(machine.local);
                break;
            case ParamBinding::Kind::env:
                m.params[i] = from(machine.env);
                break;
            case ParamBinding::Kind::mvp_row:
                m.params[i] = machine.mvp[static_cast<std::size_t>(p.index)];
                break;
            case ParamBinding::Kind::constant:
                m.params[i] = p.value;
                break;
        }
    }
    m.attribs[kAttribPosition] = vertex.position;
    for (int u = 0; u < kArbMaxTexcoordUnits; ++u) {
        m.attribs[static_cast<std::size_t>(kAttribTexcoord0 + u)] =
            vertex.texcoord[static_cast<std::size_t>(u)];
    }
    m.outputs.fill(undefined_output());

    int approx_index = 0;
    // The factor of the next approximate instruction of kind `bit`.
    const auto perturbation = [&](unsigned bit) {
        if (!(options.perturbed & bit) || options.relative_error == 0.0f) return 0.0f;
        const bool up = (options.sign_pattern >> (approx_index++ % 32)) & 1u;
        return up ? options.relative_error : -options.relative_error;
    };

    for (const Instruction& ins : d.instructions) {
        Vec4 r{};
        const auto& src = ins.src;
        switch (ins.info->opcode) {
            case Opcode::mov:
                r = vector_load(m, src[0]);
                break;
            case Opcode::add:
            case Opcode::sub:
            case Opcode::mul:
            case Opcode::min:
            case Opcode::max:
            case Opcode::sge:
            case Opcode::slt: {
                const Vec4 a = vector_load(m, src[0]), b = vector_load(m, src[1]);
                for (std::size_t i = 0; i < 4; ++i) {
                    switch (ins.info->opcode) {
                        case Opcode::add:
                            r[i] = a[i] + b[i];
                            break;
                        case Opcode::sub:
                            r[i] = a[i] - b[i];
                            break;
                        case Opcode::mul:
                            r[i] = a[i] * b[i];
                            break;
                        case Opcode::min:
                            r[i] = a[i] > b[i] ? b[i] : a[i];
                            break;
                        case Opcode::sge:
                            r[i] = a[i] >= b[i] ? 1.0f : 0.0f;
                            break;
                        case Opcode::slt:
                            r[i] = a[i] < b[i] ? 1.0f : 0.0f;
                            break;
                        default:
                            r[i] = a[i] > b[i] ? a[i] : b[i];
                            break;
                    }
                }
                break;
            }
            case Opcode::mad: {
                const Vec4 a = vector_load(m, src[0]), b = vector_load(m, src[1]),
                           c = vector_load(m, src[2]);
                for (std::size_t i = 0; i < 4; ++i) {
                    const float product = a[i] * b[i];  // rounded, then added (no fused MAD)
                    r[i] = product + c[i];
                }
                break;
            }
            case Opcode::dp3:
            case Opcode::dp4:
            case Opcode::dph: {
                const Vec4 a = vector_load(m, src[0]), b = vector_load(m, src[1]);
                float dot = a[0] * b[0];
                dot = dot + a[1] * b[1];
                dot = dot + a[2] * b[2];
                if (ins.info->opcode == Opcode::dp4) dot = dot + a[3] * b[3];
                if (ins.info->opcode == Opcode::dph) dot = dot + b[3];
                r = splat(dot);
                break;
            }
            case Opcode::swz: {
                const Vec4 a = fetch(m, src[0].file, src[0].index);
                for (std::size_t i = 0; i < 4; ++i) {
                    const std::uint8_t s = src[0].select[i];
                    const float x = s == kSelectZero ? 0.0f : s == kSelectOne ? 1.0f : a[s];
                    r[i] = src[0].negate_component[i] ? -x : x;
                }
                break;
            }
            case Opcode::ex2: {
                const float x = scalar_load(m, src[0]);
                r = splat(std::exp2(x) * (1.0f + perturbation(kArbApproxEx2)));
                break;
            }
            case Opcode::lg2: {
                // The spec states log errors in absolute terms (log2 units): add the amount.
                const float x = scalar_load(m, src[0]);
                r = splat(std::log2(x) + perturbation(kArbApproxLg2));
                break;
            }
            case Opcode::exp: {
                const float x = scalar_load(m, src[0]);
                const float floor_x = std::floor(x);
                r = {std::exp2(floor_x), x - floor_x,
                     std::exp2(x) * (1.0f + perturbation(kArbApproxExp)), 1.0f};
                break;
            }
            case Opcode::log: {
                const float x = std::fabs(scalar_load(m, src[0]));
                int e = 0;
                const float mantissa = std::frexp(x, &e);  // x = mantissa 2^e, mantissa in [0.5, 1)
                r = {x > 0.0f && std::isfinite(x) ? static_cast<float>(e - 1) : std::log2(x),
                     2.0f * mantissa, std::log2(x) + perturbation(kArbApproxLog), 1.0f};
                break;
            }
            case Opcode::rcp: {
                const float x = scalar_load(m, src[0]);
                r = splat(1.0f / x * (1.0f + perturbation(kArbApproxRcp)));
                break;
            }
            case Opcode::rsq: {
                const float x = std::fabs(scalar_load(m, src[0]));
                r = splat(1.0f / std::sqrt(x) * (1.0f + perturbation(kArbApproxRsq)));
                break;
            }
            case Opcode::pow: {
                const float a = scalar_load(m, src[0]), b = scalar_load(m, src[1]);
                r = splat(std::pow(a, b) * (1.0f + perturbation(kArbApproxPow)));
                break;
            }
        }
        if (ins.dst.file == File::temp) {
            Vec4& t = m.temps[static_cast<std::size_t>(ins.dst.index)];
            for (std::size_t i = 0; i < 4; ++i) {
                if (ins.dst.mask & (1u << i)) t[i] = r[i];
            }
        } else {
            ArbOutput& o = m.outputs[static_cast<std::size_t>(ins.dst.index)];
            for (std::size_t i = 0; i < 4; ++i) {
                if (ins.dst.mask & (1u << i)) o.value[i] = r[i];
            }
            o.written |= ins.dst.mask;
        }
    }

    results.position = m.outputs[kOutPosition];
    results.color_primary = m.outputs[kOutPrimary];
    results.color_secondary = m.outputs[kOutSecondary];
    results.fogcoord = m.outputs[kOutFog];
    for (int u = 0; u < kArbMaxTexcoordUnits; ++u) {
        results.texcoord[static_cast<std::size_t>(u)] =
            m.outputs[static_cast<std::size_t>(kOutTexcoord0 + u)];
    }
    return results;
}

}  // namespace aerial
