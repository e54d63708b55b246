// aerial-eval end to end (docs/conventions.md, Interfaces): runs the real binary with its standard
// streams
// redirected to files in a per-test temporary directory, and pins the command-line contract:
// --help, the CSV it prints, the ways points and atmospheres reach it, and for every kind of bad
// input exit status 2, empty stdout and exactly one stderr line naming the culprit.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tool_runner.hpp"

namespace {

using aerial::test::kExitBadInput;
using aerial::test::RunResult;

constexpr const char* kBinary = AERIAL_EVAL_PATH;
constexpr const char* kHeader = "x,y,z,fex_r,fex_g,fex_b,lin_r,lin_g,lin_b,esun_r,esun_g,esun_b";
constexpr size_t kColumns = 12;
/// Relative tolerance between runs that should agree up to rounding of the printed digits
/// (%.9g) and of a different but equivalent order of operations.
constexpr double kSameResultTolerance = 1e-7;

/// The earth preset of docs/conventions.md, Physics, as an atmosphere file.
constexpr const char* kEarthJson = R"({
  "rayleigh_scattering": [5.802e-6, 13.558e-6, 33.1e-6],
  "mie_scattering": [3.996e-6, 3.996e-6, 3.996e-6],
  "mie_absorption": [0, 0, 0],
  "mie_g": 0.8,
  "rayleigh_scale_height_m": 8000,
  "mie_scale_height_m": 1200,
  "ozone_absorption": [0.650e-6, 1.881e-6, 0.085e-6],
  "ozone_center_altitude_m": 25000,
  "ozone_width_m": 30000,
  "planet_radius_m": 6360000,
  "atmosphere_radius_m": 6420000,
  "ground_albedo": 0.1,
  "sun_irradiance": [1, 1, 1]
})";

/// A few points 1 to 50 km from an eye at (0, 0, 100), level, up, down and high.
constexpr const char* kPoints =
    "0,1000,100\n"
    "0,10000,100\n"
    "0,-50000,100\n"
    "10000,0,600\n"
    "-7000,-7000,0\n"
    "0,20000,10000\n";
constexpr size_t kPointCount = 6;

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::string part;
    std::istringstream stream(text);
    while (std::getline(stream, part, separator)) parts.push_back(part);
    return parts;
}

/// A parsed CSV table: the header line and the numeric rows.
struct Csv {
    std::string header;
    std::vector<std::vector<double>> rows;
};

/// Parses aerial-eval's stdout; fails the assertion on anything that is not a header followed
/// by rows of kColumns finite numbers.
::testing::AssertionResult parse_csv(const std::string& text, Csv& csv) {
    if (text.empty() || text.back() != '\n') {
        return ::testing::AssertionFailure()
               << "output does not end with a newline: '" << text << "'";
    }
    const std::vector<std::string> lines = split(text, '\n');
    csv.header = lines.front();
    csv.rows.clear();
    for (size_t i = 1; i < lines.size(); ++i) {
        const std::vector<std::string> fields = split(lines[i], ',');
        if (fields.size() != kColumns) {
            return ::testing::AssertionFailure()
                   << "line " << i + 1 << " has " << fields.size() << " columns, expected "
                   << kColumns << ": '" << lines[i] << "'";
        }
        std::vector<double> row;
        for (const std::string& field : fields) {
            char* end = nullptr;
            const double value = std::strtod(field.c_str(), &end);
            if (field.empty() || *end != '\0' || !std::isfinite(value)) {
                return ::testing::AssertionFailure()
                       << "line " << i + 1 << ": '" << field << "' is not a finite number";
            }
            row.push_back(value);
        }
        csv.rows.push_back(row);
    }
    return ::testing::AssertionSuccess();
}

