// The ARB vertex program parser's output (not installed): the instructions and bindings of a
// program, shared by the generator (aerial::gl counts a generated program's resources with the
// parser) and by the CPU executor of aerial::validation (validation/src/arb_executor.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string_view>
#include <vector>

#include "aerial/arb_program.hpp"
#include "aerial/error.hpp"

namespace aerial::detail {

/// Bits of the approximate instructions (the values of aerial::validation::ArbApprox).
inline constexpr unsigned kArbApproxBitEx2 = 1u << 0;
inline constexpr unsigned kArbApproxBitLg2 = 1u << 1;
inline constexpr unsigned kArbApproxBitExp = 1u << 2;
inline constexpr unsigned kArbApproxBitLog = 1u << 3;
inline constexpr unsigned kArbApproxBitRcp = 1u << 4;
inline constexpr unsigned kArbApproxBitRsq = 1u << 5;
inline constexpr unsigned kArbApproxBitPow = 1u << 6;

using Vec4 = std::array<float, 4>;

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr Vec4 kUndefined{kNaN, kNaN, kNaN, kNaN};

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
    pow,
    flr,
    frc,
    arl
};

/// How an instruction's operands are written.
enum class Form {
    vector1,  ///< OP dst, vector
    vector2,  ///< OP dst, vector, vector
    vector3,  ///< OP dst, vector, vector, vector
    scalar1,  ///< OP dst, scalar
    scalar2,  ///< OP dst, scalar, scalar
    swizzle,  ///< SWZ dst, register, c, c, c, c
    address,  ///< ARL address.x, scalar
};

struct OpcodeInfo {
    const char* name;
    Opcode opcode;
    Form form;
    unsigned approx;  ///< kArbApproxBit*, 0 for exact instructions
};

enum class File : std::uint8_t { temp, attrib, param, output, address };

// Attribute slots: 0 = vertex.position, 1 + n = vertex.texcoord[n].
inline constexpr int kAttribPosition = 0;
inline constexpr int kAttribTexcoord0 = 1;
// Output slots.
inline constexpr int kOutPosition = 0;
inline constexpr int kOutPrimary = 1;
inline constexpr int kOutSecondary = 2;
inline constexpr int kOutFog = 3;
inline constexpr int kOutTexcoord0 = 4;
inline constexpr int kOutputCount = kOutTexcoord0 + kArbMaxTexcoordUnits;

/// Swizzle selectors of SWZ beyond the four components.
inline constexpr std::uint8_t kSelectZero = 4;
inline constexpr std::uint8_t kSelectOne = 5;

struct ParamBinding {
    enum class Kind { local, env, mvp_row, constant } kind = Kind::constant;
    int index = 0;  ///< local/env index or matrix row
    Vec4 value{};   ///< constants
};

struct Source {
    File file = File::temp;
    int index = 0;  ///< relative: the array's first slot plus the offset
    /// array[A0.x + offset]: the slot is index + A0.x, valid within [first, first + size).
    bool relative = false;
    int array_first = 0, array_size = 0;
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

struct ArbCpuProgramData {
    std::vector<Instruction> instructions;
    std::vector<ParamBinding> params;
    int temporaries = 0;
};

/// A parsed program: its instructions and what it uses, counted as the spec counts it.
struct ParsedArbProgram {
    std::shared_ptr<const ArbCpuProgramData> data;
    ArbResources resources;
    bool position_invariant = false;
};

/// Parses program text (the subset aerial::validation::parse_arb_program documents) for the
/// public function `function` ("validation::parse_arb_program"). Errors: field "line N", message
/// "aerial::FUNCTION(): line N: column C: what is wrong".
Result<ParsedArbProgram> parse_arb_text(std::string_view function, std::string_view text);

}  // namespace aerial::detail
