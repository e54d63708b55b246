// The suite file (suite.hpp).
#include "regress/suite.hpp"

#include "regress/names.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "aerial/scene_file.hpp"
#include "aerial/validation/scene_render.hpp"
#include "support/cli.hpp"

namespace aerial::regress {

namespace {

struct Bound {
    const char* name;
    std::optional<int> Tolerance::*integer;
    std::optional<double> Tolerance::*fraction;
};

constexpr Bound kBounds[] = {
    {"max_lsb", &Tolerance::max_lsb, nullptr},
    {"p99_lsb", &Tolerance::p99_lsb, nullptr},
    {"min_p99_lsb", &Tolerance::min_p99_lsb, nullptr},
    {"max_over1", nullptr, &Tolerance::max_over1},
    {"max_over2", nullptr, &Tolerance::max_over2},
};

constexpr Names<Tier, 3> kTierNames = {
    {Tier::portable, "portable"}, {Tier::golden, "golden"}, {Tier::selftest, "selftest"}};
constexpr Names<CaseKind, 9> kCaseKindNames = {
    {CaseKind::context, "context"},  {CaseKind::cross, "cross"},
    {CaseKind::fog, "fog"},          {CaseKind::paths, "paths"},
    {CaseKind::state, "state"},      {CaseKind::cpu_model, "cpu-model"},
    {CaseKind::golden, "golden"},    {CaseKind::cpu_golden, "cpu-golden"},
    {CaseKind::selftest, "selftest"}};

constexpr const char* kChecks[] = {"cross", "fog", "paths", "cpu-model", "golden", "cpu-golden"};

/// Reads "BOUND=VALUE" into `t`; false when the word is not one.
bool read_bound(const std::string& word, Tolerance& t) {
    const auto eq = word.find('=');
    if (eq == std::string::npos) return false;
    const std::string name = word.substr(0, eq);
    const auto value = tools::parse_number(word.substr(eq + 1));
    if (!value || *value < 0) return false;
    for (const Bound& b : kBounds) {
        if (name != b.name) continue;
        if (b.integer) {
            if (*value != static_cast<int>(*value)) return false;
            t.*(b.integer) = static_cast<int>(*value);
        } else {
            t.*(b.fraction) = *value;
        }
        return true;
    }
    return false;
}

Tolerance merged(const Tolerance& base, const Tolerance& over) {
    Tolerance t = base;
    for (const Bound& b : kBounds) {
        if (b.integer && (over.*(b.integer))) t.*(b.integer) = over.*(b.integer);
        if (b.fraction && (over.*(b.fraction))) t.*(b.fraction) = over.*(b.fraction);
    }
    return t;
}

bool has_arb_program(const Suite& suite, const std::string& scene) {
    const auto file = scene::load_scene_file(suite.scene_path(scene));
    if (!file) return false;
    validation::RenderOptions options;
    options.backend = validation::RenderBackend::arb;
    return !validation::check_backend(*file, options, false).has_value();
}

Case make_case(Tier tier, CaseKind kind, std::string name, std::string scene,
               std::string backend = "", std::string path = "", Tolerance tolerance = {}) {
    Case c;
    c.tier = tier;
    c.kind = kind;
    c.name = std::move(name);
    c.scene = std::move(scene);
    c.backend = std::move(backend);
    c.path = std::move(path);
    c.tolerance = tolerance;
    return c;
}

/// The portable cases of one `cross` line.
void add_portable_cases(Suite& suite, const std::string& scene, const Tolerance& cross,
                        const std::map<std::string, Tolerance>& checks) {
    const bool arb = has_arb_program(suite, scene);
    const auto tol = [&](const char* check) {
        const auto it = checks.find(check);
        return it == checks.end() ? Tolerance{} : it->second;
    };
    const Tier p = Tier::portable;
    const std::string s = scene;
    suite.cases.push_back(
        make_case(p, CaseKind::cross, "cross/" + s + "/cpu", s, "cpu", "", cross));
    if (arb) {
        suite.cases.push_back(
            make_case(p, CaseKind::cross, "cross/" + s + "/arb", s, "arb", "", cross));
    }
    suite.cases.push_back(make_case(p, CaseKind::fog, "fog/" + s, s, "fog", "", tol("fog")));
    for (const char* path : {"combiner", "two-pass"}) {
        suite.cases.push_back(
            make_case(p, CaseKind::paths, "paths/" + s + "/" + path, s, "cpu", path, tol("paths")));
    }
    for (const char* path : {"secondary-color", "combiner", "two-pass"}) {
        suite.cases.push_back(make_case(
            p, CaseKind::state, "state/" + s + "/cpu-" + std::string(path), s, "cpu", path));
    }
    if (arb) suite.cases.push_back(make_case(p, CaseKind::state, "state/" + s + "/arb", s, "arb"));
    suite.cases.push_back(
        make_case(p, CaseKind::cpu_model, "cpu-model/" + s, s, "", "", tol("cpu-model")));
}

std::optional<Error> line_error(const std::string& path, int number, const std::string& what) {
    return Error{"suite", path + ":" + std::to_string(number) + ": " + what};
}

}  // namespace

const char* tier_name(Tier tier) { return name_in(kTierNames, tier); }
const char* case_kind_name(CaseKind kind) { return name_in(kCaseKindNames, kind); }

const Case* Suite::find(const std::string& name) const {
    for (const Case& c : cases) {
        if (c.name == name) return &c;
    }
    return nullptr;
}

std::string Suite::scene_path(const std::string& scene) const {
    return (std::filesystem::path(directory) / "scenes" / (scene + ".json")).string();
}

Result<Suite> load_suite(const std::string& path) {
    std::ifstream file(path);
    if (!file) return Error{"--suite", "--suite: cannot read " + path};
    Suite suite;
    suite.directory = std::filesystem::path(path).parent_path().string();
    if (suite.directory.empty()) suite.directory = ".";
    suite.cases.push_back(make_case(Tier::portable, CaseKind::context, "context", ""));
    std::map<std::string, Tolerance> checks;
    std::vector<std::string> golden_scenes;
    std::string line;
    for (int number = 1; std::getline(file, line); ++number) {
        std::istringstream words(line);
        std::string kind;
        if (!(words >> kind) || kind[0] == '#') continue;
        std::vector<std::string> rest;
        for (std::string w; words >> w;) rest.push_back(w);
        if (kind == "setting" && rest.size() == 2 && rest[0] == "size") {
            const auto size = tools::parse_size(rest[1], "size");
            if (!size) return *line_error(path, number, size.error().message);
            suite.width = size->first;
            suite.height = size->second;
        } else if (kind == "setting" && rest.size() == 2 && rest[0] == "env" &&
                   rest[1].find('=') != std::string::npos) {
            const auto eq = rest[1].find('=');
            suite.environment.emplace_back(rest[1].substr(0, eq), rest[1].substr(eq + 1));
        } else if (kind == "tolerance" && !rest.empty() &&
                   std::find(std::begin(kChecks), std::end(kChecks), rest[0]) !=
                       std::end(kChecks)) {
            Tolerance t;
            for (std::size_t i = 1; i < rest.size(); ++i) {
                if (!read_bound(rest[i], t)) {
                    return *line_error(path, number, "'" + rest[i] + "' is not BOUND=VALUE");
                }
            }
            checks[rest[0]] = t;
        } else if (kind == "cross" && !rest.empty()) {
            Tolerance t;
            for (std::size_t i = 1; i < rest.size(); ++i) {
                if (!read_bound(rest[i], t)) {
                    return *line_error(path, number, "'" + rest[i] + "' is not BOUND=VALUE");
                }
            }
            add_portable_cases(suite, rest[0], merged(checks["cross"], t), checks);
        } else if (kind == "golden" && (rest.size() == 2 || rest.size() == 3)) {
            const std::string name =
                rest[0] + "-" + rest[1] + (rest.size() == 3 ? "-" + rest[2] : "");
            suite.cases.push_back(make_case(Tier::golden, CaseKind::golden, "golden/" + name,
                                            rest[0], rest[1], rest.size() == 3 ? rest[2] : "",
                                            checks["golden"]));
            if (std::find(golden_scenes.begin(), golden_scenes.end(), rest[0]) ==
                golden_scenes.end()) {
                golden_scenes.push_back(rest[0]);
            }
        } else if (kind == "selftest" && rest.size() == 1 &&
                   (rest[0] == "crash" || rest[0] == "fail" || rest[0] == "hang")) {
            suite.cases.push_back(
                make_case(Tier::selftest, CaseKind::selftest, "selftest/" + rest[0], "", rest[0]));
        } else {
            return *line_error(path, number, "unknown statement '" + line + "'");
        }
    }
    for (const std::string& scene : golden_scenes) {
        suite.cases.push_back(make_case(Tier::golden, CaseKind::cpu_golden, "cpu-golden/" + scene,
                                        scene, "", "", checks["cpu-golden"]));
    }
    return suite;
}

}  // namespace aerial::regress
