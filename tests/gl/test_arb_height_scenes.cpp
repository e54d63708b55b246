// The height program on the scenes an engine draws: a sky dome of radius 100 km and 1000 km
// around the eye, and a 16 km x 16 km terrain (heights 0..600 m, eye 300..1000 m above sea
// level), earth and hazy, sun 2..90 deg, at the scene default exposure 8 and at
// aerial::auto_exposure's value. The CPU executor of the program text against the CPU height
// model (aerial::scatter<float>), in 8-bit steps after the exposure on F_ex and L_in; and the
// model-space option (ArbProgramOptions::model_matrix) against world-space vertices.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "aerial/aerial.hpp"
#include "aerial/arb_program.hpp"
#include "aerial/validation/arb_executor.hpp"

namespace {

using aerial::ArbHeightFidelity;
using aerial::ArbProgramOptions;
using aerial::Atmosphere;
using aerial::Frame;
using aerial::Model;
using aerial::View;
using Params = std::vector<std::array<float, 4>>;

constexpr double kDegree = aerial::kPi / 180.0;
/// The bound the 128-instruction program keeps on these scenes (F_ex and L_in, RGB).
constexpr int kSceneLsb = 2;
constexpr double kSunElevations[] = {2, 10, 20, 45, 90};
constexpr double kEyeAltitudes[] = {300, 1000};
const char* const kPresets[] = {"earth", "hazy"};

glm::dvec3 direction(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * kDegree, a = azimuth_deg * kDegree;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

/// Dome vertices: eye + r dir, elevations -2..90 deg, every 10 deg of azimuth.
std::vector<glm::dvec3> dome(const glm::dvec3& eye, double r) {
    std::vector<glm::dvec3> out;
    for (double e : {-2.0, -1.0, -0.5, 0.0, 0.5, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0,
                     45.0, 60.0, 75.0, 89.0, 90.0}) {
        for (int a = 0; a < 36; ++a) out.push_back(eye + r * direction(e, 10.0 * a + 3.0));
    }
    return out;
}

/// Terrain vertices: a 16 km square around the eye's foot, 65 x 65, heights 0..600 m.
std::vector<glm::dvec3> terrain() {
    std::vector<glm::dvec3> out;
    for (int i = 0; i <= 64; ++i) {
        for (int j = 0; j <= 64; ++j) {
            const double x = -8000.0 + 250.0 * i, y = -8000.0 + 250.0 * j;
            const double z = 300.0 + 150.0 * std::sin(x / 1300.0) + 150.0 * std::cos(y / 1700.0);
            out.push_back({x + 37.0, y - 11.0, std::clamp(z, 0.0, 600.0)});
        }
    }
    return out;
}

struct Scene {
    Frame<float> frame;
    float exposure = 8.0f;
};

Frame<float> height_frame(const Atmosphere& a, const glm::dvec3& eye, double sun_deg) {
    View view;
    view.eye = eye;
    view.sun_dir = direction(sun_deg, 30.0);
    auto f = aerial::prepare_frame<float>(a, view, Model::height);
    EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().message);
    return f.ok() ? *f : Frame<float>{};
}

/// aerial::auto_exposure for the frame's sun at the eye's altitude.
float automatic_exposure(const Atmosphere& a, double eye_altitude_m, double sun_deg) {
    const double elevation = sun_deg * kDegree;
    const glm::dvec3 e_sun = aerial::sun_irradiance_at_altitude(a, eye_altitude_m, elevation);
    auto ambient = aerial::sky_ambient(a, eye_altitude_m, elevation);
    EXPECT_TRUE(ambient.ok());
    return float(aerial::auto_exposure(e_sun, elevation, ambient.ok() ? *ambient : glm::dvec3(0),
                                       a.sun_irradiance));
}

int lsb(float a, float b) {
    return std::abs(int(aerial::to_unorm8(a)) - int(aerial::to_unorm8(b)));
}

struct Worst {
    int lsb = 0;
    long vertices = 0;
    long over_two = 0;  ///< vertices more than kSceneLsb off in some channel
    std::string where;
    double percent_over_two() const {
        return vertices ? 100.0 * double(over_two) / double(vertices) : 0.0;
    }
};

/// The program of `options` against scatter<float> over `vertices` (world positions) of a scene.
void measure(const aerial::validation::ArbCpuProgram& program, const ArbProgramOptions& options,
             const Scene& scene, const std::vector<glm::dvec3>& vertices, const char* what,
             Worst& worst) {
    aerial::Display display;
    display.exposure = scene.exposure;
    auto params = aerial::arb_program_parameters(scene.frame, display, options);
    ASSERT_TRUE(params.ok()) << params.error().message;
    aerial::validation::ArbMachine machine;
    machine.local = *params;
    // The levels below multiple_scattering compute the model without its higher orders.
    Frame<float> cpu_frame = scene.frame;
    if (options.height_fidelity != ArbHeightFidelity::multiple_scattering) {
        cpu_frame.multiple_scattering.reset();
    }
    for (const glm::dvec3& v : vertices) {
        aerial::validation::ArbVertex vertex;
        vertex.position = {float(v.x), float(v.y), float(v.z), 1.0f};
        const auto r = aerial::validation::run_arb_program(program, machine, vertex);
        const auto cpu = aerial::scatter(cpu_frame, glm::vec3(v));
        int here = 0;
        for (int c = 0; c < 3; ++c) {
            const auto i = static_cast<std::size_t>(c);
            const int e =
                std::max(lsb(r.color_primary.value[i], cpu.extinction[c]),
                         lsb(r.color_secondary.value[i], scene.exposure * cpu.in_scattering[c]));
            here = std::max(here, e);
            if (e > worst.lsb) {
                char buffer[240];
                const glm::dvec3 d = v - glm::dvec3(scene.frame.view.eye);
                std::snprintf(buffer, sizeof buffer,
                              "%s eye z=%g sun z=%.3f exposure %g, d=(%.0f, %.0f, %.0f) c=%d: "
                              "program F %g L %g, cpu F %g L %g",
                              what, scene.frame.view.eye.z, scene.frame.view.sun_dir.z,
                              scene.exposure, d.x, d.y, d.z, c, r.color_primary.value[i],
                              r.color_secondary.value[i], cpu.extinction[c],
                              scene.exposure * cpu.in_scattering[c]);
                worst.lsb = e;
                worst.where = buffer;
            }
        }
        ++worst.vertices;
        if (here > kSceneLsb) ++worst.over_two;
    }
}

/// The worst case per preset (kPresets' order) of the 100 km dome, the 1000 km dome and the
/// terrain.
struct SceneFigures {
    Worst dome100[2], dome1000[2], terrain[2];
};

SceneFigures measure_scenes(const ArbProgramOptions& options) {
    SceneFigures out;
    auto generated = aerial::generate_arb_program(options);
    EXPECT_TRUE(generated.ok()) << (generated.ok() ? "" : generated.error().message);
    if (!generated.ok()) return out;
    auto program = aerial::validation::parse_arb_program(generated->text);
    EXPECT_TRUE(program.ok());
    if (!program.ok()) return out;
    for (std::size_t p = 0; p < 2; ++p) {
        const char* name = kPresets[p];
        const Atmosphere a = *aerial::atmosphere_preset(name);
        for (double h : kEyeAltitudes) {
            const glm::dvec3 eye(130.0, -70.0, h);
            for (double sun : kSunElevations) {
                Scene scene{height_frame(a, eye, sun)};
                for (float exposure : {8.0f, automatic_exposure(a, h, sun)}) {
                    scene.exposure = exposure;
                    const auto& o = generated->options;
                    measure(*program, o, scene, dome(eye, 1e5), name, out.dome100[p]);
                    measure(*program, o, scene, dome(eye, 1e6), name, out.dome1000[p]);
                    measure(*program, o, scene, terrain(), name, out.terrain[p]);
                }
            }
        }
    }
    return out;
}

ArbProgramOptions height_options(ArbHeightFidelity fidelity) {
    ArbProgramOptions o;
    o.model = Model::height;
    o.height_fidelity = fidelity;
    o.limits = aerial::arb_reference_limits(fidelity);
    // Direct3D 9-class native limits also for spec_minimum (its program fits 128 regardless).
    o.limits.max_instructions = std::max(o.limits.max_instructions, 256);
    return o;
}

void print(ArbHeightFidelity level, const char* scene, const Worst (&w)[2]) {
    for (std::size_t p = 0; p < 2; ++p) {
        std::printf(
            "[ info     ] %s, %-13s %-5s: max %3d LSB, %5.1f%% of vertices > %d (worst: %s)\n",
            aerial::arb_height_fidelity_name(level), scene, kPresets[p], w[p].lsb,
            w[p].percent_over_two(), kSceneLsb, w[p].where.c_str());
    }
}

SceneFigures measure_and_print(ArbHeightFidelity level) {
    const SceneFigures f = measure_scenes(height_options(level));
    print(level, "dome 100 km", f.dome100);
    print(level, "dome 1000 km", f.dome1000);
    print(level, "terrain", f.terrain);
    return f;
}

}  // namespace

