// CPU executor of ARB vertex programs (parsed by aerial::gl's parser, module/src/gl/
// arb_parser.cpp): float arithmetic that follows the pseudo-code of the spec
// (ARB_vertex_program, section 2.14.5), with optional perturbation of the approximate
// instructions.
#include "aerial/validation/arb_executor.hpp"

#include <cmath>
#include <cstdint>
#include <utility>

#include "gl/arb_parser.hpp"

namespace aerial::validation {

using namespace aerial::detail;

static_assert(kArbApproxEx2 == kArbApproxBitEx2 && kArbApproxLg2 == kArbApproxBitLg2 &&
                  kArbApproxExp == kArbApproxBitExp && kArbApproxLog == kArbApproxBitLog &&
                  kArbApproxRcp == kArbApproxBitRcp && kArbApproxRsq == kArbApproxBitRsq &&
                  kArbApproxPow == kArbApproxBitPow,
              "the executor's approximation bits are the parser's");

namespace {

struct Machine {
    int address = 0;  ///< A0.x
    std::vector<Vec4> temps;
    std::vector<Vec4> params;
    std::array<Vec4, 1 + kArbMaxTexcoordUnits> attribs;
    std::array<ArbOutput, kOutputCount> outputs;
};

const Vec4& fetch(const Machine& m, File file, int index) {
    switch (file) {
        case File::address:
            break;
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

/// The register a source reads: array[A0.x + n] resolved, undefined outside the array (as the
/// spec leaves it).
const Vec4& source_register(const Machine& m, const Source& s) {
    if (!s.relative) return fetch(m, s.file, s.index);
    const int slot = s.index + m.address;
    if (slot < s.array_first || slot >= s.array_first + s.array_size) return kUndefined;
    return fetch(m, s.file, slot);
}

Vec4 vector_load(const Machine& m, const Source& s) {
    const Vec4& r = source_register(m, s);
    Vec4 v;
    for (std::size_t i = 0; i < 4; ++i) {
        const float x = r[s.select[i]];
        v[i] = s.negate ? -x : x;
    }
    return v;
}

float scalar_load(const Machine& m, const Source& s) {
    const float x = source_register(m, s)[s.select[0]];
    return s.negate ? -x : x;
}

Vec4 splat(float x) { return {x, x, x, x}; }

}  // namespace

Result<ArbCpuProgram> parse_arb_program(std::string_view text) {
    auto parsed = detail::parse_arb_text("validation::parse_arb_program", text);
    if (!parsed) return parsed.error();
    ArbCpuProgram program;
    program.data = std::move(parsed->data);
    program.resources = parsed->resources;
    program.position_invariant = parsed->position_invariant;
    return program;
}

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
                const Vec4 a = source_register(m, src[0]);
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
            case Opcode::flr:
            case Opcode::frc: {
                const Vec4 a = vector_load(m, src[0]);
                for (std::size_t i = 0; i < 4; ++i) {
                    const float f = std::floor(a[i]);
                    r[i] = ins.info->opcode == Opcode::flr ? f : a[i] - f;
                }
                break;
            }
            case Opcode::arl: {
                // floor(x); out of int range (or NaN) it indexes nothing: every read undefined.
                const float f = std::floor(scalar_load(m, src[0]));
                m.address = f > -1e6f && f < 1e6f ? static_cast<int>(f) : 1 << 30;
                continue;
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

}  // namespace aerial::validation
