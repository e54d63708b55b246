// The ARB vertex program of the hoffman-preetham model: its size, its resources and limits, its
// parameter layout, its options (local/env, texcoords, position invariance), and its output run
// on the CPU interpreter against aerial::scatter, exactly and with old-hardware precision.
// The longest grids run in part under AERIAL_TEST_SCALE (test_scale.hpp).
#include <sys/wait.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/validation/arb_executor.hpp"
#include "test_scale.hpp"

namespace {

using aerial::ArbProgramOptions;
using aerial::Atmosphere;
using aerial::Display;
using aerial::Frame;
using aerial::Model;
using aerial::View;
using aerial::validation::ArbResults;
using Params = std::vector<std::array<float, 4>>;

constexpr double kDegree = aerial::kPi / 180.0;
/// The precision the spec promises for EXP/LOG, applied to every approximate instruction.
constexpr float kOldHardwareError = 1.0f / 2048.0f;
/// The 2002 demo's program.
constexpr int kOriginalInstructionCount = 33;
constexpr int kTargetInstructionCount = 24;

aerial::ArbProgram generate(const ArbProgramOptions& options = {}) {
    auto p = aerial::generate_arb_program(options);
    EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().message);
    return p.ok() ? *p : aerial::ArbProgram{};
}

aerial::validation::ArbCpuProgram parse(const std::string& text) {
    auto p = aerial::validation::parse_arb_program(text);
    EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().message) << "\n" << text;
    return p.ok() ? *p : aerial::validation::ArbCpuProgram{};
}

Atmosphere preset(const std::string& name) {
    auto a = aerial::atmosphere_preset(name);
    EXPECT_TRUE(a.ok()) << name;
    return a.ok() ? *a : Atmosphere{};
}

glm::dvec3 direction(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

Frame<float> frame_for(const Atmosphere& atmosphere, const glm::dvec3& eye, const glm::dvec3& sun,
                       double meters_per_unit = 1.0) {
    View view;
    view.eye = eye;
    view.sun_dir = glm::normalize(sun);
    view.meters_per_unit = meters_per_unit;
    auto f = aerial::prepare_frame<float>(atmosphere, view, Model::hoffman_preetham);
    EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().message);
    return f.ok() ? *f : Frame<float>{};
}

Params parameters(const Frame<float>& frame, float exposure, const ArbProgramOptions& o = {}) {
    Display display;
    display.exposure = exposure;
    auto p = aerial::arb_program_parameters(frame, display, o);
    EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.error().message);
    return p.ok() ? *p : Params(aerial::kArbParameterCount);
}

/// A machine holding exactly the parameters at their indices; every other index is unset.
aerial::validation::ArbMachine machine_with(const Params& params, const ArbProgramOptions& o = {}) {
    aerial::validation::ArbMachine m;
    auto& space = o.parameter_space == aerial::ParameterSpace::local ? m.local : m.env;
    const float nan = std::nanf("");
    space.assign(static_cast<std::size_t>(o.parameter_base), {nan, nan, nan, nan});
    space.insert(space.end(), params.begin(), params.end());
    return m;
}

aerial::validation::ArbVertex vertex_at(const glm::vec3& p) {
    aerial::validation::ArbVertex v;
    v.position = {p.x, p.y, p.z, 1.0f};
    return v;
}

int lsb_difference(float a, float b) {
    return std::abs(int(aerial::to_unorm8(a)) - int(aerial::to_unorm8(b)));
}

bool all_finite(const std::array<float, 4>& v, unsigned mask = 0xf) {
    for (int i = 0; i < 4; ++i) {
        if ((mask >> i) & 1u && !std::isfinite(v[static_cast<std::size_t>(i)])) return false;
    }
    return true;
}