// The 128-instruction program: within 3 LSB on the terrain; on the dome its error is pinned as a
// regression bound (measured, not a target): it leaves out the model's placement of the sunlight
// points by the optical depth without the sag, their weights' correction by the exact optical
// depth and each channel's own attenuation to them, which rays of 100 km and more need
// (docs/arb-program.md). Per preset: earth, hazy.
constexpr int kSpecTerrainLsb = 3;
constexpr int kSpecDome100Lsb[2] = {57, 68};
constexpr double kSpecDome1000PercentOverTwo[2] = {96.0, 96.0};

TEST(ArbHeightScenes, SpecMinimumProgramIsWithin3LsbOnTerrainAndPinnedOnTheDome) {
    const SceneFigures f = measure_and_print(ArbHeightFidelity::spec_minimum);
    for (std::size_t p = 0; p < 2; ++p) {
        EXPECT_LE(f.terrain[p].lsb, kSpecTerrainLsb) << f.terrain[p].where;
        EXPECT_LE(f.dome100[p].lsb, kSpecDome100Lsb[p]) << f.dome100[p].where;
        EXPECT_LE(f.dome1000[p].percent_over_two(), kSpecDome1000PercentOverTwo[p]);
    }
}

namespace {

/// Every scene of a level within kSceneLsb of the CPU model, for both presets.
void expect_within_on_every_scene(ArbHeightFidelity level) {
    const SceneFigures f = measure_and_print(level);
    for (std::size_t p = 0; p < 2; ++p) {
        EXPECT_LE(f.terrain[p].lsb, kSceneLsb) << f.terrain[p].where;
        EXPECT_LE(f.dome100[p].lsb, kSceneLsb) << f.dome100[p].where;
        EXPECT_LE(f.dome1000[p].lsb, kSceneLsb) << f.dome1000[p].where;
    }
}

}  // namespace