/// The physical invariants of every row: F_ex in [0, 1], L_in >= 0, E_sun >= 0.
::testing::AssertionResult rows_are_physical(const Csv& csv) {
    for (size_t i = 0; i < csv.rows.size(); ++i) {
        const std::vector<double>& row = csv.rows[i];
        for (size_t c = 0; c < 3; ++c) {
            if (!(row[3 + c] >= 0.0 && row[3 + c] <= 1.0)) {
                return ::testing::AssertionFailure() << "row " << i + 1 << ": F_ex channel " << c
                                                     << " = " << row[3 + c] << " is outside [0, 1]";
            }
            if (!(row[6 + c] >= 0.0)) {
                return ::testing::AssertionFailure() << "row " << i + 1 << ": L_in channel " << c
                                                     << " = " << row[6 + c] << " is negative";
            }
            if (!(row[9 + c] >= 0.0)) {
                return ::testing::AssertionFailure() << "row " << i + 1 << ": E_sun channel " << c
                                                     << " = " << row[9 + c] << " is negative";
            }
        }
    }
    return ::testing::AssertionSuccess();
}

/// Whether two tables hold the same values within a relative tolerance.
::testing::AssertionResult same_values(const Csv& a, const Csv& b, double tolerance) {
    if (a.rows.size() != b.rows.size()) {
        return ::testing::AssertionFailure()
               << a.rows.size() << " rows against " << b.rows.size() << " rows";
    }
    for (size_t i = 0; i < a.rows.size(); ++i) {
        for (size_t c = 3; c < kColumns; ++c) {
            const double x = a.rows[i][c], y = b.rows[i][c];
            if (std::abs(x - y) > tolerance * std::max(std::abs(x), std::abs(y))) {
                return ::testing::AssertionFailure()
                       << "row " << i + 1 << " column " << c << ": " << x << " against " << y;
            }
        }
    }
    return ::testing::AssertionSuccess();
}

/// The bad-input contract of docs/conventions.md, Interfaces, for aerial-eval (tool_runner.hpp).
::testing::AssertionResult rejected_naming(const RunResult& run,
                                           std::initializer_list<const char*> expected) {
    return aerial::test::rejected_naming(run, "aerial-eval", expected);
}

class AerialEval : public aerial::test::ToolTest {
  protected:
    /// Runs aerial-eval with `args`, `input` on stdin.
    RunResult run(const std::vector<std::string>& args, const std::string& input = "") {
        return ToolTest::run(kBinary, args, input);
    }

    /// A successful run: exit 0, nothing on stderr, a well-formed CSV.
    Csv run_ok(const std::vector<std::string>& args, const std::string& input = kPoints) {
        const RunResult result = run(args, input);
        Csv csv;
        EXPECT_EQ(result.exit_code, 0) << "stderr: " << result.err;
        EXPECT_EQ(result.err, "");
        EXPECT_TRUE(parse_csv(result.out, csv)) << "stdout: " << result.out;
        return csv;
    }

    static std::vector<std::string> with(std::vector<std::string> args,
                                         std::initializer_list<std::string> more) {
        args.insert(args.end(), more);
        return args;
    }

    /// A complete, valid command line with the earth preset.
    const std::vector<std::string> earth_{"--preset", "earth", "--eye=0,0,100", "--sun=0,0.6,0.8"};
    /// The same without an atmosphere.
    const std::vector<std::string> view_{"--eye=0,0,100", "--sun=0,0.6,0.8"};
};

// ---- --help ----------------------------------------------------------------------------------

TEST_F(AerialEval, HelpExitsZeroAndMentionsEveryFlag) {
    const RunResult result = run({"--help"});
    EXPECT_EQ(result.exit_code, 0) << result.err;
    EXPECT_EQ(result.err, "");
    for (const char* flag :
         {"--help", "--preset", "--atmosphere", "--eye", "--sun", "--model", "--up", "--points"}) {
        EXPECT_NE(result.out.find(flag), std::string::npos) << "--help does not mention " << flag;
    }
    EXPECT_NE(result.out.find(kHeader), std::string::npos) << "--help does not show the CSV header";
    for (const char* model : {"hoffman-preetham", "height", "single-scattering", "reference"}) {
        EXPECT_NE(result.out.find(model), std::string::npos) << "--help does not name " << model;
    }
}

// ---- good runs -------------------------------------------------------------------------------