/// Directions to probe from an eye: a spread of azimuths and elevations, plus the sun itself,
/// its close neighbourhood (the Mie peak) and the anti-sun.
std::vector<glm::dvec3> view_directions(const glm::dvec3& sun, int azimuths) {
    std::vector<glm::dvec3> dirs;
    for (int a = 0; a < azimuths; ++a) {
        for (double e : {-45.0, -10.0, -2.0, 0.0, 2.0, 10.0, 45.0, 89.0}) {
            dirs.push_back(direction(e, 360.0 * a / azimuths + 7.0));
        }
    }
    const glm::dvec3 side = glm::normalize(
        glm::cross(sun, std::abs(sun.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
    for (double off : {0.0, 0.3, 1.0, 3.0, 10.0, 30.0, 90.0, 180.0}) {
        dirs.push_back(std::cos(off * kDegree) * sun + std::sin(off * kDegree) * side);
    }
    return dirs;
}

const std::vector<double> kDistancesM{1, 3, 10, 30, 100, 300, 1e3, 3e3, 1e4, 3e4, 5e4};

/// Display L_in at infinity in the direction of `dir`: exposure E_sun beta_sc(theta) / beta_ex,
/// the largest value L_in approaches along that ray (before clamping).
double asymptotic_display(const Frame<float>& f, float exposure, const glm::dvec3& dir, int c) {
    const double cos_theta = glm::dot(dir, f.view.sun_dir);
    const double beta_ex = double(f.rayleigh_scattering[c]) + double(f.mie_extinction[c]);
    if (beta_ex <= 0.0) return 0.0;
    return exposure * f.sun_irradiance_eye[c] *
           (f.rayleigh_scattering[c] * aerial::rayleigh_phase(cos_theta) +
            f.mie_scattering[c] * aerial::henyey_greenstein_phase(cos_theta, double(f.mie_g))) /
           beta_ex;
}

struct Parity {
    int max_fex_lsb = 0;
    int max_lin_lsb = 0;
    double max_raw_lsb = 0.0;  ///< before rounding to 8 bits, after clamping to [0, 1]
    long vertices = 0;
    long off_by_one = 0;
    std::string worst;
};

/// Compares the program with aerial::scatter at one vertex and records the worst case.
void compare(const ArbResults& r, const Frame<float>& f, float exposure, const glm::vec3& p,
             Parity& parity, const std::string& where) {
    const aerial::Scattering<float> cpu = aerial::scatter(f, p);
    Display display;
    display.exposure = exposure;
    ++parity.vertices;
    bool any = false;
    for (int c = 0; c < 3; ++c) {
        const std::size_t i = static_cast<std::size_t>(c);
        const int fex = lsb_difference(r.color_primary.value[i], cpu.extinction[c]);
        const int lin = lsb_difference(r.color_secondary.value[i],
                                       aerial::display_value(display, cpu.in_scattering[c]));
        any = any || fex > 0 || lin > 0;
        const auto clamp01 = [](float x) { return std::clamp(x, 0.0f, 1.0f); };
        parity.max_raw_lsb =
            std::max({parity.max_raw_lsb,
                      255.0 * std::abs(clamp01(r.color_primary.value[i]) - cpu.extinction[c]),
                      255.0 * std::abs(clamp01(r.color_secondary.value[i]) -
                                       aerial::display_value(display, cpu.in_scattering[c]))});
        if (std::max(fex, lin) > std::max(parity.max_fex_lsb, parity.max_lin_lsb)) {
            parity.worst = where + " channel " + std::to_string(c) +
                           ": F_ex arb=" + std::to_string(r.color_primary.value[i]) +
                           " cpu=" + std::to_string(cpu.extinction[c]) +
                           ", L_in arb=" + std::to_string(r.color_secondary.value[i]) + " cpu=" +
                           std::to_string(aerial::display_value(display, cpu.in_scattering[c]));
        }
        parity.max_fex_lsb = std::max(parity.max_fex_lsb, fex);
        parity.max_lin_lsb = std::max(parity.max_lin_lsb, lin);
    }
    if (any) ++parity.off_by_one;
}

// ---- The program text ------------------------------------------------------------------------

TEST(ArbProgram, DefaultProgramFitsTheInstructionTarget) {
    const aerial::ArbProgram program = generate();
    std::printf(
        "[ info     ] default program: %d instructions (target <= %d, 2002 original %d), "
        "%d temporaries, %d parameters, %d attributes\n%s",
        program.instruction_count, kTargetInstructionCount, kOriginalInstructionCount,
        program.resources.temporaries, program.resources.parameters, program.resources.attributes,
        program.text.c_str());
    EXPECT_LE(program.instruction_count, kTargetInstructionCount);
    EXPECT_EQ(program.instruction_count, program.resources.instructions);
    EXPECT_EQ(program.text.rfind("!!ARBvp1.0", 0), 0u) << "must start with the header";
    ASSERT_GE(program.text.size(), 4u);
    EXPECT_EQ(program.text.substr(program.text.size() - 4), "END\n") << "must end with END";
    // Within the spec minimums, so that it loads everywhere.
    EXPECT_LE(program.resources.temporaries, 12);
    EXPECT_LE(program.resources.parameters, 96);
    EXPECT_LE(program.resources.attributes, 16);
    // One instruction per line: every line with a ';' holds exactly one statement.
    std::size_t start = 0;
    while (start < program.text.size()) {
        const std::size_t end = program.text.find('\n', start);
        const std::string line = program.text.substr(start, end - start);
        const std::string code = line.substr(0, line.find('#'));
        EXPECT_LE(std::count(code.begin(), code.end(), ';'), 1) << line;
        start = end == std::string::npos ? program.text.size() : end + 1;
    }
}

TEST(ArbProgram, CountsOnlyExecutableInstructions) {
    // 4 DP4 of the transform + the scattering + one MOV per texture unit; declarations, OPTION and
    // END do not count.
    const int base = generate().instruction_count - 1;  // default: one texture unit
    ArbProgramOptions o;
    o.texcoord_units = 0;
    EXPECT_EQ(generate(o).instruction_count, base);
    o.texcoord_units = 3;
    EXPECT_EQ(generate(o).instruction_count, base + 3);
    o.position_invariant = true;
    EXPECT_EQ(generate(o).instruction_count, base + 3 - 4);
    const auto synthetic = parse(
        "!!ARBvp1.0\nOPTION ARB_position_invariant;\nTEMP a, b;\nPARAM c = program.local[0];\n"
        "ATTRIB p = vertex.position;\nOUTPUT o = result.color;\nMOV a, p;\nADD b, a, c;\n"
        "MOV o, b;\nEND\n");
    EXPECT_EQ(synthetic.resources.instructions, 3);
    EXPECT_EQ(synthetic.resources.temporaries, 2);
    EXPECT_EQ(synthetic.resources.parameters, 1);
    EXPECT_EQ(synthetic.resources.attributes, 1);
}

/// In both parameter spaces and at each base in BASES, the program generated with OPTIONS reads
/// program.SPACE[base .. base + COUNT) and nothing else, and every one of them.
void expect_reads_exactly_its_parameters(const ArbProgramOptions& options, int count,
                                         std::initializer_list<int> bases) {
    const std::regex use(R"(program\.(local|env)\[(\d+)\])");
    for (auto space : {aerial::ParameterSpace::local, aerial::ParameterSpace::env}) {
        for (int base : bases) {
            ArbProgramOptions o = options;
            o.parameter_space = space;
            o.parameter_base = base;
            const std::string text = generate(o).text;
            std::vector<bool> used(static_cast<std::size_t>(count), false);
            for (auto it = std::sregex_iterator(text.begin(), text.end(), use);
                 it != std::sregex_iterator(); ++it) {
                const int index = std::stoi((*it)[2].str());
                EXPECT_EQ((*it)[1].str(), space == aerial::ParameterSpace::local ? "local" : "env");
                ASSERT_GE(index, base) << text;
                ASSERT_LT(index, base + count) << text;
                used[static_cast<std::size_t>(index - base)] = true;
            }
            for (int i = 0; i < count; ++i) {
                EXPECT_TRUE(used[static_cast<std::size_t>(i)]) << "parameter " << i << " unused";
            }
        }
    }
}

TEST(ArbProgram, ReadsOnlyTheDocumentedParameterIndices) {
    ASSERT_NO_FATAL_FAILURE(expect_reads_exactly_its_parameters(
        ArbProgramOptions{}, aerial::kArbParameterCount, {0, 7, 90}));
}

TEST(ArbProgram, WritesEveryOutputItUsesAndNothingElse) {
    const auto program = parse(generate().text);
    const Frame<float> f = frame_for(Atmosphere{}, {0, 0, 100}, {0, 0.6, 0.8});
    const ArbResults r = aerial::validation::run_arb_program(
        program, machine_with(parameters(f, 8.0f)), vertex_at({0, 5e3f, 50}));
    EXPECT_EQ(r.position.written, 0xfu);
    EXPECT_EQ(r.color_primary.written, 0xfu);
    EXPECT_EQ(r.color_secondary.written, 0xfu);
    EXPECT_EQ(r.fogcoord.written & 1u, 1u);
    EXPECT_EQ(r.texcoord[0].written, 0xfu);
    EXPECT_EQ(r.texcoord[1].written, 0u);
    EXPECT_TRUE(all_finite(r.position.value) && all_finite(r.color_primary.value) &&
                all_finite(r.color_secondary.value) && all_finite(r.fogcoord.value, 1));
    EXPECT_EQ(r.color_primary.value[3], 1.0f) << "primary alpha";
    EXPECT_EQ(r.color_secondary.value[3], 0.0f) << "secondary alpha";
}

// ---- Options ---------------------------------------------------------------------------------

TEST(ArbProgram, EnvAndLocalVariantsGiveIdenticalResults) {
    const Frame<float> f = frame_for(preset("hazy"), {10, -20, 300}, direction(12, 40));
    const auto reference = parse(generate().text);
    const Params p = parameters(f, 6.0f);
    for (auto space : {aerial::ParameterSpace::local, aerial::ParameterSpace::env}) {
        for (int base : {0, 11, 90}) {
            SCOPED_TRACE("base " + std::to_string(base));
            ArbProgramOptions o;
            o.parameter_space = space;
            o.parameter_base = base;
            const auto program = parse(generate(o).text);
            for (double d : {1.0, 300.0, 20000.0}) {
                const glm::vec3 v = glm::vec3(f.view.eye + d * direction(3, 50));
                const ArbResults a =
                    aerial::validation::run_arb_program(program, machine_with(p, o), vertex_at(v));
                const ArbResults b =
                    aerial::validation::run_arb_program(reference, machine_with(p), vertex_at(v));
                EXPECT_EQ(a.color_primary.value, b.color_primary.value);
                EXPECT_EQ(a.color_secondary.value, b.color_secondary.value);
                EXPECT_EQ(a.fogcoord.value[0], b.fogcoord.value[0]);
            }
            // It reads the space it was generated for: the other one leaves it without values.
            ArbProgramOptions other = o;
            other.parameter_space = space == aerial::ParameterSpace::local
                                        ? aerial::ParameterSpace::env
                                        : aerial::ParameterSpace::local;
            const ArbResults wrong = aerial::validation::run_arb_program(
                program, machine_with(p, other), vertex_at({0, 100, 0}));
            EXPECT_FALSE(all_finite(wrong.color_secondary.value));
        }
    }
}

TEST(ArbProgram, PassesThroughEachTexcoordUnitItIsAskedFor) {
    const Frame<float> f = frame_for(Atmosphere{}, {0, 0, 10}, {0, 0, 1});
    const Params p = parameters(f, 1.0f);
    aerial::validation::ArbVertex v = vertex_at({100, 200, 0});
    for (int u = 0; u < aerial::kArbMaxTexcoordUnits; ++u) {
        const float k = float(u);
        v.texcoord[static_cast<std::size_t>(u)] = {k + 0.25f, -k, 2.0f * k, 1.0f + k};
    }
    for (int units = 0; units <= aerial::kArbMaxTexcoordUnits; ++units) {
        SCOPED_TRACE("units " + std::to_string(units));
        ArbProgramOptions o;
        o.texcoord_units = units;
        const auto program = parse(generate(o).text);
        EXPECT_EQ(program.resources.attributes, 1 + units);
        const ArbResults r = aerial::validation::run_arb_program(program, machine_with(p), v);
        for (int u = 0; u < aerial::kArbMaxTexcoordUnits; ++u) {
            const auto& out = r.texcoord[static_cast<std::size_t>(u)];
            if (u < units) {
                EXPECT_EQ(out.written, 0xfu) << "unit " << u;
                EXPECT_EQ(out.value, v.texcoord[static_cast<std::size_t>(u)]) << "unit " << u;
            } else {
                EXPECT_EQ(out.written, 0u) << "unit " << u;
            }
        }
    }
}

TEST(ArbProgram, PositionInvariantOptionLeavesThePositionToGl) {
    const Frame<float> f = frame_for(preset("earth"), {0, 0, 50}, direction(20, 10));
    const Params p = parameters(f, 10.0f);
    ArbProgramOptions invariant;
    invariant.position_invariant = true;
    const aerial::ArbProgram with_option = generate(invariant);
    const aerial::ArbProgram without = generate();
    EXPECT_NE(with_option.text.find("\nOPTION ARB_position_invariant;\n"), std::string::npos);
    EXPECT_EQ(with_option.text.find("result.position"), std::string::npos);
    EXPECT_EQ(with_option.text.find("state.matrix"), std::string::npos);
    EXPECT_EQ(with_option.instruction_count, without.instruction_count - 4);

    aerial::validation::ArbMachine m = machine_with(p);
    m.mvp = {{{0.5f, 0, 0, 1}, {0, 2, 0, -3}, {0, 0, -1, 0.5f}, {0, 0, -1, 0}}};
    const glm::vec3 v(300, 4000, 20);
    const ArbResults a =
        aerial::validation::run_arb_program(parse(with_option.text), m, vertex_at(v));
    const ArbResults b = aerial::validation::run_arb_program(parse(without.text), m, vertex_at(v));
    EXPECT_EQ(a.position.written, 0u);
    EXPECT_EQ(b.position.written, 0xfu);
    EXPECT_FLOAT_EQ(b.position.value[0], 0.5f * v.x + 1.0f);
    EXPECT_FLOAT_EQ(b.position.value[1], 2.0f * v.y - 3.0f);
    EXPECT_FLOAT_EQ(b.position.value[2], -v.z + 0.5f);
    EXPECT_FLOAT_EQ(b.position.value[3], -v.z);
    EXPECT_EQ(a.color_primary.value, b.color_primary.value);
    EXPECT_EQ(a.color_secondary.value, b.color_secondary.value);
    EXPECT_EQ(a.fogcoord.value[0], b.fogcoord.value[0]);
}

// ---- Limits and errors -----------------------------------------------------------------------

TEST(ArbProgram, LimitChecksNameTheExceededLimit) {
    struct Case {
        const char* field;
        const char* gl_name;
        void (*shrink)(ArbProgramOptions&);
    };
    const Case cases[] = {
        {"instructions", "MAX_PROGRAM_INSTRUCTIONS_ARB",
         [](ArbProgramOptions& o) { o.limits.max_instructions = 20; }},
        {"temporaries", "MAX_PROGRAM_TEMPORARIES_ARB",
         [](ArbProgramOptions& o) { o.limits.max_temporaries = 4; }},
        {"parameters", "MAX_PROGRAM_PARAMETERS_ARB",
         [](ArbProgramOptions& o) { o.limits.max_parameters = 8; }},
        {"attributes", "MAX_PROGRAM_ATTRIBS_ARB",
         [](ArbProgramOptions& o) { o.limits.max_attributes = 1; }},
    };
    for (const Case& c : cases) {
        ArbProgramOptions o;
        c.shrink(o);
        const auto r = aerial::generate_arb_program(o);
        ASSERT_FALSE(r.ok()) << c.field;
        EXPECT_EQ(r.error().field, c.field);
        EXPECT_EQ(r.error().message.rfind(
                      std::string("aerial::generate_arb_program(): ") + c.field + ": expected ", 0),
                  0u)
            << r.error().message;
        EXPECT_NE(r.error().message.find(c.gl_name), std::string::npos) << r.error().message;
    }
    // The spec minimums themselves: 128 instructions fit, 129 do not; 124 with position
    // invariance (section 2.14.4.5.1).
    aerial::ArbResources r;
    r.instructions = 128;
    EXPECT_FALSE(aerial::check_arb_limits(r, {}, false).has_value());
    r.instructions = 129;
    ASSERT_TRUE(aerial::check_arb_limits(r, {}, false).has_value());
    EXPECT_EQ(aerial::check_arb_limits(r, {}, false)->message,
              "aerial::check_arb_limits(): instructions: expected at most 128 "
              "(MAX_PROGRAM_INSTRUCTIONS_ARB), got 129 in the program");
    r.instructions = 124;
    EXPECT_FALSE(aerial::check_arb_limits(r, {}, true).has_value());
    r.instructions = 125;
    const auto invariant = aerial::check_arb_limits(r, {}, true);
    ASSERT_TRUE(invariant.has_value());
    EXPECT_NE(invariant->message.find("ARB_position_invariant"), std::string::npos);
    r = {};
    r.temporaries = 13;
    EXPECT_EQ(aerial::check_arb_limits(r, {}, false)->field, "temporaries");
    r = {};
    r.parameters = 97;
    EXPECT_EQ(aerial::check_arb_limits(r, {}, false)->field, "parameters");
    r = {};
    r.attributes = 17;
    EXPECT_EQ(aerial::check_arb_limits(r, {}, false)->field, "attributes");
    // Counting a long program: 129 MOVs.
    std::string text = "!!ARBvp1.0\nTEMP t;\n";
    for (int i = 0; i < 129; ++i) text += "MOV t, vertex.position;\n";
    const auto parsed = parse(text + "END\n");
    EXPECT_EQ(parsed.resources.instructions, 129);
    EXPECT_EQ(aerial::check_arb_limits(parsed.resources, {}, false)->field, "instructions");
}

TEST(ArbProgram, RejectsOptionsItCannotGenerate) {
    const auto expect_field = [](const ArbProgramOptions& o, const std::string& field) {
        const auto r = aerial::generate_arb_program(o);
        ASSERT_FALSE(r.ok()) << field;
        EXPECT_EQ(r.error().field, field);
        EXPECT_EQ(
            r.error().message.rfind("aerial::generate_arb_program(): " + field + ": expected ", 0),
            0u)
            << r.error().message;
    };
    ArbProgramOptions o;
    o.model = Model::reference;
    expect_field(o, "model");
    o = {};
    o.parameter_base = -1;
    expect_field(o, "parameter_base");
    o.parameter_base = 91;  // 91 + 6 > 96
    expect_field(o, "parameter_base");
    o = {};
    o.texcoord_units = aerial::kArbMaxTexcoordUnits + 1;
    expect_field(o, "texcoord_units");
    o.texcoord_units = -1;
    expect_field(o, "texcoord_units");
    o = {};
    o.parameter_base = 90;  // the last six indices
    EXPECT_TRUE(aerial::generate_arb_program(o).ok());
}

// The one message style for the ARB program generator, pinned whole.
TEST(ArbProgram, MessagesAreFunctionFieldExpectedGot) {
    ArbProgramOptions o;
    o.model = Model::reference;
    EXPECT_EQ(aerial::generate_arb_program(o).error().message,
              "aerial::generate_arb_program(): model: expected hoffman-preetham or height (the "
              "models with an ARB program), got reference");
    o = {};
    o.parameter_base = 91;
    EXPECT_EQ(aerial::generate_arb_program(o).error().message,
              "aerial::generate_arb_program(): parameter_base: expected at most 90 (the program "
              "reads 6 of the 96 program parameters, MAX_PROGRAM_PARAMETERS_ARB), got 91");
    const Frame<float> f = frame_for(Atmosphere{}, {0, 0, 2}, {0, 0, 1});
    Display dark;
    dark.exposure = 0.0f;
    EXPECT_EQ(aerial::arb_program_parameters(f, dark).error().message,
              "aerial::arb_program_parameters(): display.exposure: expected a finite value > 0, "
              "got 0");
    EXPECT_EQ(
        aerial::validation::parse_arb_program("!!ARBvp1.0\nTEMP t, t;\nEND\n").error().message,
        "aerial::validation::parse_arb_program(): line 2: column 9: 't' is already "
        "declared");
}

// ---- Parameters ------------------------------------------------------------------------------

TEST(ArbProgramParameters, RejectWhatTheProgramCannotShow) {
    View view;
    const auto height = aerial::prepare_frame<float>(Atmosphere{}, view, Model::height);
    ASSERT_TRUE(height.ok());
    const auto r = aerial::arb_program_parameters(*height, Display{});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "frame.model");

    const Frame<float> f = frame_for(Atmosphere{}, {0, 0, 2}, {0, 0, 1});
    for (float exposure : {0.0f, -1.0f, std::nanf(""), INFINITY}) {
        Display d;
        d.exposure = exposure;
        const auto e = aerial::arb_program_parameters(f, d);
        ASSERT_FALSE(e.ok()) << exposure;
        EXPECT_EQ(e.error().field, "display.exposure");
    }
    Display exponential;
    exponential.tone = aerial::ToneCurve::exponential;
    const auto e = aerial::arb_program_parameters(f, exponential);
    ASSERT_FALSE(e.ok());
    EXPECT_EQ(e.error().field, "display.tone");
    EXPECT_EQ(e.error().message,
              "aerial::arb_program_parameters(): display.tone: expected clamp (the ARB program "
              "applies the exposure and GL clamps), got exponential");
}

TEST(ArbProgramParameters, LayoutMatchesWhatTheProgramReads) {
    const Frame<float> f = frame_for(preset("earth"), {5, 6, 70}, direction(25, 200));
    const Params p = parameters(f, 12.0f);
    ASSERT_EQ(p.size(), static_cast<std::size_t>(aerial::kArbParameterCount));
    // The documented constants.
    EXPECT_EQ(p[0][0], 5.0f);
    EXPECT_EQ(p[0][2], 70.0f);
    EXPECT_EQ(p[0][3], 1.0f - 1.0f / 1048576.0f) << "eye.w = 1 - 2^-20";
    for (std::size_t i = 1; i <= 4; ++i) EXPECT_EQ(p[i][3], 0.0f) << "parameter " << i << ".w";
    const float g = f.mie_g;
    EXPECT_EQ(p[5], (std::array<float, 4>{g, 0.25f, (1.0f - g) * (1.0f - g), -1.0f}));
    for (int c = 0; c < 3; ++c) {
        const std::size_t i = static_cast<std::size_t>(c);
        EXPECT_FLOAT_EQ(p[1][i], float(f.view.sun_dir[c]));
        EXPECT_FLOAT_EQ(p[2][i], -(f.rayleigh_scattering[c] + f.mie_extinction[c]) *
                                     float(1.0 / std::log(2.0)));
        EXPECT_GT(p[3][i], 0.0f);
        EXPECT_GT(p[4][i], 0.0f);
    }
    // Every component the program reads matters: poisoning it poisons an output.
    const auto program = parse(generate().text);
    const aerial::validation::ArbVertex v = vertex_at({2000, -3000, 40});
    const ArbResults clean = aerial::validation::run_arb_program(program, machine_with(p), v);
    ASSERT_TRUE(all_finite(clean.color_primary.value) && all_finite(clean.color_secondary.value));
    for (std::size_t i = 0; i < p.size(); ++i) {
        for (std::size_t j = 0; j < 4; ++j) {
            if (i == 2 && j == 3) continue;  // extinction.w: documented as unused
            Params poisoned = p;
            poisoned[i][j] = std::nanf("");
            const ArbResults r =
                aerial::validation::run_arb_program(program, machine_with(poisoned), v);
            EXPECT_FALSE(all_finite(r.color_primary.value) && all_finite(r.color_secondary.value) &&
                         all_finite(r.fogcoord.value, 1))
                << "parameter " << i << " component " << j << " is not read";
        }
    }
}

TEST(ArbProgramParameters, ChannelsWithoutExtinctionStayFiniteAndMatchTheModel) {
    Atmosphere one_dark = preset("earth");
    one_dark.rayleigh_scattering.x = 0.0;  // red: no extinction at all
    one_dark.mie_scattering.x = 0.0;
    Atmosphere tiny = preset("earth");
    tiny.rayleigh_scattering.y = 1e-20;  // green: 1e-15 of the others
    tiny.mie_scattering.y = 1e-21;
    Atmosphere vacuum = preset("earth");
    vacuum.rayleigh_scattering = glm::dvec3(0.0);
    vacuum.mie_scattering = glm::dvec3(0.0);
    const auto program = parse(generate().text);
    double worst_raw_lsb = 0.0;
    for (const Atmosphere* a : {&one_dark, &tiny, &vacuum}) {
        const Frame<float> f = frame_for(*a, {0, 0, 30}, direction(30, 0));
        for (float exposure : {1.0f, 50.0f}) {
            const Params p = parameters(f, exposure);
            for (const auto& row : p) EXPECT_TRUE(all_finite(row));
            Parity parity;
            for (double d : kDistancesM) {
                for (const glm::dvec3& dir : view_directions(f.view.sun_dir, 3)) {
                    const glm::vec3 v = glm::vec3(f.view.eye + d * dir);
                    const ArbResults r =
                        aerial::validation::run_arb_program(program, machine_with(p), vertex_at(v));
                    ASSERT_TRUE(all_finite(r.color_primary.value) &&
                                all_finite(r.color_secondary.value));
                    compare(r, f, exposure, v, parity, "d=" + std::to_string(d));
                    // Before rounding to 8 bits: the raised channels are off by < 0.5 LSB.
                    const aerial::Scattering<float> cpu = aerial::scatter(f, v);
                    for (int c = 0; c < 3; ++c) {
                        const std::size_t i = static_cast<std::size_t>(c);
                        Display display;
                        display.exposure = exposure;
                        const float lin = std::min(r.color_secondary.value[i], 1.0f);
                        worst_raw_lsb = std::max(
                            {worst_raw_lsb,
                             255.0 * std::abs(r.color_primary.value[i] - cpu.extinction[c]),
                             255.0 * std::abs(lin - aerial::display_value(display,
                                                                          cpu.in_scattering[c]))});
                    }
                }
            }
            EXPECT_LE(std::max(parity.max_fex_lsb, parity.max_lin_lsb), 1) << parity.worst;
        }
    }
    std::printf("[ info     ] channels without extinction: max error %.2g LSB before rounding\n",
                worst_raw_lsb);
    EXPECT_LT(worst_raw_lsb, 0.5);
}

TEST(ArbProgram, VertexAtTheEyeHasNoHazeAndNoNaN) {
    const Frame<float> f = frame_for(preset("foggy"), {100, 200, 3}, direction(5, 0));
    const auto program = parse(generate().text);
    const ArbResults r = aerial::validation::run_arb_program(
        program, machine_with(parameters(f, 30.0f)), vertex_at(glm::vec3(f.view.eye)));
    for (std::size_t c = 0; c < 3; ++c) {
        EXPECT_EQ(r.color_primary.value[c], 1.0f);
        EXPECT_EQ(r.color_secondary.value[c], 0.0f);
    }
    EXPECT_TRUE(std::isfinite(r.fogcoord.value[0]));
    EXPECT_LT(r.fogcoord.value[0], 1e-5f);
}

// ---- Parity with the CPU model ---------------------------------------------------------------

TEST(ArbProgram, ReproducesTheCpuModelWithin1LsbOverAWideGrid) {
    const auto program = parse(generate().text);
    const std::vector<glm::dvec3> eyes{
        {0, 0, 2}, {0, 0, 100}, {0, 0, 1000}, {0, 0, 10000}, {3000, -2000, 300}};
    Parity parity;
    for (const std::string& name : aerial::atmosphere_preset_names()) {
        const Atmosphere a = preset(name);
        for (const glm::dvec3& eye : eyes) {
            for (double sun_elevation : {-5.0, 0.0, 5.0, 20.0, 45.0, 90.0}) {
                const Frame<float> f = frame_for(a, eye, direction(sun_elevation, 30));
                const std::vector<glm::dvec3> dirs = view_directions(f.view.sun_dir, 8);
                for (float exposure : {1.0f, 4.0f, 16.0f, 64.0f}) {
                    const aerial::validation::ArbMachine m = machine_with(parameters(f, exposure));
                    for (double d : kDistancesM) {
                        for (const glm::dvec3& dir : dirs) {
                            const glm::vec3 v = glm::vec3(eye + d * dir);
                            const ArbResults r =
                                aerial::validation::run_arb_program(program, m, vertex_at(v));
                            compare(r, f, exposure, v, parity,
                                    name + " eye z=" + std::to_string(eye.z) +
                                        " sun=" + std::to_string(sun_elevation) + " exposure=" +
                                        std::to_string(exposure) + " d=" + std::to_string(d));
                        }
                    }
                }
            }
        }
    }
    std::printf(
        "[ info     ] ARB program vs aerial::scatter over %ld vertices: max F_ex %d LSB, "
        "max L_in %d LSB, %.3f%% of vertices off by one in some channel; max error before "
        "rounding %.3f LSB\n",
        parity.vertices, parity.max_fex_lsb, parity.max_lin_lsb,
        100.0 * double(parity.off_by_one) / double(parity.vertices), parity.max_raw_lsb);
    EXPECT_LE(parity.max_fex_lsb, 1) << parity.worst;
    EXPECT_LE(parity.max_lin_lsb, 1) << parity.worst;
}

TEST(ArbProgram, ReproducesTheCpuModelForBackwardScattering) {
    // g < 0: the sun parameter is negated and |g| enters the phase, which keeps the HG base a sum
    // of positive terms at the anti-sun peak.
    const auto program = parse(generate().text);
    Parity parity;
    for (double g : {-0.3, -0.76, -0.9}) {
        Atmosphere a = preset("hazy");
        a.mie_g = g;
        const Frame<float> f = frame_for(a, {500, -700, 50}, direction(25, 60));
        const Params p = parameters(f, 4.0f);
        EXPECT_FLOAT_EQ(p[1][0], -float(f.view.sun_dir.x));
        EXPECT_FLOAT_EQ(p[5][0], float(std::abs(g)));
        const aerial::validation::ArbMachine m = machine_with(p);
        for (double d : kDistancesM) {
            for (const glm::dvec3& dir : view_directions(-f.view.sun_dir, 4)) {
                const glm::vec3 v = glm::vec3(f.view.eye + d * dir);
                compare(aerial::validation::run_arb_program(program, m, vertex_at(v)), f, 4.0f, v,
                        parity, "g=" + std::to_string(g) + " d=" + std::to_string(d));
            }
        }
    }
    EXPECT_LE(std::max(parity.max_fex_lsb, parity.max_lin_lsb), 1) << parity.worst;
    EXPECT_LT(parity.max_raw_lsb, 0.5) << parity.worst;
}

TEST(ArbProgram, ReproducesTheCpuModelInOtherEngineUnits) {
    const auto program = parse(generate().text);
    for (double meters_per_unit : {0.01, 0.3048, 1000.0}) {
        Parity parity;
        for (const std::string& name : {std::string("earth"), std::string("foggy")}) {
            const glm::dvec3 eye = glm::dvec3(40, -25, 150) / meters_per_unit;
            const Frame<float> f =
                frame_for(preset(name), eye, direction(15, 100), meters_per_unit);
            const aerial::validation::ArbMachine m = machine_with(parameters(f, 10.0f));
            for (double d : kDistancesM) {
                for (const glm::dvec3& dir : view_directions(f.view.sun_dir, 4)) {
                    const glm::vec3 v = glm::vec3(eye + d / meters_per_unit * dir);
                    const ArbResults r =
                        aerial::validation::run_arb_program(program, m, vertex_at(v));
                    compare(r, f, 10.0f, v, parity, name + " d=" + std::to_string(d));
                    EXPECT_NEAR(r.fogcoord.value[0], d / meters_per_unit,
                                1e-5 * d / meters_per_unit + 1e-6 * glm::length(eye))
                        << "fog coordinate in engine units";
                }
            }
        }
        EXPECT_LE(std::max(parity.max_fex_lsb, parity.max_lin_lsb), 1)
            << "meters_per_unit " << meters_per_unit << ": " << parity.worst;
    }
}

// ---- Old hardware: approximate instructions with ~11 bits -----------------------------------

TEST(ArbProgram, PerturbedApproximationsStayWithin1LsbPlusTheExtinctionBound) {
    // Every combination of signs of a 2^-11 relative error e on RSQ, the three EX2 and POW.
    // To first order, with lin = exposure L_in(infinity) along the ray and L_in = lin (1 - F):
    //   EX2 moves F by e F: F_ex by <= 0.13 LSB, but L_in by e F lin (the cancellation in 1 - F);
    //   POW moves L_in by e (1 - F) lin;  RSQ moves h by e, so the Mie term by 1.5 e (1 - F) lin,
    //   and s by e, so F by e tau F.
    // Hence |dL_in| <= e lin (F + 2.5 (1 - F) + tau F): within 1 LSB wherever that is below
    // 1/255, i.e. where the haze at infinity is at most ~7 times display white; more towards a
    // bright Mie lobe at a high exposure, and near the eye, where F is close to 1.
    const auto program = parse(generate().text);
    const int approx = aerial::validation::count_approximate_instructions(program);
    ASSERT_EQ(approx, 5);
    const std::uint32_t patterns = 1u << approx;
    const double ex2_lsb_per_lin = 255.0 * double(kOldHardwareError);

    int worst_fex = 0, worst_lin = 0, worst_lin_moderate = 0;
    double lin_at_worst = 0.0;
    std::string worst_where;
    long vertices = 0;
    aerial::testing::GridSample sample("vertices");
    for (const std::string& name : aerial::atmosphere_preset_names()) {
        const Atmosphere a = preset(name);
        for (const glm::dvec3& eye :
             {glm::dvec3(0, 0, 2), glm::dvec3(0, 0, 1000), glm::dvec3(0, 0, 10000)}) {
            for (double sun_elevation : {0.0, 10.0, 45.0, 90.0}) {
                const Frame<float> f = frame_for(a, eye, direction(sun_elevation, 30));
                const std::vector<glm::dvec3> dirs = view_directions(f.view.sun_dir, 4);
                for (float exposure : {1.0f, 4.0f, 16.0f}) {
                    const aerial::validation::ArbMachine m = machine_with(parameters(f, exposure));
                    Display display;
                    display.exposure = exposure;
                    for (double d : kDistancesM) {
                        for (const glm::dvec3& dir : dirs) {
                            if (!sample.keep()) continue;
                            const glm::vec3 v = glm::vec3(eye + d * dir);
                            const aerial::Scattering<float> cpu = aerial::scatter(f, v);
                            ++vertices;
                            for (std::uint32_t pattern = 0; pattern < patterns; ++pattern) {
                                aerial::validation::ArbInterpreterOptions o;
                                o.relative_error = kOldHardwareError;
                                o.sign_pattern = pattern;
                                const ArbResults r = aerial::validation::run_arb_program(
                                    program, m, vertex_at(v), o);
                                for (int c = 0; c < 3; ++c) {
                                    const std::size_t i = static_cast<std::size_t>(c);
                                    const int fex =
                                        lsb_difference(r.color_primary.value[i], cpu.extinction[c]);
                                    const int lin = lsb_difference(
                                        r.color_secondary.value[i],
                                        aerial::display_value(display, cpu.in_scattering[c]));
                                    const double lin_inf = asymptotic_display(f, exposure, dir, c);
                                    const double fex_c = cpu.extinction[c];
                                    const double tau = fex_c > 0.0 ? -std::log(fex_c) : 0.0;
                                    const double predicted =
                                        ex2_lsb_per_lin * lin_inf *
                                        (fex_c + 2.5 * (1.0 - fex_c) + tau * fex_c);
                                    const int bound = 1 + int(std::floor(predicted + 0.01));
                                    worst_fex = std::max(worst_fex, fex);
                                    EXPECT_LE(fex, 1) << name << " d=" << d;
                                    ASSERT_LE(lin, bound)
                                        << name << " eye z=" << eye.z << " sun " << sun_elevation
                                        << " exposure " << exposure << " d=" << d << " channel "
                                        << c << " L_in(inf) " << lin_inf;
                                    if (lin > worst_lin) {
                                        worst_lin = lin;
                                        lin_at_worst = lin_inf;
                                        worst_where = name + " exposure " +
                                                      std::to_string(exposure) +
                                                      " d=" + std::to_string(d);
                                    }
                                    if (predicted <= 0.9) {
                                        worst_lin_moderate = std::max(worst_lin_moderate, lin);
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    std::printf(
        "[ info     ] 2^-11 on RSQ/EX2/POW, all %u sign patterns, %ld vertices: max F_ex "
        "%d LSB; max L_in %d LSB where the first-order bound is < 0.9 LSB (exposure * "
        "L_in(inf) <~ 7); max L_in overall %d LSB (%s, exposure * L_in(inf) = %.1f)\n",
        patterns, vertices, worst_fex, worst_lin_moderate, worst_lin, worst_where.c_str(),
        lin_at_worst);
    EXPECT_LE(worst_fex, 1);
    EXPECT_LE(worst_lin_moderate, 1);
}

TEST(ArbProgram, GuardedProgramStaysWithin1LsbWithCoarseApproximationsAtAnyExposure) {
    // guard_coarse_ex2 clamps F_ex into its series bounds, so that EX2's error can only act
    // where those bounds are wider than it: at most 2^-11 min(1, tau^3/6 / 2^-11) lin.
    ArbProgramOptions guarded;
    guarded.guard_coarse_ex2 = true;
    const aerial::ArbProgram text = generate(guarded);
    EXPECT_EQ(text.instruction_count, generate().instruction_count + 7);
    const auto program = parse(text.text);
    const int approx = aerial::validation::count_approximate_instructions(program);
    ASSERT_EQ(approx, 5);
    int worst_exact = 0, worst_perturbed = 0;
    std::string where;
    long vertices = 0;
    aerial::testing::GridSample sample("vertices");
    for (const std::string& name : aerial::atmosphere_preset_names()) {
        const Atmosphere a = preset(name);
        for (const glm::dvec3& eye : {glm::dvec3(0, 0, 2), glm::dvec3(0, 0, 3000)}) {
            for (double sun_elevation : {10.0, 45.0}) {
                const Frame<float> f = frame_for(a, eye, direction(sun_elevation, 30));
                const std::vector<glm::dvec3> dirs = view_directions(f.view.sun_dir, 2);
                for (float exposure : {1.0f, 16.0f, 256.0f, 1024.0f}) {
                    const aerial::validation::ArbMachine m = machine_with(parameters(f, exposure));
                    Display display;
                    display.exposure = exposure;
                    for (double d = 1.0; d < 6e4; d *= 1.5) {
                        for (const glm::dvec3& dir : dirs) {
                            if (!sample.keep()) continue;
                            const glm::vec3 v = glm::vec3(eye + d * dir);
                            const aerial::Scattering<float> cpu = aerial::scatter(f, v);
                            ++vertices;
                            for (std::uint32_t pattern = 0; pattern <= (1u << approx); ++pattern) {
                                aerial::validation::ArbInterpreterOptions o;  // the last run: exact
                                o.relative_error = pattern < (1u << approx) ? kOldHardwareError : 0;
                                o.sign_pattern = pattern;
                                const ArbResults r = aerial::validation::run_arb_program(
                                    program, m, vertex_at(v), o);
                                int worst = 0;
                                for (int c = 0; c < 3; ++c) {
                                    const std::size_t i = static_cast<std::size_t>(c);
                                    worst = std::max(
                                        {worst,
                                         lsb_difference(r.color_primary.value[i],
                                                        cpu.extinction[c]),
                                         lsb_difference(r.color_secondary.value[i],
                                                        aerial::display_value(
                                                            display, cpu.in_scattering[c]))});
                                }
                                int& slot = o.relative_error > 0 ? worst_perturbed : worst_exact;
                                if (worst > slot) {
                                    slot = worst;
                                    where = name + " exposure " + std::to_string(exposure) +
                                            " d=" + std::to_string(d);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    std::printf(
        "[ info     ] guarded program (%d instructions), %ld vertices, exposures 1 to 1024: "
        "max %d LSB exact, max %d LSB with 2^-11 on RSQ/EX2/POW (all sign patterns)\n",
        text.instruction_count, vertices, worst_exact, worst_perturbed);
    EXPECT_LE(worst_exact, 1) << where;
    EXPECT_LE(worst_perturbed, 1) << where;
}

TEST(ArbProgram, CoarseRsqIsHarmlessAtTheMiePeak) {
    // Looking straight at the sun, where the HG lobe is steepest in cos(theta). Had the program
    // taken 1 - cos(theta) from dot(d, sun) / s, RSQ off by 2^-11 would move it by 2^-11 and the
    // g = 0.85 peak, where 1 + g^2 - 2g = 0.0225, by 1.5 * 2 g 2^-11 / 0.0225 = 5.5 %.
    // w = |d / s - sun|^2 only moves by 2^-11 relative: within 1 LSB.
    const auto program = parse(generate().text);
    const Frame<float> f = frame_for(preset("foggy"), {0, 0, 2}, direction(10, 0));
    const aerial::validation::ArbMachine m = machine_with(parameters(f, 1.0f));
    Display display;
    int worst = 0;
    for (double d : kDistancesM) {
        const glm::vec3 v = glm::vec3(f.view.eye + d * f.view.sun_dir);
        const aerial::Scattering<float> cpu = aerial::scatter(f, v);
        for (std::uint32_t sign : {0u, 1u}) {
            aerial::validation::ArbInterpreterOptions o;
            o.relative_error = kOldHardwareError;
            o.perturbed = aerial::validation::kArbApproxRsq;
            o.sign_pattern = sign;
            const ArbResults r = aerial::validation::run_arb_program(program, m, vertex_at(v), o);
            for (int c = 0; c < 3; ++c) {
                worst = std::max(
                    worst, lsb_difference(r.color_secondary.value[std::size_t(c)],
                                          aerial::display_value(display, cpu.in_scattering[c])));
            }
        }
    }
    EXPECT_LE(worst, 1);
}

#ifdef AERIAL_EVAL_PATH
/// Runs aerial-eval with `args`, returns its stdout and exit status.
std::pair<std::string, int> run_aerial_eval(const std::string& args) {
    const std::string command = std::string("'") + AERIAL_EVAL_PATH + "' " + args + " 2>/dev/null";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return {"", -1};
    std::string out;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
    const int status = pclose(pipe);
    return {out, WIFEXITED(status) ? WEXITSTATUS(status) : -1};
}

TEST(ArbProgram, AerialEvalPrintsExactlyTheGeneratedText) {
    const auto [out, status] = run_aerial_eval("--print-arb-program");
    EXPECT_EQ(status, 0);
    EXPECT_EQ(out, generate().text);
    EXPECT_EQ(run_aerial_eval("--print-arb-program --model hoffman-preetham").first, out);
    ArbProgramOptions height;
    height.model = Model::height;
    EXPECT_EQ(run_aerial_eval("--print-arb-program --model height").first, generate(height).text);
    EXPECT_EQ(run_aerial_eval("--print-arb-program --model reference").second, 2)
        << "reference has no program";
    // The fidelity levels of the height program, each checked against its reference limits.
    for (auto f :
         {aerial::ArbHeightFidelity::spec_minimum, aerial::ArbHeightFidelity::exact_optical_depth,
          aerial::ArbHeightFidelity::full, aerial::ArbHeightFidelity::multiple_scattering}) {
        ArbProgramOptions o = height;
        o.height_fidelity = f;
        o.limits = aerial::arb_reference_limits(f);
        const std::string flag =
            std::string("--arb-height-fidelity ") + aerial::arb_height_fidelity_name(f);
        const auto [text, code] = run_aerial_eval("--print-arb-program " + flag);
        EXPECT_EQ(code, 0) << flag;
        EXPECT_EQ(text, generate(o).text) << flag;
        EXPECT_EQ(run_aerial_eval("--print-arb-program --model height " + flag).first, text);
    }
    EXPECT_EQ(run_aerial_eval("--print-arb-program --arb-height-fidelity fullest").second, 2);
    EXPECT_EQ(run_aerial_eval("--print-arb-program --arb-height-fidelity automatic").second, 2)
        << "without a driver there is nothing to choose from";
    EXPECT_EQ(run_aerial_eval("--print-arb-program --model hoffman-preetham "
                              "--arb-height-fidelity full")
                  .second,
              2);
    EXPECT_EQ(
        run_aerial_eval("--preset earth --eye 0,0,2 --sun 0,0,1 --arb-height-fidelity full").second,
        2)
        << "only with --print-arb-program";
}
#endif

// ---- The interpreter itself ------------------------------------------------------------------

ArbResults run_text(const std::string& body, const aerial::validation::ArbVertex& v = {},
                    const aerial::validation::ArbInterpreterOptions& o = {}) {
    aerial::validation::ArbMachine m;
    m.local = {{1, 2, 3, 4}, {-0.5f, 0.25f, 8, 16}};
    return aerial::validation::run_arb_program(parse("!!ARBvp1.0\n" + body + "END\n"), m, v, o);
}

TEST(ArbInterpreter, SwizzlesMasksAndNegationFollowTheSpec) {
    const ArbResults r = run_text(
        "PARAM a = program.local[0];\nTEMP t;\n"
        "MOV t, a.wzyx;\n"
        "MOV t.y, -a.x;\n"
        "MOV result.color, t;\n"
        "MOV result.color.secondary.xz, a.y;\n"
        "SWZ result.texcoord[2], a, -w, 0, 1, x;\n");
    EXPECT_EQ(r.color_primary.value, (std::array<float, 4>{4, -1, 2, 1}));
    EXPECT_EQ(r.color_secondary.written, 0x5u);
    EXPECT_EQ(r.color_secondary.value[0], 2.0f);
    EXPECT_EQ(r.color_secondary.value[2], 2.0f);
    EXPECT_TRUE(std::isnan(r.color_secondary.value[1]));
    EXPECT_EQ(r.texcoord[2].value, (std::array<float, 4>{-4, 0, 1, 1}));
}

TEST(ArbInterpreter, VectorAndDotInstructions) {
    const ArbResults r = run_text(
        "PARAM a = program.local[0];\nPARAM b = program.local[1];\nPARAM c = {1, 0.5, 2};\n"
        "TEMP t;\n"
        "DP3 result.texcoord[0], a, b;\n"
        "DP4 result.texcoord[1], a, b;\n"
        "DPH result.texcoord[2], a, b;\n"
        "MAD result.texcoord[3], a, b, c;\n"
        "MIN t, a, b;\nMAX t.w, a, b;\nMOV result.texcoord[4], t;\n"
        "SUB result.texcoord[5], a, 1.5;\n");
    const float dp3 = 1 * -0.5f + 2 * 0.25f + 3 * 8.0f;
    EXPECT_EQ(r.texcoord[0].value, (std::array<float, 4>{dp3, dp3, dp3, dp3}));
    EXPECT_EQ(r.texcoord[1].value[0], dp3 + 4 * 16.0f);
    EXPECT_EQ(r.texcoord[2].value[0], dp3 + 16.0f);
    EXPECT_EQ(r.texcoord[3].value, (std::array<float, 4>{0.5f, 1.0f, 26.0f, 65.0f}))
        << "constant vectors default w to 1";
    EXPECT_EQ(r.texcoord[4].value, (std::array<float, 4>{-0.5f, 0.25f, 3.0f, 16.0f}));
    EXPECT_EQ(r.texcoord[5].value, (std::array<float, 4>{-0.5f, 0.5f, 1.5f, 2.5f}));
}

TEST(ArbInterpreter, ScalarInstructionsReplicateAndExpLogSplitExactly) {
    const ArbResults r = run_text(
        "PARAM b = program.local[1];\n"
        "RSQ result.texcoord[0], -b.w;\n"  // absolute value: 1/4
        "RCP result.texcoord[1], b.x;\n"
        "EX2 result.texcoord[2], b.z;\n"
        "LG2 result.texcoord[3], b.z;\n"
        "POW result.texcoord[4], b.z, b.y;\n"
        "EXP result.texcoord[5], -b.x;\n"  // 0.5
        "LOG result.texcoord[6], -b.z;\n");
    EXPECT_EQ(r.texcoord[0].value, (std::array<float, 4>{0.25f, 0.25f, 0.25f, 0.25f}));
    EXPECT_EQ(r.texcoord[1].value[3], -2.0f);
    EXPECT_EQ(r.texcoord[2].value[1], 256.0f);
    EXPECT_EQ(r.texcoord[3].value[2], 3.0f);
    EXPECT_FLOAT_EQ(r.texcoord[4].value[0], std::pow(8.0f, 0.25f));
    EXPECT_EQ(r.texcoord[5].value[0], 1.0f);  // 2^floor(0.5)
    EXPECT_EQ(r.texcoord[5].value[1], 0.5f);  // fraction
    EXPECT_FLOAT_EQ(r.texcoord[5].value[2], std::sqrt(2.0f));
    EXPECT_EQ(r.texcoord[5].value[3], 1.0f);
    EXPECT_EQ(r.texcoord[6].value, (std::array<float, 4>{3.0f, 1.0f, 3.0f, 1.0f}));
}

TEST(ArbInterpreter, AddressRegisterIndexesArraysAndFloorAndFractionSplit) {
    // ARL takes the floor; array[a.x + n] reads element floor + n; outside the array the read is
    // undefined (NaN here), as the spec leaves it.
    const ArbResults r = run_text(
        "PARAM arr[2] = { program.local[0..1] };\nADDRESS a;\nTEMP t;\n"
        "ARL a.x, arr[1].x;\n"                     // floor(-0.5) = -1
        "MOV result.color, arr[a.x + 2];\n"        // element 1
        "MOV result.color.secondary, arr[a.x];\n"  // element -1: undefined
        "FLR result.texcoord[0], arr[1];\n"
        "FRC result.texcoord[1], arr[1];\n");
    EXPECT_EQ(r.color_primary.value, (std::array<float, 4>{-0.5f, 0.25f, 8, 16}));
    EXPECT_TRUE(std::isnan(r.color_secondary.value[0]));
    EXPECT_EQ(r.texcoord[0].value, (std::array<float, 4>{-1, 0, 8, 16}));
    EXPECT_EQ(r.texcoord[1].value, (std::array<float, 4>{0.5f, 0.25f, 0, 0}));
}

TEST(ArbInterpreter, PerturbationFollowsTheSignPatternInProgramOrder) {
    const std::string body =
        "PARAM b = program.local[1];\n"
        "EX2 result.texcoord[0], b.z;\n"
        "MOV result.texcoord[1], b;\n"
        "RCP result.texcoord[2], b.z;\n";
    aerial::validation::ArbInterpreterOptions o;
    o.relative_error = 1.0f / 2048.0f;
    o.sign_pattern = 0b10;  // first approximate instruction down, second up
    const ArbResults r = run_text(body, {}, o);
    EXPECT_EQ(r.texcoord[0].value[0], 256.0f * (1.0f - 1.0f / 2048.0f));
    EXPECT_EQ(r.texcoord[1].value[2], 8.0f) << "exact instructions are not perturbed";
    EXPECT_EQ(r.texcoord[2].value[0], 0.125f * (1.0f + 1.0f / 2048.0f));
    o.perturbed = aerial::validation::kArbApproxRcp;  // only RCP counts now: it is number 0, down
    const ArbResults only_rcp = run_text(body, {}, o);
    EXPECT_EQ(only_rcp.texcoord[0].value[0], 256.0f);
    EXPECT_EQ(only_rcp.texcoord[2].value[0], 0.125f * (1.0f - 1.0f / 2048.0f));
}

TEST(ArbInterpreter, ParseErrorsGiveTheLine) {
    struct Case {
        std::string text;
        std::string field;
        std::string says;
    };
    const std::vector<Case> cases{
        {"!!ARBfp1.0\nEND\n", "line 1", "!!ARBvp1.0"},
        {"!!ARBvp1.0\nTEMP t;\nFOO t, t;\nEND\n", "line 3", "FOO"},
        {"!!ARBvp1.0\nMOV result.color, x;\nEND\n", "line 2", "'x' is not declared"},
        {"!!ARBvp1.0\nTEMP t;\nMOV t.yx, vertex.position;\nEND\n", "line 3", "write mask"},
        {"!!ARBvp1.0\nTEMP t;\nRSQ t, vertex.position;\nEND\n", "line 3", "scalar"},
        {"!!ARBvp1.0\nTEMP t;\nMOV t, vertex.position.xy;\nEND\n", "line 3", "swizzle"},
        {"!!ARBvp1.0\nTEMP t;\nMOV t, vertex.position;\n", "line 4", "END"},
        {"!!ARBvp1.0\nATTRIB p = vertex.position;\nMOV p, p;\nEND\n", "line 3", "read-only"},
        {"!!ARBvp1.0\nTEMP t, t;\nEND\n", "line 2", "already declared"},
        {"!!ARBvp1.0\nTEMP result;\nEND\n", "line 2", "reserved"},
        {"!!ARBvp1.0\nOPTION ARB_position_invariant;\nMOV result.position, vertex.position;\nEND\n",
         "line 3", "ARB_position_invariant"},
        {"!!ARBvp1.0\nPARAM m[4] = { state.matrix.mvp };\nMOV result.color, m[4];\nEND\n", "line 3",
         "out of range"},
        {"!!ARBvp1.0\nTEMP t;\nMOV t, vertex.normal;\nEND\n", "line 3", "vertex.normal"},
        {"!!ARBvp1.0\nADDRESS a;\nADDRESS b;\nEND\n", "line 3", "one ADDRESS register"},
        {"!!ARBvp1.0\nADDRESS a;\nPARAM m[4] = { state.matrix.mvp };\nMOV result.color, "
         "m[a.x + 64];\nEND\n",
         "line 4", "[-64, 63]"},
        {"!!ARBvp1.0\nTEMP t;\nPARAM m[4] = { state.matrix.mvp };\nMOV result.color, m[t.x];\n"
         "END\n",
         "line 4", "not an ADDRESS register"},
        {"!!ARBvp1.0\nADDRESS a;\nTEMP t;\nMOV a.x, t;\nEND\n", "line 4", "only ARL"},
        {"!!ARBvp1.0\nTEMP t;\nARL t.x, t.x;\nEND\n", "line 3", "ARL writes"},
    };
    for (const Case& c : cases) {
        const auto r = aerial::validation::parse_arb_program(c.text);
        ASSERT_FALSE(r.ok()) << c.text;
        EXPECT_EQ(r.error().field, c.field) << r.error().message;
        EXPECT_EQ(r.error().message.rfind(
                      "aerial::validation::parse_arb_program(): " + c.field + ": column ", 0),
                  0u)
            << r.error().message;
        EXPECT_NE(r.error().message.find(c.says), std::string::npos) << r.error().message;
    }
}

}  // namespace

// ---- The height program ----------------------------------------------------------------------

namespace {

ArbProgramOptions at_fidelity(aerial::ArbHeightFidelity fidelity) {
    ArbProgramOptions o;
    o.model = Model::height;
    o.height_fidelity = fidelity;
    o.limits = aerial::arb_reference_limits(fidelity);
    // Direct3D 9-class native limits also for spec_minimum (its program fits 128 regardless).
    o.limits.max_instructions = std::max(o.limits.max_instructions, 256);
    return o;
}

}  // namespace

namespace {
namespace height {

ArbProgramOptions options(const ArbProgramOptions& base = {}) {
    ArbProgramOptions o = base;
    o.model = Model::height;
    return o;
}

View view_for(const glm::dvec3& eye, const glm::dvec3& sun, double meters_per_unit = 1.0) {
    View view;
    view.eye = eye;
    view.sun_dir = glm::normalize(sun);
    view.meters_per_unit = meters_per_unit;
    return view;
}

Frame<float> frame_for(const Atmosphere& atmosphere, const View& view) {
    auto f = aerial::prepare_frame<float>(atmosphere, view, Model::height);
    EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().message);
    return f.ok() ? *f : Frame<float>{};
}

Params parameters(const Frame<float>& frame, float exposure, const ArbProgramOptions& o = {}) {
    return ::parameters(frame, exposure, options(o));
}

/// Eyes from the ground to 30 km, sun elevations from -10 to 90 degrees, vertices in every
/// direction (including the sun, its neighbourhood and the horizontal) from 1 m to 150 km, plus
/// vertices at the eye's altitude around the sphere and vertices far below sea level.
struct Grid {
    std::vector<glm::dvec3> eyes{{0, 0, 2},    {0, 0, 100},   {300, -200, 1000},
                                 {0, 0, 3000}, {0, 0, 10000}, {0, 0, 30000}};
    std::vector<double> sun_elevations{-10, -3, 0, 2, 5, 10, 20, 45, 90};
    std::vector<double> distances{1, 10, 100, 1e3, 3e3, 1e4, 3e4, 6e4, 1e5, 1.5e5};
    int azimuths = 4;
};

/// The vertices of one eye: view directions at each distance, and points at the eye's own
/// altitude (on the sphere) and 20 km below sea level.
std::vector<glm::dvec3> vertices_for(const Grid& grid, const Frame<float>& f) {
    std::vector<glm::dvec3> out;
    const glm::dvec3 eye = f.view.eye;
    for (double d : grid.distances) {
        for (const glm::dvec3& dir : view_directions(f.view.sun_dir, grid.azimuths)) {
            out.push_back(eye + d * dir);
        }
        // Same altitude as the eye: along the sphere through it.
        const double r = f.atmosphere.planet_radius_m;
        const glm::dvec3 centre(0, 0, -r);
        const double angle = d / (r + eye.z);
        const glm::dvec3 from_centre = eye - centre;
        const glm::dvec3 turned(from_centre.x + std::sin(angle) * glm::length(from_centre),
                                from_centre.y, from_centre.z * std::cos(angle));
        out.push_back(centre + glm::length(from_centre) * glm::normalize(turned));
    }
    out.push_back(eye + glm::dvec3(500, 0, -eye.z - 20000));  // far below sea level
    out.push_back(eye + glm::dvec3(0, 0, -eye.z - 3e6));
    return out;
}

/// F_ex, L_in of the program against a double-precision model at one vertex, in 8-bit steps after
/// the exposure and GL's clamp.
struct Lsb {
    int extinction = 0;
    int in_scattering = 0;
};

Lsb lsb_against(const ArbResults& r, const aerial::Scattering<double>& model, float exposure) {
    Lsb out;
    for (int c = 0; c < 3; ++c) {
        const std::size_t i = static_cast<std::size_t>(c);
        out.extinction = std::max(
            out.extinction, lsb_difference(r.color_primary.value[i], float(model.extinction[c])));
        out.in_scattering = std::max(
            out.in_scattering, lsb_difference(r.color_secondary.value[i],
                                              float(double(exposure) * model.in_scattering[c])));
    }
    return out;
}

/// The worst case of a set of vertices, with where it happened.
struct Worst {
    int lsb = 0;
    long vertices = 0;
    long over_one = 0;  ///< vertices off by more than 1 LSB
    std::string where;
    void add(int lsb_here, const std::string& here) {
        ++vertices;
        if (lsb_here > 1) ++over_one;
        if (lsb_here > lsb) {
            lsb = lsb_here;
            where = here;
        }
    }
    double percent_over_one() const {
        return vertices ? 100.0 * double(over_one) / double(vertices) : 0;
    }
};

/// Everything the grid tests need of one view: the float frame for the program, the double
/// frame for the model, the vertices, and an exposure that maps the brightest L_in of the CPU
/// model over the vertices to display white (the hardest exposure for absolute errors).
struct Case {
    std::string name;
    View view;
    Frame<float> frame;
    std::vector<glm::dvec3> vertices;
    std::vector<aerial::Scattering<double>> cpu;
    float exposure = 1.0f;
};

/// The CPU model of a case: with its higher orders for the multiple_scattering level, without
/// them (Frame::multiple_scattering reset) for the levels below it.
Case make_case(const std::string& preset_name, const glm::dvec3& eye, double sun_elevation_deg,
               const Grid& grid, bool multiple_scattering) {
    Case k;
    k.name = preset_name;
    const Atmosphere a = preset(preset_name);
    k.view = view_for(eye, direction(sun_elevation_deg, 30));
    k.frame = frame_for(a, k.view);
    auto fd = aerial::prepare_frame<double>(a, k.view, Model::height);
    EXPECT_TRUE(fd.ok());
    aerial::Frame<double> cpu_frame = fd.ok() ? *fd : aerial::Frame<double>{};
    if (!multiple_scattering) cpu_frame.multiple_scattering.reset();
    k.vertices = vertices_for(grid, k.frame);
    double brightest = 0.0;
    for (const glm::dvec3& v : k.vertices) {
        k.cpu.push_back(aerial::scatter(cpu_frame, v));
        for (int c = 0; c < 3; ++c) brightest = std::max(brightest, k.cpu.back().in_scattering[c]);
    }
    k.exposure = brightest > 0.0 ? float(1.0 / brightest) : 1.0f;
    return k;
}

/// Calls VISIT with the case of each of PRESETS, GRID's eyes and its sun elevations, in that
/// order; none after a fatal failure.
template <class Visit>
void for_each_case(const std::vector<std::string>& presets, const Grid& grid, Visit visit,
                   bool multiple_scattering = false) {
    for (const std::string& name : presets) {
        for (const glm::dvec3& eye : grid.eyes) {
            for (double sun : grid.sun_elevations) {
                if (::testing::Test::HasFatalFailure()) return;
                visit(make_case(name, eye, sun, grid, multiple_scattering));
            }
        }
    }
}

std::string describe(const Case& k, const glm::dvec3& vertex) {
    const glm::dvec3 d = vertex - k.view.eye;
    char buffer[200];
    std::snprintf(buffer, sizeof buffer, "%s eye z=%g sun %.0f deg, vertex at d=(%.0f, %.0f, %.0f)",
                  k.name.c_str(), k.view.eye.z,
                  std::asin(std::clamp(k.view.sun_dir.z, -1.0, 1.0)) / kDegree, d.x, d.y, d.z);
    return buffer;
}

aerial::validation::ArbCpuProgram program(const ArbProgramOptions& o = {}) {
    return parse(generate(options(o)).text);
}

}  // namespace height
}  // namespace

/// The height program against the CPU height model (double) over height::Grid, exposure from
/// height::make_case: F_ex everywhere, L_in by preset and ray length with the sun >= 5 deg. The
/// L_in figures are regression bounds measured with this program, not targets:
/// docs/arb-program.md's
/// section says where and why it departs from the CPU model.
constexpr int kHeightExtinctionLsb = 1;
struct HeightInScatteringBound {
    const char* preset;
    int rays_to_1km_lsb;
    int rays_to_30km_lsb;
};
constexpr HeightInScatteringBound kHeightInScatteringLsb[] = {
    {"earth", 1, 12}, {"hp2002", 1, 27}, {"hazy", 1, 29}, {"foggy", 6, 201}, {"mars", 1, 2}};

TEST(ArbHeightProgram, FitsTheSpecMinimumsWithUpToFourTextureUnitsOrTheModelMatrix) {
    const aerial::ArbProgram p = generate(height::options());
    std::printf(
        "[ info     ] height program: %d instructions, %d temporaries, %d parameters "
        "(%d program parameters), %d attributes\n",
        p.instruction_count, p.resources.temporaries, p.resources.parameters,
        aerial::kArbHeightParameterCount, p.resources.attributes);
    EXPECT_LE(p.instruction_count, 128);
    EXPECT_LE(p.resources.temporaries, 12);
    EXPECT_LE(p.resources.parameters, 96);
    EXPECT_EQ(p.text.rfind("!!ARBvp1.0\n", 0), 0u);
    EXPECT_EQ(p.text.substr(p.text.size() - 4), "END\n");
    ArbProgramOptions o = height::options();
    o.texcoord_units = 4;
    EXPECT_TRUE(aerial::generate_arb_program(o).ok()) << "four texture units fit";
    o.position_invariant = true;
    EXPECT_TRUE(aerial::generate_arb_program(o).ok()) << "four texture units, position invariant";
    o.texcoord_units = 5;
    const auto too_many = aerial::generate_arb_program(o);
    ASSERT_FALSE(too_many.ok()) << "five units exceed the 124 instructions left";
    EXPECT_EQ(too_many.error().field, "instructions");
    // Model-space vertices: 3 DP4 more, which one texture unit still leaves within 128.
    ArbProgramOptions model = height::options();
    model.model_matrix = true;
    const aerial::ArbProgram m = generate(model);
    EXPECT_EQ(m.instruction_count, p.instruction_count + 3);
    EXPECT_LE(m.instruction_count, 128);
    model.texcoord_units = 2;
    const auto two = aerial::generate_arb_program(model);
    ASSERT_FALSE(two.ok()) << "the model matrix and two units exceed 128 instructions";
    EXPECT_EQ(two.error().message,
              "aerial::generate_arb_program(): instructions: expected at most 128 "
              "(MAX_PROGRAM_INSTRUCTIONS_ARB), got 129 in the program");
    // The 2002 program is unchanged by the height model's arrival.
    EXPECT_EQ(generate().instruction_count, 22);
}

TEST(ArbHeightProgram, ReadsEveryDocumentedParameterAndNothingElse) {
    ASSERT_NO_FATAL_FAILURE(
        expect_reads_exactly_its_parameters(height::options(), aerial::kArbHeightParameterCount,
                                            {0, 5, 96 - aerial::kArbHeightParameterCount}));
    ArbProgramOptions beyond = height::options();
    beyond.parameter_base = 96 - aerial::kArbHeightParameterCount + 1;
    const auto r = aerial::generate_arb_program(beyond);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "parameter_base");

    // Every component the program reads matters: changing it changes an output at one of a few
    // vertices (a long ray, one at the eye's altitude, one far below sea level, where the clamps
    // act). Only eyealt.w (parameter 5) and, at the spec_minimum level, ray.w and mie.w
    // (9, 10) and the slopes' w (13, 14) are documented as unused; extr.w and extm.w keep the
    // secondary alpha at 0. (NaN would not do: MIN and MAX may drop it, and some of the reads are
    // clamps.)
    const Frame<float> f =
        height::frame_for(preset("hazy"), height::view_for({0, 0, 200}, direction(20, 0)));
    const Params p = height::parameters(f, 8.0f);
    ASSERT_EQ(p.size(), std::size_t(aerial::kArbHeightParameterCount));
    const auto program = height::program();
    const std::vector<glm::vec3> vertices{
        {0, 0, 200}, {4000, 2500, 900}, {60000, 1000, 0}, {3000, 0, 199.3f}, {500, 0, -30000}};
    const auto outputs = [&](const Params& q) {
        std::vector<float> out;
        for (const glm::vec3& v : vertices) {
            const ArbResults run =
                aerial::validation::run_arb_program(program, machine_with(q), vertex_at(v));
            for (std::size_t c = 0; c < 4; ++c) {
                out.push_back(run.color_primary.value[c]);
                out.push_back(run.color_secondary.value[c]);
            }
            out.push_back(run.fogcoord.value[0]);
        }
        return out;
    };
    const std::vector<float> clean = outputs(p);
    for (float x : clean) ASSERT_TRUE(std::isfinite(x));
    for (std::size_t i = 0; i < p.size(); ++i) {
        for (std::size_t j = 0; j < 4; ++j) {
            Params changed = p;
            changed[i][j] = p[i][j] == 0.0f ? 0.5f : p[i][j] * 1.5f;
            const bool unused = j == 3 && (i == 5 || i == 9 || i == 10 || i == 13 || i == 14);
            if (unused) {
                EXPECT_EQ(outputs(changed), clean)
                    << "parameter " << i << ".w is documented as unused";
            } else {
                EXPECT_NE(outputs(changed), clean)
                    << "parameter " << i << " component " << j << " is not read";
            }
        }
    }
}

TEST(ArbHeightProgram, OptionsChangeOnlyWhereParametersComeFromAndWhatIsPassedThrough) {
    const Frame<float> f =
        height::frame_for(preset("earth"), height::view_for({30, -20, 400}, direction(15, 40)));
    const Params p = height::parameters(f, 6.0f);
    const auto reference = height::program();
    aerial::validation::ArbVertex v = vertex_at({3000, 9000, 150});
    v.texcoord[0] = {0.25f, 0.5f, 0, 1};
    v.texcoord[1] = {1, 2, 3, 4};
    const ArbResults base = aerial::validation::run_arb_program(reference, machine_with(p), v);
    EXPECT_EQ(base.position.written, 0xfu);
    EXPECT_EQ(base.color_primary.written, 0xfu);
    EXPECT_EQ(base.color_secondary.written, 0xfu);
    EXPECT_EQ(base.fogcoord.written & 1u, 1u);
    EXPECT_EQ(base.texcoord[0].value, v.texcoord[0]);
    EXPECT_EQ(base.texcoord[1].written, 0u);
    EXPECT_EQ(base.color_primary.value[3], 1.0f) << "primary alpha";
    EXPECT_EQ(base.color_secondary.value[3], 0.0f) << "secondary alpha";
    for (auto space : {aerial::ParameterSpace::local, aerial::ParameterSpace::env}) {
        for (int base_index : {0, 40}) {
            ArbProgramOptions o;
            o.parameter_space = space;
            o.parameter_base = base_index;
            o.texcoord_units = 2;
            const ArbResults r = aerial::validation::run_arb_program(
                height::program(o), machine_with(p, height::options(o)), v);
            EXPECT_EQ(r.color_primary.value, base.color_primary.value);
            EXPECT_EQ(r.color_secondary.value, base.color_secondary.value);
            EXPECT_EQ(r.fogcoord.value[0], base.fogcoord.value[0]);
            EXPECT_EQ(r.texcoord[1].value, v.texcoord[1]);
        }
    }
    ArbProgramOptions invariant;
    invariant.position_invariant = true;
    const aerial::ArbProgram text = generate(height::options(invariant));
    EXPECT_EQ(text.instruction_count, generate(height::options()).instruction_count - 4);
    const ArbResults r = aerial::validation::run_arb_program(parse(text.text), machine_with(p), v);
    EXPECT_EQ(r.position.written, 0u);
    EXPECT_EQ(r.color_secondary.value, base.color_secondary.value);
}

TEST(ArbHeightProgramParameters, RejectFramesOfAnotherModel) {
    const View view = height::view_for({0, 0, 10}, direction(30, 0));
    const auto hp = aerial::prepare_frame<float>(Atmosphere{}, view, Model::hoffman_preetham);
    ASSERT_TRUE(hp.ok());
    const auto r = aerial::arb_program_parameters(*hp, Display{}, height::options());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().field, "frame.model");
    EXPECT_NE(r.error().message.find("height"), std::string::npos) << r.error().message;
    Display exponential;
    exponential.tone = aerial::ToneCurve::exponential;
    const auto e = aerial::arb_program_parameters(height::frame_for(Atmosphere{}, view),
                                                  exponential, height::options());
    ASSERT_FALSE(e.ok());
    EXPECT_EQ(e.error().field, "display.tone");
}

TEST(ArbHeightProgram, ExtinctionMatchesTheCpuModelWithin1LsbOverTheWholeGrid) {
    const auto program = height::program();
    const height::Grid grid;
    height::Worst worst;
    height::for_each_case(aerial::atmosphere_preset_names(), grid, [&](const height::Case& k) {
        const aerial::validation::ArbMachine m =
            machine_with(height::parameters(k.frame, k.exposure));
        for (std::size_t i = 0; i < k.vertices.size(); ++i) {
            const ArbResults r = aerial::validation::run_arb_program(
                program, m, vertex_at(glm::vec3(k.vertices[i])));
            worst.add(height::lsb_against(r, k.cpu[i], k.exposure).extinction,
                      height::describe(k, k.vertices[i]));
        }
    });
    std::printf(
        "[ info     ] height program F_ex vs CPU height model (double), %ld vertices: max "
        "%d LSB\n",
        worst.vertices, worst.lsb);
    EXPECT_LE(worst.lsb, kHeightExtinctionLsb) << worst.where;
}

TEST(ArbHeightProgram, InScatteringMatchesTheCpuModelOnShortRaysAndStaysCloseInClearAir) {
    // Against the CPU model in double, per preset, by ray length, with the sun at least 5 deg up
    // (sunlit segments; twilight below). The program's quadrature drops the model's correction
    // of the weights by the exact optical depth, so it departs where two components with very
    // different scale heights both carry optical depth (rays leaving or entering a haze layer)
    // and on long rays; it keeps the eye's sun column factors along the segment.
    const auto program = height::program();
    height::Grid grid;
    grid.sun_elevations = {5, 10, 20, 45, 90};
    const double lengths[] = {1e3, 3.1e4, 1e9};
    const char* length_names[] = {"<= 1 km", "<= 30 km", "> 30 km"};
    for (const std::string& name : aerial::atmosphere_preset_names()) {
        height::Worst by_length[3];
        height::for_each_case({name}, grid, [&](const height::Case& k) {
            const aerial::validation::ArbMachine m =
                machine_with(height::parameters(k.frame, k.exposure));
            for (std::size_t i = 0; i + 2 < k.vertices.size(); ++i) {  // not the deep ones
                const ArbResults r = aerial::validation::run_arb_program(
                    program, m, vertex_at(glm::vec3(k.vertices[i])));
                const double d = glm::length(k.vertices[i] - k.view.eye);
                const int b = d <= lengths[0] ? 0 : d <= lengths[1] ? 1 : 2;
                by_length[b].add(height::lsb_against(r, k.cpu[i], k.exposure).in_scattering,
                                 height::describe(k, k.vertices[i]));
            }
        });
        for (int b = 0; b < 3; ++b) {
            std::printf(
                "[ info     ] height L_in vs CPU, %-6s rays %-8s: max %3d LSB, %5.1f%% of "
                "vertices > 1 LSB (worst: %s)\n",
                name.c_str(), length_names[b], by_length[b].lsb, by_length[b].percent_over_one(),
                by_length[b].where.c_str());
        }
        for (const HeightInScatteringBound& bound : kHeightInScatteringLsb) {
            if (name != bound.preset) continue;
            EXPECT_LE(by_length[0].lsb, bound.rays_to_1km_lsb) << by_length[0].where;
            EXPECT_LE(by_length[1].lsb, bound.rays_to_30km_lsb) << by_length[1].where;
        }
    }
}

/// Regression bounds of the program's L_in against the reference model, measured (the CPU height
/// model's own figures on the same set are 56, 29, 157 and 5 LSB).
struct HeightReferenceBound {
    const char* preset;
    int lsb;
};
constexpr HeightReferenceBound kHeightReferenceLsb[] = {
    {"earth", 56}, {"hazy", 35}, {"foggy", 215}, {"mars", 28}};

TEST(ArbHeightProgram, AgainstTheReferenceModelItErrsLikeTheCpuHeightModel) {
    // Error against the `reference` integrator, for the program and for the CPU height model, at
    // the same exposure: where the program departs from the CPU model, how far is either from
    // the truth? Eyes up to 10 km, rays up to 30 km, sun 5 to 60 deg.
    const auto program = height::program();
    ArbProgramOptions exact_options;
    exact_options.height_fidelity = aerial::ArbHeightFidelity::exact_optical_depth;
    exact_options.limits.max_instructions = 256;
    const auto exact = height::program(exact_options);
    height::Grid grid;
    grid.eyes = {{0, 0, 2}, {0, 0, 1000}, {0, 0, 10000}};
    grid.distances = {1e3, 1e4, 3e4};
    grid.azimuths = 2;
    grid.sun_elevations = {5.0, 20.0, 60.0};
    for (const char* name : {"earth", "hazy", "foggy", "mars"}) {
        height::Worst arb, cpu, arb_exact;
        height::for_each_case({name}, grid, [&](const height::Case& k) {
            const aerial::validation::ArbMachine m =
                machine_with(height::parameters(k.frame, k.exposure));
            for (std::size_t i = 0; i + 2 < k.vertices.size(); ++i) {
                const aerial::Scattering<double> truth =
                    aerial::reference_scattering(preset(name), k.view, k.vertices[i]);
                const ArbResults r = aerial::validation::run_arb_program(
                    program, m, vertex_at(glm::vec3(k.vertices[i])));
                int model = 0;
                for (int c = 0; c < 3; ++c) {
                    model = std::max(model,
                                     lsb_difference(float(k.exposure * k.cpu[i].in_scattering[c]),
                                                    float(k.exposure * truth.in_scattering[c])));
                }
                const std::string where = height::describe(k, k.vertices[i]);
                arb.add(height::lsb_against(r, truth, k.exposure).in_scattering, where);
                const ArbResults e = aerial::validation::run_arb_program(
                    exact, m, vertex_at(glm::vec3(k.vertices[i])));
                arb_exact.add(height::lsb_against(e, truth, k.exposure).in_scattering, where);
                cpu.add(model, where);
            }
        });
        std::printf(
            "[ info     ] L_in vs reference, %-6s %ld vertices: program max %3d LSB (%5.1f%% "
            "> 1), with exact optical depth %3d LSB (%5.1f%% > 1), CPU height model max %3d LSB "
            "(%5.1f%% > 1); program worst at %s\n",
            name, arb.vertices, arb.lsb, arb.percent_over_one(), arb_exact.lsb,
            arb_exact.percent_over_one(), cpu.lsb, cpu.percent_over_one(), arb.where.c_str());
        for (const HeightReferenceBound& bound : kHeightReferenceLsb) {
            if (std::string(name) == bound.preset) {
                EXPECT_LE(arb.lsb, bound.lsb) << arb.where;
            }
        }
    }
}

TEST(ArbHeightProgram, StaysFiniteForDegenerateViews) {
    // Eye at the vertex, horizontal rays, vertices far below sea level (density clamped as the CPU
    // model clamps it) and very far away, the sun below the horizon, channels without extinction,
    // backward Mie scattering, other engine units: every output finite, F_ex in [0, 1], L_in >= 0.
    Atmosphere dark = preset("earth");
    dark.rayleigh_scattering.x = 0.0;
    dark.mie_scattering = glm::dvec3(0.0);
    Atmosphere backward = preset("hazy");
    backward.mie_g = -0.7;
    std::vector<std::pair<std::string, Atmosphere>> atmospheres;
    for (const std::string& name : aerial::atmosphere_preset_names()) {
        atmospheres.emplace_back(name, preset(name));
    }
    atmospheres.emplace_back("no red, no Mie", dark);
    atmospheres.emplace_back("g < 0", backward);
    const auto program = height::program();
    long checked = 0;
    for (const auto& [name, a] : atmospheres) {
        for (double meters_per_unit : {1.0, 0.01, 1000.0}) {
            for (const glm::dvec3& eye_m : {glm::dvec3(0, 0, 0), glm::dvec3(10, 20, 2),
                                            glm::dvec3(0, 0, -4000), glm::dvec3(0, 0, 100000)}) {
                for (double sun : {-90.0, -10.0, -0.5, 0.0, 0.5, 30.0, 90.0}) {
                    const glm::dvec3 eye = eye_m / meters_per_unit;
                    const View view = height::view_for(eye, direction(sun, 70), meters_per_unit);
                    const Frame<float> f = height::frame_for(a, view);
                    for (float exposure : {1.0f, 1e4f}) {
                        const aerial::validation::ArbMachine m =
                            machine_with(height::parameters(f, exposure));
                        std::vector<glm::dvec3> offsets_m{
                            {0, 0, 0},   {1e-3, 0, 0},   {5000, 0, 0},
                            {3e5, 1, 0}, {0, 0, -20000}, {700, 0, -3e6},
                            {1e9, 0, 0}, {0, 0, 1e9},    {-3e4, 2e4, -eye_m.z}};
                        for (const glm::dvec3& offset : offsets_m) {
                            const glm::vec3 v = glm::vec3(eye + offset / meters_per_unit);
                            const ArbResults r =
                                aerial::validation::run_arb_program(program, m, vertex_at(v));
                            ++checked;
                            const std::string where =
                                name + " mpu " + std::to_string(meters_per_unit) + " eye z " +
                                std::to_string(eye_m.z) + " sun " + std::to_string(sun) +
                                " offset x " + std::to_string(offset.x) + " z " +
                                std::to_string(offset.z);
                            ASSERT_TRUE(all_finite(r.color_primary.value) &&
                                        all_finite(r.color_secondary.value) &&
                                        all_finite(r.fogcoord.value, 1) &&
                                        all_finite(r.position.value))
                                << where;
                            for (std::size_t c = 0; c < 3; ++c) {
                                ASSERT_GE(r.color_primary.value[c], 0.0f) << where;
                                ASSERT_LE(r.color_primary.value[c], 1.0f) << where;
                                ASSERT_GE(r.color_secondary.value[c], 0.0f) << where;
                            }
                            // At the eye F_ex = 1 and L_in = 0 exactly, except where the
                            // density clamp makes beta so large (foggy, 4 km below sea level:
                            // 1e8 /m) that the 2^-20 m the program keeps |d| from 0 is opaque.
                            if (offset == glm::dvec3(0.0) && eye_m.z >= 0.0) {
                                for (std::size_t c = 0; c < 3; ++c) {
                                    EXPECT_EQ(r.color_primary.value[c], 1.0f) << where;
                                    EXPECT_EQ(r.color_secondary.value[c], 0.0f) << where;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    std::printf("[ info     ] height program finite at %ld degenerate vertices\n", checked);
}

TEST(ArbHeightProgram, ReportsItsErrorWithOldHardwarePrecision) {
    // 2^-11 on every approximate instruction (RSQ, RCP, EX2, LG2, POW), 48 seeded sign patterns
    // per vertex (the program has too many approximate instructions for all of them). The
    // program is not robust to it: F_ex is from exact_optical_depth on (phi from its series below
    // 0.25; spec_minimum takes the quotient alone and needs an exact EX2 on nearly level rays), but
    // the node placement divides log2(1 + f (2^-b - 1)) by b, which an absolute error of 2^-11 in
    // LG2 (or a relative one in EX2) swamps when the two ends of the segment have nearly the same
    // extinction (|b| << 1), and L_in = (1 - F_ex)/beta cancels near the eye as in the 2002
    // program. Figures printed; F_ex asserted.
    for (auto level :
         {aerial::ArbHeightFidelity::spec_minimum, aerial::ArbHeightFidelity::exact_optical_depth,
          aerial::ArbHeightFidelity::full}) {
        const ArbProgramOptions o = at_fidelity(level);
        const auto program = parse(generate(o).text);
        const int approx = aerial::validation::count_approximate_instructions(program);
        height::Grid grid;
        grid.eyes = {{0, 0, 2}, {0, 0, 1000}};
        grid.sun_elevations = {10, 45};
        grid.distances = {10, 1e3, 1e4, 3e4};
        grid.azimuths = 2;
        std::uint32_t seed = 12345u;
        const auto next = [&] {
            seed = seed * 1664525u + 1013904223u;
            return seed;
        };
        height::Worst fex, fex_exact, lin, lin_exact;
        aerial::testing::GridSample sample("vertices");
        height::for_each_case(aerial::atmosphere_preset_names(), grid, [&](const height::Case& k) {
            const aerial::validation::ArbMachine m =
                machine_with(::parameters(k.frame, k.exposure, o));
            for (std::size_t i = 0; i + 2 < k.vertices.size(); ++i) {
                if (!sample.keep()) continue;
                const aerial::validation::ArbVertex v = vertex_at(glm::vec3(k.vertices[i]));
                const height::Lsb exact = height::lsb_against(
                    aerial::validation::run_arb_program(program, m, v), k.cpu[i], k.exposure);
                height::Lsb worst;
                for (int pattern = 0; pattern < 48; ++pattern) {
                    aerial::validation::ArbInterpreterOptions rounding;
                    rounding.relative_error = kOldHardwareError;
                    rounding.sign_pattern = pattern == 0 ? 0u : pattern == 1 ? ~0u : next();
                    const height::Lsb e = height::lsb_against(
                        aerial::validation::run_arb_program(program, m, v, rounding), k.cpu[i],
                        k.exposure);
                    worst.extinction = std::max(worst.extinction, e.extinction);
                    worst.in_scattering = std::max(worst.in_scattering, e.in_scattering);
                }
                const std::string where = height::describe(k, k.vertices[i]);
                fex.add(worst.extinction, where);
                fex_exact.add(exact.extinction, where);
                lin.add(worst.in_scattering, where);
                lin_exact.add(exact.in_scattering, where);
            }
        });
        std::printf(
            "[ info     ] height program (%s) with 2^-11 on its %d approximate instructions, %ld "
            "vertices: F_ex max %d LSB; L_in max %d LSB (%.1f%% > 1 LSB; unperturbed: max %d, "
            "%.1f%% > 1), worst at %s\n",
            aerial::arb_height_fidelity_name(level), approx, lin.vertices, fex.lsb, lin.lsb,
            lin.percent_over_one(), lin_exact.lsb, lin_exact.percent_over_one(), lin.where.c_str());
        EXPECT_LE(fex_exact.lsb, 1) << fex_exact.where;
        // spec_minimum takes phi from its quotient alone, which a 2^-11 EX2 swamps on nearly
        // level rays; the higher levels use its series there.
        if (level != aerial::ArbHeightFidelity::spec_minimum) {
            EXPECT_LE(fex.lsb, 1) << fex.where;
        }
    }
}

/// Regression bounds of the exact_optical_depth level against the CPU model, measured like
/// kHeightInScatteringLsb (rays up to 30 km; the first column is unused).
constexpr HeightInScatteringBound kHeightExactInScatteringLsb[] = {
    {"earth", 0, 1}, {"hp2002", 0, 1}, {"hazy", 0, 1}, {"foggy", 0, 18}, {"mars", 0, 1}};

TEST(ArbHeightProgram, ExactOpticalDepthOptionWeightsThePointsLikeTheCpuModel) {
    // Beyond the spec minimum: at the exact_optical_depth level the weights carry exp(tau_fit -
    // tau) like the model's; what remains is the eye's sun column along the segment and the
    // missing per-point shadow. Sun >= 5 deg, rays up to 30 km, per preset.
    ArbProgramOptions exact;
    exact.height_fidelity = aerial::ArbHeightFidelity::exact_optical_depth;
    exact.limits.max_instructions = 256;  // Direct3D 9-class native limit
    const aerial::ArbProgram text = generate(height::options(exact));
    std::printf(
        "[ info     ] height program with exact optical depth: %d instructions, %d "
        "temporaries\n",
        text.instruction_count, text.resources.temporaries);
    // 23 for the correction, 4 for phi's series, 7 for each channel's own attenuation to the
    // points, less 2 where that replaces the per-channel path factor.
    EXPECT_EQ(text.instruction_count, generate(height::options()).instruction_count + 34);
    EXPECT_LE(text.resources.temporaries, 12);
    ArbProgramOptions at_minimum;
    at_minimum.height_fidelity = aerial::ArbHeightFidelity::exact_optical_depth;
    const auto rejected = aerial::generate_arb_program(height::options(at_minimum));
    ASSERT_FALSE(rejected.ok()) << "beyond 128 instructions";
    EXPECT_EQ(rejected.error().field, "instructions");

    const auto with = parse(text.text);
    const auto without = height::program();
    height::Grid grid;
    grid.sun_elevations = {5, 10, 20, 45, 90};
    for (const std::string& name : aerial::atmosphere_preset_names()) {
        height::Worst exact_worst, default_worst;
        height::for_each_case({name}, grid, [&](const height::Case& k) {
            const aerial::validation::ArbMachine m =
                machine_with(height::parameters(k.frame, k.exposure));
            for (std::size_t i = 0; i + 2 < k.vertices.size(); ++i) {
                if (glm::length(k.vertices[i] - k.view.eye) > 3.1e4) continue;
                const aerial::validation::ArbVertex v = vertex_at(glm::vec3(k.vertices[i]));
                const std::string where = height::describe(k, k.vertices[i]);
                const ArbResults a = aerial::validation::run_arb_program(with, m, v);
                ASSERT_TRUE(all_finite(a.color_secondary.value)) << where;
                exact_worst.add(height::lsb_against(a, k.cpu[i], k.exposure).in_scattering, where);
                default_worst.add(
                    height::lsb_against(aerial::validation::run_arb_program(without, m, v),
                                        k.cpu[i], k.exposure)
                        .in_scattering,
                    where);
            }
        });
        std::printf(
            "[ info     ] L_in vs CPU, %-6s rays <= 30 km: exact optical depth max %3d "
            "LSB (%4.1f%% > 1), default max %3d LSB (%4.1f%% > 1); worst at %s\n",
            name.c_str(), exact_worst.lsb, exact_worst.percent_over_one(), default_worst.lsb,
            default_worst.percent_over_one(), exact_worst.where.c_str());
        EXPECT_LE(exact_worst.lsb, default_worst.lsb) << exact_worst.where;
        for (const HeightInScatteringBound& bound : kHeightExactInScatteringLsb) {
            if (name == bound.preset) {
                EXPECT_LE(exact_worst.lsb, bound.rays_to_30km_lsb) << exact_worst.where;
            }
        }
    }
}

// ---- The height program's fidelity levels ----------------------------------------------------

namespace {

/// A level's program (at_fidelity) run by the executor against the CPU height model (double)
/// over height::Grid, every preset: the worst F_ex and L_in, printed. The CPU model has its higher
/// orders for the multiple_scattering level and not for the others.
std::pair<height::Worst, height::Worst> level_against_cpu(aerial::ArbHeightFidelity level) {
    const ArbProgramOptions o = at_fidelity(level);
    const aerial::ArbProgram text = generate(o);
    const char* name = aerial::arb_height_fidelity_name(level);
    std::printf("[ info     ] %s height program: %d instructions, %d temporaries, %d parameters\n",
                name, text.instruction_count, text.resources.temporaries,
                text.resources.parameters);
    const auto program = parse(text.text);
    height::Worst fex, lin;
    height::for_each_case(
        aerial::atmosphere_preset_names(), height::Grid{},
        [&](const height::Case& k) {
            const aerial::validation::ArbMachine m =
                machine_with(::parameters(k.frame, k.exposure, o));
            for (std::size_t i = 0; i < k.vertices.size(); ++i) {
                const ArbResults r = aerial::validation::run_arb_program(
                    program, m, vertex_at(glm::vec3(k.vertices[i])));
                const height::Lsb e = height::lsb_against(r, k.cpu[i], k.exposure);
                const std::string where = height::describe(k, k.vertices[i]);
                fex.add(e.extinction, where);
                lin.add(e.in_scattering, where);
            }
        },
        level == aerial::ArbHeightFidelity::multiple_scattering);
    std::printf(
        "[ info     ] %s height program vs CPU height model (double), %ld vertices: F_ex max %d "
        "LSB, L_in max %d LSB (%.3f%% > 1), worst at %s\n",
        name, lin.vertices, fex.lsb, lin.lsb, lin.percent_over_one(), lin.where.c_str());
    return {fex, lin};
}

}  // namespace

TEST(ArbHeightProgram, FullFidelityMatchesTheCpuModelWithin1LsbOverTheWholeGrid) {
    // All of the model's single scattering: every preset, eyes 2 m to 30 km, the sun from -10 to
    // 90 deg (twilight, the planet's shadow), rays from 1 m to 150 km and vertices far below sea
    // level, against the CPU model without its higher orders.
    const auto [fex, lin] = level_against_cpu(aerial::ArbHeightFidelity::full);
    EXPECT_LE(fex.lsb, 1) << fex.where;
    EXPECT_LE(lin.lsb, 1) << lin.where;
}

TEST(ArbHeightProgram, MultipleScatteringLevelMatchesTheCpuModelWithin1LsbOverTheWholeGrid) {
    // The whole CPU model, its higher orders included (the slice read through ARL).
    const auto [fex, lin] = level_against_cpu(aerial::ArbHeightFidelity::multiple_scattering);
    EXPECT_LE(fex.lsb, 1) << fex.where;
    // Measured: 2 LSB at 1 vertex of 111240 (foggy, a sun 3 deg below the horizon, a ray of
    // 150 km), the float program's table coordinates against the double model's.
    EXPECT_LE(lin.lsb, 2) << lin.where;
    EXPECT_LT(lin.percent_over_one(), 0.01) << lin.where;
}

TEST(ArbHeightFidelity, AutomaticTakesTheHighestLevelTheLimitsAcceptAndFallsBack) {
    using aerial::ArbHeightFidelity;
    const int exact =
        generate(at_fidelity(ArbHeightFidelity::exact_optical_depth)).instruction_count;
    const aerial::ArbProgram full_program = generate(at_fidelity(ArbHeightFidelity::full));
    const int full = full_program.instruction_count;
    ASSERT_LT(128, exact);
    ASSERT_LT(exact, full);
    ASSERT_LE(full, 256) << "fits Direct3D 9-class native limits";
    EXPECT_LE(full_program.resources.temporaries, 12);
    // Simulated driver limits: each level where it fits, the next lower one a step below.
    const struct {
        int max_instructions;
        int max_temporaries;
        ArbHeightFidelity expected;
    } cases[] = {{128, 12, ArbHeightFidelity::spec_minimum},
                 {exact - 1, 12, ArbHeightFidelity::spec_minimum},
                 {exact, 12, ArbHeightFidelity::exact_optical_depth},
                 {full - 1, 12, ArbHeightFidelity::exact_optical_depth},
                 {full, 12, ArbHeightFidelity::full},
                 {16384, 11, ArbHeightFidelity::exact_optical_depth},
                 {16384, 10, ArbHeightFidelity::spec_minimum}};
    for (const auto& c : cases) {
        ArbProgramOptions o = height::options();
        o.limits.max_instructions = c.max_instructions;
        o.limits.max_temporaries = c.max_temporaries;
        const std::string where = std::to_string(c.max_instructions) + " instructions, " +
                                  std::to_string(c.max_temporaries) + " temporaries";
        EXPECT_EQ(aerial::resolve_arb_height_fidelity(o), c.expected) << where;
        const auto p = aerial::generate_arb_program(o);
        if (c.max_temporaries < 11) {
            ASSERT_FALSE(p.ok()) << where << ": not even the smallest level fits";
            EXPECT_EQ(p.error().field, "temporaries");
            continue;
        }
        ASSERT_TRUE(p.ok()) << where << ": " << p.error().message;
        EXPECT_EQ(p->options.height_fidelity, c.expected) << where << ": reports its choice";
        ArbProgramOptions explicit_level = o;
        explicit_level.height_fidelity = c.expected;
        EXPECT_EQ(p->text, generate(explicit_level).text) << where;
        EXPECT_EQ(aerial::arb_parameter_count(o), aerial::arb_parameter_count(p->options));
    }
    // Position invariance frees 4 instructions of the limit's... and takes 4 from it.
    ArbProgramOptions invariant = height::options();
    invariant.position_invariant = true;
    invariant.limits.max_instructions = full;
    EXPECT_EQ(aerial::resolve_arb_height_fidelity(invariant), ArbHeightFidelity::full);
    // Parameters: 17 for full, 15 below; the index range limits the choice too.
    EXPECT_EQ(aerial::arb_parameter_count(at_fidelity(ArbHeightFidelity::full)),
              aerial::kArbHeightFullParameterCount);
    EXPECT_EQ(aerial::arb_parameter_count(at_fidelity(ArbHeightFidelity::exact_optical_depth)),
              aerial::kArbHeightParameterCount);
    ArbProgramOptions high_base = height::options();
    high_base.limits.max_instructions = 256;
    high_base.parameter_base = 96 - aerial::kArbHeightParameterCount;
    EXPECT_EQ(aerial::resolve_arb_height_fidelity(high_base),
              ArbHeightFidelity::exact_optical_depth)
        << "full's 17 parameters do not fit above index 81";
    // An explicit level beyond the limits is an error naming the limit, not a silent fallback.
    ArbProgramOptions forced = height::options();
    forced.height_fidelity = ArbHeightFidelity::full;
    const auto refused = aerial::generate_arb_program(forced);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().field, "instructions");
    // Names.
    for (ArbHeightFidelity f : {ArbHeightFidelity::automatic, ArbHeightFidelity::spec_minimum,
                                ArbHeightFidelity::exact_optical_depth, ArbHeightFidelity::full,
                                ArbHeightFidelity::multiple_scattering}) {
        const auto parsed = aerial::parse_arb_height_fidelity(aerial::arb_height_fidelity_name(f));
        ASSERT_TRUE(parsed.ok());
        EXPECT_EQ(*parsed, f);
    }
    const auto unknown = aerial::parse_arb_height_fidelity("fullest");
    ASSERT_FALSE(unknown.ok());
    EXPECT_EQ(unknown.error().field, "height_fidelity");
    EXPECT_EQ(unknown.error().message,
              "aerial::parse_arb_height_fidelity(): height_fidelity: expected one of automatic, "
              "spec-minimum, exact-optical-depth, full, multiple-scattering, got 'fullest'");
}

TEST(ArbHeightFidelity, EachLevelGetsItsOwnParameters) {
    // The parameters follow the level: 17 vectors for full, its eye column factors are not
    // capped, and eyealt.w says whether the sun reaches the eye; asking for automatic resolves
    // like generate_arb_program.
    const Frame<float> f =
        height::frame_for(preset("earth"), height::view_for({0, 0, 100}, direction(-0.2, 0)));
    const Params spec = ::parameters(f, 4.0f, at_fidelity(aerial::ArbHeightFidelity::spec_minimum));
    const Params full = ::parameters(f, 4.0f, at_fidelity(aerial::ArbHeightFidelity::full));
    ArbProgramOptions automatic = at_fidelity(aerial::ArbHeightFidelity::automatic);
    EXPECT_EQ(spec.size(), std::size_t(aerial::kArbHeightParameterCount));
    EXPECT_EQ(full.size(), std::size_t(aerial::kArbHeightFullParameterCount));
    EXPECT_EQ(::parameters(f, 4.0f, automatic), full);
    EXPECT_EQ(spec[5][3], 0.0f);
    EXPECT_EQ(full[5][3], 1.0f) << "the sun at -0.2 deg still reaches an eye at 100 m";
    EXPECT_FLOAT_EQ(full[12][0], float(f.eye_log_chapman_rayleigh * 1.4426950408889634));
    const Frame<float> night =
        height::frame_for(preset("earth"), height::view_for({0, 0, 100}, direction(-2, 0)));
    const Params blocked = ::parameters(night, 4.0f, at_fidelity(aerial::ArbHeightFidelity::full));
    EXPECT_EQ(blocked[5][3], 0.0f) << "the planet blocks the sun at -2 deg from 100 m";
    EXPECT_EQ(blocked[12][0], 0.0f);
    EXPECT_EQ(blocked[12][1], 0.0f);
}

TEST(ArbHeightFidelity, FullProgramReadsEveryParameterItDocuments) {
    // Changing any component of the 16 vectors changes an output at one of a few vertices (a
    // sunlit view and one at twilight, where the vertex's column and the shadow act), except
    // the fit clamp's z and w, documented as unused (eyealt.w is read at this level).
    const ArbProgramOptions o = at_fidelity(aerial::ArbHeightFidelity::full);
    const auto program = parse(generate(o).text);
    struct ViewCase {
        const char* preset;
        glm::dvec3 eye;
        double sun;
    };
    // Sunlit; twilight (the eye in the planet's shadow, vertices high up still lit, with the
    // sun below their horizon); a ray from 20 km down into the fog layer (the fit's clamp).
    const std::vector<ViewCase> views{
        {"hazy", {0, 0, 200}, 20.0}, {"hazy", {0, 0, 3000}, -3.0}, {"foggy", {0, 0, 20000}, 30.0}};
    const std::vector<glm::vec3> offsets{{0, 0, 0},          {4000, 2500, 900},  {60000, 1000, 0},
                                         {3000, 0, -0.7f},   {500, 0, -30000},   {-90000, 0, 8000},
                                         {-40000, 0, -2000}, {-20000, 0, 20000}, {0, 0, 20000}};
    for (std::size_t i = 0; i < std::size_t(aerial::kArbHeightFullParameterCount); ++i) {
        for (std::size_t j = 0; j < 4; ++j) {
            bool changed_somewhere = false;
            for (const ViewCase& view : views) {
                const glm::dvec3 eye = view.eye;
                const Frame<float> f = height::frame_for(
                    preset(view.preset), height::view_for(eye, direction(view.sun, 0)));
                const Params p = ::parameters(f, 8.0f, o);
                Params changed = p;
                // The fit clamp is a log2 bound: Rayleigh's binds lowered by 200, the fog's
                // stops binding raised by 60.
                changed[i][j] = i == 16           ? p[i][j] + (j == 0 ? -200.0f : 60.0f)
                                : p[i][j] == 0.0f ? 0.5f
                                                  : p[i][j] * 1.5f;
                for (const glm::vec3& offset : offsets) {
                    const glm::vec3 v = glm::vec3(eye) + offset;
                    const ArbResults a =
                        aerial::validation::run_arb_program(program, machine_with(p), vertex_at(v));
                    const ArbResults b = aerial::validation::run_arb_program(
                        program, machine_with(changed), vertex_at(v));
                    changed_somewhere |= a.color_primary.value != b.color_primary.value ||
                                         a.color_secondary.value != b.color_secondary.value ||
                                         a.fogcoord.value[0] != b.fogcoord.value[0];
                }
            }
            const bool unused = i == 16 && j >= 2;
            EXPECT_EQ(changed_somewhere, !unused) << "parameter " << i << " component " << j;
        }
    }
}