TEST(ArbHeightScenes, FullProgramIsWithin2LsbOnDomeAndTerrain) {
    expect_within_on_every_scene(ArbHeightFidelity::full);
}

TEST(ArbHeightScenes, MultipleScatteringProgramIsWithin2LsbOnDomeAndTerrain) {
    expect_within_on_every_scene(ArbHeightFidelity::multiple_scattering);
}

TEST(ArbHeightScenes, ExactOpticalDepthProgramIsWithin2LsbOnTerrain) {
    const SceneFigures f = measure_and_print(ArbHeightFidelity::exact_optical_depth);
    for (std::size_t p = 0; p < 2; ++p) {
        EXPECT_LE(f.terrain[p].lsb, kSceneLsb) << f.terrain[p].where;
    }
}

// ---- Model-space vertices and the parameter layout -------------------------------------------

namespace {

/// A model matrix (column-major): a rotation about an oblique axis, a scale of 2, a translation.
std::array<float, 16> model_matrix() {
    const glm::dvec3 axis = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    const double angle = 0.7, c = std::cos(angle), s = std::sin(angle), k = 2.0;
    const glm::dvec3 t(1500.0, -800.0, 250.0);
    std::array<float, 16> m{};
    for (int col = 0; col < 3; ++col) {
        glm::dvec3 e(0.0);
        e[col] = 1.0;
        const glm::dvec3 r = e * c + glm::cross(axis, e) * s + axis * glm::dot(axis, e) * (1 - c);
        for (int row = 0; row < 3; ++row) m[std::size_t(4 * col + row)] = float(k * r[row]);
    }
    m[12] = float(t.x), m[13] = float(t.y), m[14] = float(t.z), m[15] = 1.0f;
    return m;
}

glm::dvec3 apply(const std::array<float, 16>& m, const glm::dvec3& v) {
    glm::dvec3 out;
    for (int row = 0; row < 3; ++row) {
        out[row] = m[std::size_t(row)] * v.x + m[std::size_t(4 + row)] * v.y +
                   m[std::size_t(8 + row)] * v.z + m[std::size_t(12 + row)];
    }
    return out;
}

/// The largest difference in 8-bit codes (F_ex, L_in) and the largest relative difference of the
/// fog coordinate between the program with the model matrix at model-space vertices and without
/// it at their world positions.
struct ModelFigures {
    int lsb = 0;
    double fog = 0.0;
    std::string where;
};

ModelFigures compare_model_space(ArbProgramOptions o, const Frame<float>& frame, float exposure) {
    ModelFigures out;
    const std::array<float, 16> m = model_matrix();
    aerial::Display display;
    display.exposure = exposure;
    o.model_matrix = false;
    const auto world = aerial::generate_arb_program(o);
    o.model_matrix = true;
    const auto model = aerial::generate_arb_program(o);
    EXPECT_TRUE(world.ok() && model.ok()) << (model.ok() ? "" : model.error().message);
    if (!world.ok() || !model.ok()) return out;
    const auto world_program = *aerial::validation::parse_arb_program(world->text);
    const auto model_program = *aerial::validation::parse_arb_program(model->text);
    aerial::validation::ArbMachine world_machine, model_machine;
    world_machine.local = *aerial::arb_program_parameters(frame, display, world->options);
    model_machine.local = *aerial::arb_program_parameters(frame, display, model->options);
    const int first = aerial::arb_model_matrix_parameter_index(model->options);
    const auto rows = aerial::arb_model_matrix_parameters(m.data());
    for (std::size_t i = 0; i < 3; ++i) model_machine.local[std::size_t(first) + i] = rows[i];
    // Model-space vertices around the origin whose world positions span terrain and dome.
    std::vector<glm::dvec3> vertices;
    for (double r : {1.0, 300.0, 4000.0, 50000.0}) {
        for (double e : {-5.0, 0.0, 5.0, 30.0, 80.0}) {
            for (int a = 0; a < 8; ++a) vertices.push_back(r * direction(e, 45.0 * a + 10.0));
        }
    }
    for (const glm::dvec3& v : vertices) {
        aerial::validation::ArbVertex in_model, in_world;
        in_model.position = {float(v.x), float(v.y), float(v.z), 1.0f};
        const glm::dvec3 w = apply(m, v);
        in_world.position = {float(w.x), float(w.y), float(w.z), 1.0f};
        const auto a = aerial::validation::run_arb_program(model_program, model_machine, in_model);
        const auto b = aerial::validation::run_arb_program(world_program, world_machine, in_world);
        for (std::size_t c = 0; c < 3; ++c) {
            const int e = std::max(lsb(a.color_primary.value[c], b.color_primary.value[c]),
                                   lsb(a.color_secondary.value[c], b.color_secondary.value[c]));
            if (e > out.lsb) {
                out.lsb = e;
                out.where = "model vertex (" + std::to_string(v.x) + ", " + std::to_string(v.y) +
                            ", " + std::to_string(v.z) + ")";
            }
        }
        out.fog = std::max(out.fog, std::abs(double(a.fogcoord.value[0]) - b.fogcoord.value[0]) /
                                        std::max(1.0, double(b.fogcoord.value[0])));
        // The clip-space position is mvp * vertex.position, in model space (identity mvp here).
        for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(a.position.value[c], in_model.position[c]);
    }
    return out;
}

}  // namespace