TEST_F(AerialEval, PrintsTheHeaderThenOneRowOfTwelveFinitePhysicalValuesPerPoint) {
    const Csv csv = run_ok(earth_);
    EXPECT_EQ(csv.header, kHeader);
    ASSERT_EQ(csv.rows.size(), kPointCount);
    EXPECT_TRUE(rows_are_physical(csv));
    // The first three columns echo the points, in order.
    const std::vector<std::string> lines = split(kPoints, '\n');
    for (size_t i = 0; i < kPointCount; ++i) {
        const std::vector<std::string> xyz = split(lines[i], ',');
        for (size_t c = 0; c < 3; ++c) {
            EXPECT_EQ(csv.rows[i][c], std::stod(xyz[c])) << "row " << i + 1 << " column " << c;
        }
    }
    // Haze grows with distance: F_ex falls and L_in rises from 1 km to 10 km, level.
    for (size_t c = 0; c < 3; ++c) {
        EXPECT_LT(csv.rows[1][3 + c], csv.rows[0][3 + c]) << "F_ex channel " << c;
        EXPECT_GT(csv.rows[1][6 + c], csv.rows[0][6 + c]) << "L_in channel " << c;
    }
}

TEST_F(AerialEval, EmptyInputPrintsOnlyTheHeader) {
    const RunResult result = run(earth_, "");
    EXPECT_EQ(result.exit_code, 0) << result.err;
    EXPECT_EQ(result.out, std::string(kHeader) + "\n");
}

TEST_F(AerialEval, ReadsTheSamePointsFromStdinAndFromPointsFile) {
    const RunResult from_stdin = run(earth_, kPoints);
    const RunResult from_file = run(with(earth_, {"--points", file("points.txt", kPoints)}));
    const RunResult from_file_equals =
        run(with(earth_, {"--points=" + file("points2.txt", kPoints)}), "999,999,999\n");
    EXPECT_EQ(from_stdin.exit_code, 0) << from_stdin.err;
    EXPECT_EQ(from_file.exit_code, 0) << from_file.err;
    EXPECT_EQ(from_file_equals.exit_code, 0) << from_file_equals.err;
    EXPECT_EQ(from_stdin.out, from_file.out);
    EXPECT_EQ(from_stdin.out, from_file_equals.out) << "--points must take precedence over stdin";
}

TEST_F(AerialEval, IgnoresBlankLinesAndWholeLineAndTrailingComments) {
    const std::string commented =
        "# points for the test\n"
        "\n"
        "0,1000,100\n"
        "   \n"
        "  # indented comment\n"
        "0,10000,100   # trailing comment, with commas 1,2,3\n"
        "0,-50000,100#no space before it\n"
        "\t\n"
        "10000,0,600\n"
        "-7000,-7000,0\n"
        "0,20000,10000\n"
        "# last line without newline";
    const RunResult plain = run(earth_, kPoints);
    const RunResult from_stdin = run(earth_, commented);
    const RunResult from_file = run(with(earth_, {"--points", file("commented.txt", commented)}));
    EXPECT_EQ(from_stdin.exit_code, 0) << from_stdin.err;
    EXPECT_EQ(from_file.exit_code, 0) << from_file.err;
    EXPECT_EQ(from_stdin.out, plain.out);
    EXPECT_EQ(from_file.out, plain.out);
}

TEST_F(AerialEval, AcceptsWindowsLineEndingsAndSpacesAroundNumbers) {
    const RunResult plain = run(earth_, "0,1000,100\n0,10000,100\n");
    const RunResult crlf = run(earth_, "0,1000,100\r\n 0 , 10000 , 100 \r\n");
    EXPECT_EQ(crlf.exit_code, 0) << crlf.err;
    EXPECT_EQ(crlf.out, plain.out);
}

TEST_F(AerialEval, AcceptsNegativeVectorValuesInTheEqualsForm) {
    // Mirroring x -> -x leaves the planet, the up axis and a sun in the y-z plane unchanged, so
    // an eye and a point at negative x must give what their mirror images at positive x give. A
    // flag parser that dropped or misread the minus signs would see a different distance.
    const Csv negative = run_ok({"--preset", "earth", "--eye=-1000,0,100", "--sun=0,0.6,0.8"},
                                "-3000,0,100\n-21000,-5000,2000\n");
    const Csv positive = run_ok({"--preset", "earth", "--eye=1000,0,100", "--sun=0,0.6,0.8"},
                                "3000,0,100\n21000,-5000,2000\n");
    ASSERT_EQ(negative.rows.size(), 2u);
    EXPECT_TRUE(rows_are_physical(negative));
    EXPECT_EQ(negative.rows[0][0], -3000.0);
    EXPECT_TRUE(same_values(negative, positive, kSameResultTolerance));
    // A sun with a negative component: mirroring y -> -y as well.
    const Csv south =
        run_ok({"--preset", "earth", "--eye=0,-10,100", "--sun=-0.36,-0.48,0.8"}, "0,-10010,100\n");
    const Csv north =
        run_ok({"--preset", "earth", "--eye=0,10,100", "--sun=-0.36,0.48,0.8"}, "0,10010,100\n");
    EXPECT_TRUE(same_values(south, north, kSameResultTolerance));
}

TEST_F(AerialEval, UpAxisRotatesTheWholeWorld) {
    // The same scene with the world's up along +X instead of +Z (z -> x, x -> y, y -> z).
    const Csv z_up = run_ok({"--preset", "earth", "--eye=0,0,100", "--sun=0,0.6,0.8"},
                            "0,10000,100\n3000,-20000,2500\n");
    const Csv x_up = run_ok({"--preset", "earth", "--eye=100,0,0", "--sun=0.8,0,0.6", "--up=1,0,0"},
                            "100,0,10000\n2500,3000,-20000\n");
    EXPECT_TRUE(same_values(z_up, x_up, kSameResultTolerance));
}

TEST_F(AerialEval, AtmosphereFileWithTheEarthValuesMatchesTheEarthPreset) {
    const std::string json = file("earth.json", kEarthJson);
    // Not `reference`: its tables cost seconds per run, so it runs once, in
    // AcceptsEveryModelNameAndEachGivesItsOwnResult. single-scattering integrates the ozone layer
    // along every path, so the file's ozone fields must give the preset's layer.
    for (const char* model : {"hoffman-preetham", "height", "single-scattering"}) {
        const RunResult preset = run(with(earth_, {"--model", model}), kPoints);
        const RunResult from_file =
            run(with(view_, {"--atmosphere", json, "--model", model}), kPoints);
        EXPECT_EQ(from_file.exit_code, 0) << from_file.err;
        EXPECT_EQ(from_file.out, preset.out) << "model " << model;
    }
    // Missing fields keep the earth values (docs/conventions.md, Interfaces, lists them as
    // optional), except the absorbers and the ground albedo, which are 0 when missing.
    const char* partial_json =
        R"({"mie_g": 0.8, "ground_albedo": 0.1, "ozone_absorption": [0.65e-6, 1.881e-6, 8.5e-8]})";
    const RunResult partial =
        run(with(view_, {"--atmosphere", file("partial.json", partial_json)}), kPoints);
    EXPECT_EQ(partial.exit_code, 0) << partial.err;
    EXPECT_EQ(partial.out, run(earth_, kPoints).out);
}

TEST_F(AerialEval, AtmosphereFileValuesChangeTheResult) {
    // Twice the Rayleigh coefficient and no haze: the file is really read.
    const std::string json = file("thick.json", R"({
        "rayleigh_scattering": [11.604e-6, 27.116e-6, 66.2e-6],
        "mie_scattering": [0, 0, 0]
    })");
    const Csv thick = run_ok(with(view_, {"--atmosphere", json}));
    const Csv earth = run_ok(earth_);
    ASSERT_EQ(thick.rows.size(), earth.rows.size());
    EXPECT_TRUE(rows_are_physical(thick));
    EXPECT_LT(thick.rows[1][5], earth.rows[1][5]) << "blue F_ex at 10 km";
}