TEST(ArbModelMatrix, ModelSpaceVerticesGiveTheWorldSpaceResultWithin1Lsb) {
    const Atmosphere a = *aerial::atmosphere_preset("hazy");
    for (double sun : {2.0, 20.0, 90.0}) {
        const glm::dvec3 eye(130.0, -70.0, 500.0);
        for (ArbHeightFidelity level :
             {ArbHeightFidelity::spec_minimum, ArbHeightFidelity::exact_optical_depth,
              ArbHeightFidelity::full}) {
            const ModelFigures f =
                compare_model_space(height_options(level), height_frame(a, eye, sun), 8.0f);
            std::printf("[ info     ] height %s, sun %g deg: model space vs world %d LSB, fog %g\n",
                        aerial::arb_height_fidelity_name(level), sun, f.lsb, f.fog);
            EXPECT_LE(f.lsb, 1) << f.where;
            EXPECT_LE(f.fog, 1e-5);
        }
        View view;
        view.eye = eye;
        view.sun_dir = direction(sun, 30.0);
        const auto frame = aerial::prepare_frame<float>(a, view, Model::hoffman_preetham);
        ASSERT_TRUE(frame.ok());
        const ModelFigures f = compare_model_space(ArbProgramOptions{}, *frame, 8.0f);
        std::printf("[ info     ] hoffman-preetham, sun %g deg: model space vs world %d LSB\n", sun,
                    f.lsb);
        EXPECT_LE(f.lsb, 1) << f.where;
        EXPECT_LE(f.fog, 1e-5);
    }
}