TEST_F(AerialEval, AcceptsEveryModelNameAndEachGivesItsOwnResult) {
    // `reference` is run once, here, on earth: its higher-order tables take seconds to compute.
    const std::vector<const char*> models = {"hoffman-preetham", "height", "single-scattering",
                                             "reference"};
    std::vector<Csv> results;
    for (const char* model : models) {
        SCOPED_TRACE(model);
        const Csv csv = run_ok(with(earth_, {"--model", model}));
        EXPECT_EQ(csv.header, kHeader);
        EXPECT_EQ(csv.rows.size(), kPointCount);
        EXPECT_TRUE(rows_are_physical(csv));
        results.push_back(csv);
    }
    ASSERT_EQ(results.size(), models.size());
    for (const Csv& csv : results) ASSERT_EQ(csv.rows.size(), kPointCount);
    // The models differ (at 10 km altitude the 2002 model's constant sea-level density is far
    // off): each name selects a different model.
    for (size_t a = 0; a < models.size(); ++a) {
        for (size_t b = a + 1; b < models.size(); ++b) {
            EXPECT_NE(results[a].rows.back(), results[b].rows.back())
                << models[a] << " vs " << models[b];
        }
    }
    // `reference` is single-scattering plus the higher orders: the same extinction and sun
    // irradiance, and more in-scattered light on every channel at every point.
    const Csv& single = results[2];
    const Csv& reference = results[3];
    for (size_t i = 0; i < kPointCount; ++i) {
        SCOPED_TRACE("row " + std::to_string(i + 1));
        for (size_t c = 0; c < 3; ++c) {
            for (const size_t column : {3 + c, 9 + c}) {
                EXPECT_NEAR(reference.rows[i][column], single.rows[i][column],
                            kSameResultTolerance * single.rows[i][column])
                    << "column " << column;
            }
            EXPECT_GT(reference.rows[i][6 + c], single.rows[i][6 + c]) << "L_in channel " << c;
        }
    }
    // The default is `height` (--help says so).
    const Csv by_default = run_ok(earth_);
    EXPECT_EQ(by_default.rows, results[1].rows);
}

TEST_F(AerialEval, AcceptsEveryPresetName) {
    for (const char* preset : {"earth", "hp2002", "hazy", "foggy", "mars"}) {
        SCOPED_TRACE(preset);
        const Csv csv = run_ok(with(view_, {"--preset", preset}));
        EXPECT_EQ(csv.rows.size(), kPointCount);
        EXPECT_TRUE(rows_are_physical(csv));
    }
}

// ---- bad input: exit 2, one stderr line naming the culprit, nothing on stdout ---------------

TEST_F(AerialEval, PrintsTheArbProgramOfTheChosenModel) {
    // The default is the 2002 model; --model height prints the height program; both are complete
    // programs (header to END) that differ; the numerical models have none and are refused with
    // one line naming the model.
    const RunResult plain = run({"--print-arb-program"});
    const RunResult hp = run({"--print-arb-program", "--model", "hoffman-preetham"});
    const RunResult height = run({"--print-arb-program", "--model=height"});
    for (const RunResult* r : {&plain, &hp, &height}) {
        EXPECT_EQ(r->exit_code, 0) << r->err;
        EXPECT_EQ(r->err, "");
        EXPECT_EQ(r->out.rfind("!!ARBvp1.0\n", 0), 0u) << r->out;
        ASSERT_GE(r->out.size(), 4u);
        EXPECT_EQ(r->out.substr(r->out.size() - 4), "END\n");
    }
    EXPECT_EQ(plain.out, hp.out);
    EXPECT_NE(height.out, hp.out);
    EXPECT_NE(height.out.find("height model"), std::string::npos) << height.out;
    for (const std::string model : {"single-scattering", "reference"}) {
        SCOPED_TRACE(model);
        const RunResult refused = run({"--print-arb-program", "--model", model});
        EXPECT_EQ(refused.exit_code, kExitBadInput);
        EXPECT_EQ(refused.out, "");
        EXPECT_EQ(refused.err,
                  "aerial-eval: --model: the ARB vertex program exists for hoffman-preetham and "
                  "height, got '" +
                      model + "'\n");
    }
}

TEST_F(AerialEval, ReportsTheReferenceTablesOrdersBoundAndShares) {
    const RunResult result = run({"--preset", "mars", "--reference-tables"});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_EQ(result.err, "");
    int orders = 0;
    double r = 0, g = 0, b = 0, seconds = -1;
    ASSERT_EQ(std::sscanf(result.out.c_str(), "orders=%d remainder_bound=%lf,%lf,%lf seconds=%lf",
                          &orders, &r, &g, &b, &seconds),
              5)
        << result.out;
    EXPECT_GE(orders, 3);
    EXPECT_LT(std::max({r, g, b}), 1e-3);
    EXPECT_GT(seconds, 0.0);
    // One line per order from 2, shares falling and summing to 1.
    double sum = 0.0, previous = 1.0;
    int lines = 0;
    std::istringstream in(result.out);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
        int order = 0;
        double share = 0.0;
        ASSERT_EQ(std::sscanf(line.c_str(), "order=%d share=%lf", &order, &share), 2) << line;
        EXPECT_EQ(order, lines + 2);
        EXPECT_LT(share, previous);
        previous = share;
        sum += share;
        ++lines;
    }
    EXPECT_EQ(lines, orders - 1);
    EXPECT_NEAR(sum, 1.0, 1e-3);
    EXPECT_TRUE(rejected_naming(run({"--preset", "mars", "--reference-tables", "--eye=0,0,1"}),
                                {"--reference-tables", "--eye"}));
}

TEST_F(AerialEval, RejectsMissingEyeNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(run({"--preset", "earth", "--sun=0,0,1"}, kPoints), {"--eye"}));
}

TEST_F(AerialEval, RejectsMissingSunNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(run({"--preset", "earth", "--eye=0,0,1"}, kPoints), {"--sun"}));
}

TEST_F(AerialEval, RejectsMissingAtmosphereNamingBothFlags) {
    EXPECT_TRUE(rejected_naming(run(view_, kPoints), {"--preset", "--atmosphere"}));
}

TEST_F(AerialEval, RejectsPresetTogetherWithAtmosphereFile) {
    const std::string json = file("earth.json", kEarthJson);
    EXPECT_TRUE(rejected_naming(run(with(earth_, {"--atmosphere", json}), kPoints),
                                {"--preset", "--atmosphere"}));
}

TEST_F(AerialEval, RejectsUnknownPresetNamingItAndTheKnownOnes) {
    EXPECT_TRUE(rejected_naming(run(with(view_, {"--preset", "venus"}), kPoints),
                                {"--preset", "venus", "earth"}));
}

TEST_F(AerialEval, RejectsUnknownModelNamingItAndTheKnownOnes) {
    EXPECT_TRUE(rejected_naming(run(with(earth_, {"--model", "rayleigh-only"}), kPoints),
                                {"--model", "rayleigh-only", "hoffman-preetham", "height",
                                 "single-scattering", "reference"}));
}

TEST_F(AerialEval, RejectsEyeWithTwoNumbersNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(run({"--preset", "earth", "--eye=0,100", "--sun=0,0,1"}, kPoints),
                                {"--eye", "0,100"}));
}

TEST_F(AerialEval, RejectsEyeWithFourNumbersNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(
        run({"--preset", "earth", "--eye=0,0,100,1", "--sun=0,0,1"}, kPoints), {"--eye"}));
}

TEST_F(AerialEval, RejectsEyeWithLettersNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(
        run({"--preset", "earth", "--eye=0,zero,100", "--sun=0,0,1"}, kPoints), {"--eye"}));
    EXPECT_TRUE(rejected_naming(
        run({"--preset", "earth", "--eye=0,0,100m", "--sun=0,0,1"}, kPoints), {"--eye"}));
}

TEST_F(AerialEval, RejectsNonFiniteEyeNamingTheFlag) {
    for (const char* eye :
         {"--eye=nan,0,100", "--eye=0,inf,100", "--eye=0,0,-infinity", "--eye=1e999,0,0"}) {
        SCOPED_TRACE(eye);
        EXPECT_TRUE(
            rejected_naming(run({"--preset", "earth", eye, "--sun=0,0,1"}, kPoints), {"--eye"}));
    }
}

TEST_F(AerialEval, RejectsZeroSunDirectionNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(run({"--preset", "earth", "--eye=0,0,100", "--sun=0,0,0"}, kPoints),
                                {"--sun"}));
}

TEST_F(AerialEval, RejectsNonFiniteSunNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(
        run({"--preset", "earth", "--eye=0,0,100", "--sun=0,nan,1"}, kPoints), {"--sun"}));
}