TEST(ArbModelMatrix, RowsAreTheMatrixTopRowsAfterTheFrameParameters) {
    const std::array<float, 16> m = model_matrix();
    const auto rows = aerial::arb_model_matrix_parameters(m.data());
    for (std::size_t r = 0; r < 3; ++r) {
        for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(rows[r][c], m[4 * c + r]);
    }
    ArbProgramOptions o = height_options(ArbHeightFidelity::spec_minimum);
    o.model_matrix = true;
    o.parameter_base = 7;
    EXPECT_EQ(aerial::arb_model_matrix_parameter_index(o), 7 + aerial::kArbHeightParameterCount);
    EXPECT_EQ(aerial::arb_parameter_count(o), aerial::kArbHeightParameterCount + 3);
    ArbProgramOptions hp;
    hp.model_matrix = true;
    EXPECT_EQ(aerial::arb_model_matrix_parameter_index(hp), aerial::kArbParameterCount);
    EXPECT_EQ(aerial::generate_arb_program(hp)->instruction_count, 26);
    // The frame's parameters end with the identity's rows, so that an upload of them alone draws
    // world-space vertices.
    const Frame<float> f = height_frame(*aerial::atmosphere_preset("earth"), {0, 0, 300}, 20.0);
    aerial::Display display;
    const auto p = aerial::arb_program_parameters(f, display, o);
    ASSERT_TRUE(p.ok());
    ASSERT_EQ(p->size(), std::size_t(aerial::arb_parameter_count(o)));
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const auto id = aerial::arb_model_matrix_parameters(identity);
    for (std::size_t r = 0; r < 3; ++r)
        EXPECT_EQ((*p)[std::size_t(aerial::kArbHeightParameterCount) + r], id[r]);
}

TEST(ArbParameterLayout, EveryVectorIsDeclaredByItsNameAtItsIndex) {
    for (Model model : {Model::hoffman_preetham, Model::height}) {
        for (ArbHeightFidelity level :
             {ArbHeightFidelity::automatic, ArbHeightFidelity::spec_minimum,
              ArbHeightFidelity::exact_optical_depth, ArbHeightFidelity::full}) {
            for (bool with_matrix : {false, true}) {
                for (aerial::ParameterSpace space :
                     {aerial::ParameterSpace::local, aerial::ParameterSpace::env}) {
                    ArbProgramOptions o = height_options(level);
                    o.model = model;
                    o.model_matrix = with_matrix;
                    o.parameter_space = space;
                    o.parameter_base = 5;
                    const auto program = aerial::generate_arb_program(o);
                    ASSERT_TRUE(program.ok()) << program.error().message;
                    const auto layout = aerial::arb_parameter_layout(o);
                    EXPECT_EQ(layout.size(), aerial::arb_parameter_layout(program->options).size());
                    EXPECT_EQ(int(layout.size()), aerial::arb_parameter_count(o));
                    const std::string prefix =
                        space == aerial::ParameterSpace::local ? "program.local[" : "program.env[";
                    for (std::size_t i = 0; i < layout.size(); ++i) {
                        EXPECT_EQ(layout[i].index, 5 + int(i));
                        EXPECT_STRNE(layout[i].meaning, "");
                        const std::string declaration = "PARAM " + std::string(layout[i].name) +
                                                        " = " + prefix +
                                                        std::to_string(layout[i].index) + "];";
                        EXPECT_NE(program->text.find(declaration), std::string::npos)
                            << declaration;
                        for (std::size_t j = 0; j < i; ++j) {
                            EXPECT_STRNE(layout[i].name, layout[j].name);
                        }
                    }
                    if (with_matrix) {
                        const std::size_t n = layout.size();
                        EXPECT_STREQ(layout[n - 3].name, "model0");
                        EXPECT_EQ(layout[n - 3].index, aerial::arb_model_matrix_parameter_index(o));
                    }
                }
            }
        }
    }
    ArbProgramOptions none;
    none.model = Model::reference;
    EXPECT_TRUE(aerial::arb_parameter_layout(none).empty());
}

TEST(ArbParameterLayout, AnExplicitLevelThatDoesNotFitNamesTheLimitAndBothNumbers) {
    ArbProgramOptions o;
    o.model = Model::height;
    o.height_fidelity = ArbHeightFidelity::full;
    const auto refused = aerial::generate_arb_program(o);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().message,
              "aerial::generate_arb_program(): instructions: expected at most 128 "
              "(MAX_PROGRAM_INSTRUCTIONS_ARB), got 245 in the program");
    o.height_fidelity = ArbHeightFidelity::automatic;
    const auto chosen = aerial::generate_arb_program(o);
    ASSERT_TRUE(chosen.ok());
    EXPECT_EQ(chosen->options.height_fidelity, ArbHeightFidelity::spec_minimum);
    o.limits.max_instructions = 256;
    EXPECT_EQ(aerial::generate_arb_program(o)->options.height_fidelity, ArbHeightFidelity::full);
}