TEST_F(AerialEval, RejectsZeroUpAxisNamingTheFlag) {
    EXPECT_TRUE(rejected_naming(run(with(earth_, {"--up=0,0,0"}), kPoints), {"--up"}));
}

TEST_F(AerialEval, RejectsUnknownFlagNamingIt) {
    EXPECT_TRUE(rejected_naming(run(with(earth_, {"--exposure=2"}), kPoints), {"--exposure"}));
}

TEST_F(AerialEval, RejectsMissingAtmosphereFileNamingFlagAndPath) {
    const std::string missing = path("no-such-dir/air.json");
    EXPECT_TRUE(rejected_naming(run(with(view_, {"--atmosphere", missing}), kPoints),
                                {"--atmosphere", missing.c_str()}));
}

TEST_F(AerialEval, RejectsMalformedJsonNamingTheFile) {
    const std::string json = file("broken.json", "{\"mie_g\": 0.8,\n");
    EXPECT_TRUE(rejected_naming(run(with(view_, {"--atmosphere", json}), kPoints),
                                {"--atmosphere", json.c_str(), "json: parse error"}));
}

TEST_F(AerialEval, RejectsJsonWithUnknownFieldNamingIt) {
    // The error names the field and lists the known ones (the ozone and ground fields among them).
    const std::string json = file("unknown.json", R"({"mie_g": 0.8, "water_vapour": 1e-6})");
    EXPECT_TRUE(
        rejected_naming(run(with(view_, {"--atmosphere", json}), kPoints),
                        {"water_vapour", "ozone_absorption", "ozone_width_m", "ground_albedo"}));
}

TEST_F(AerialEval, RejectsJsonWithNegativeCoefficientNamingTheElement) {
    const std::string json =
        file("negative.json", R"({"rayleigh_scattering": [5.802e-6, -13.558e-6, 33.1e-6]})");
    EXPECT_TRUE(rejected_naming(run(with(view_, {"--atmosphere", json}), kPoints),
                                {"rayleigh_scattering[1]"}));
}

TEST_F(AerialEval, RejectsJsonWithMieGOfOneNamingTheField) {
    const std::string json = file("g1.json", R"({"mie_g": 1})");
    EXPECT_TRUE(rejected_naming(run(with(view_, {"--atmosphere", json}), kPoints), {"mie_g"}));
}

TEST_F(AerialEval, RejectsJsonWithAtmosphereBelowThePlanetNamingTheField) {
    const std::string json =
        file("low.json", R"({"planet_radius_m": 6360000, "atmosphere_radius_m": 6350000})");
    EXPECT_TRUE(rejected_naming(run(with(view_, {"--atmosphere", json}), kPoints),
                                {"atmosphere_radius_m"}));
}

TEST_F(AerialEval, RejectsJsonWithWrongTypeNamingTheField) {
    const std::string json = file("type.json", R"({"mie_scattering": 4e-6})");
    EXPECT_TRUE(
        rejected_naming(run(with(view_, {"--atmosphere", json}), kPoints), {"mie_scattering"}));
}

TEST_F(AerialEval, RejectsBadLineInPointsFileNamingFileAndLineWithoutPartialOutput) {
    // Two good points first: nothing may be printed for them.
    const std::string points = file("points.txt", "0,1000,100\n# comment\n0,1000\n0,2000,100\n");
    EXPECT_TRUE(rejected_naming(run(with(earth_, {"--points", points})),
                                {points.c_str(), "line 3", "0,1000"}));
}

TEST_F(AerialEval, RejectsNonFinitePointOnStdinNamingTheLine) {
    EXPECT_TRUE(rejected_naming(run(earth_, "0,1000,100\n\n0,nan,100\n"), {"stdin", "line 3"}));
}

TEST_F(AerialEval, RejectsMissingPointsFileNamingFlagAndPath) {
    const std::string missing = path("no-such-dir/pts.txt");
    EXPECT_TRUE(rejected_naming(run(with(earth_, {"--points", missing}), kPoints),
                                {"--points", missing.c_str()}));
}

}  // namespace
