// Reports (report.hpp).
#include "regress/report.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace aerial::regress {

namespace {

constexpr const char* kMetricColumns[] = {"max_lsb", "p99_lsb", "rmse_lsb", "over1", "over2"};

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

std::string xml(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string seconds_text(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f", s);
    return text;
}

std::optional<std::string> written(std::ofstream& file, const std::string& path) {
    file.flush();
    if (!file) return "cannot write " + path;
    return std::nullopt;
}

}  // namespace

Result<Baseline> load_baseline(const std::string& path) {
    std::ifstream file(path);
    if (!file) return Error{"--baseline", "--baseline: cannot read " + path};
    Baseline baseline;
    std::string line;
    for (int number = 1; std::getline(file, line); ++number) {
        std::istringstream words(line);
        std::string name, status, extra;
        if (!(words >> name) || name[0] == '#') continue;
        const bool two_words = static_cast<bool>(words >> status) && !(words >> extra);
        const auto parsed = two_words ? parse_status(status) : std::nullopt;
        if (!parsed) {
            return Error{"--baseline", "--baseline: " + path + ":" + std::to_string(number) +
                                           ": expected 'CASE STATUS' (pass, fail, skip, crash, "
                                           "not-supported), got '" +
                                           line + "'"};
        }
        baseline[name] = *parsed;
    }
    return baseline;
}

std::optional<std::string> write_baseline(const std::string& path,
                                          const std::vector<Outcome>& outcomes) {
    std::ofstream file(path);
    file << "# aerial-regress baseline: the cases expected not to pass (CASE STATUS)\n";
    for (const Outcome& o : outcomes) {
        if (o.result.status != Status::pass) {
            file << o.c->name << " " << status_name(o.result.status) << "\n";
        }
    }
    return written(file, path);
}

Verdict judge(const std::vector<Outcome>& outcomes, const Baseline& baseline) {
    Verdict v;
    for (const Outcome& o : outcomes) {
        const auto it = baseline.find(o.c->name);
        const Status expected = it == baseline.end() ? Status::pass : it->second;
        const Status got = o.result.status;
        if (got == expected) continue;
        const std::string line =
            o.c->name + ": " + status_name(expected) + " -> " + status_name(got);
        if (got == Status::fail || got == Status::crash) {
            v.regressions.push_back(line);
        } else if (got == Status::pass) {
            v.fixes.push_back(line);
        } else {
            v.changes.push_back(line);
        }
    }
    return v;
}

std::string summary(const Identity& id, const std::vector<Outcome>& outcomes,
                    const Verdict& verdict) {
    std::ostringstream out;
    out << "aerial-regress: " << id.platform << " " << (id.driver.empty() ? "-" : id.driver)
        << " -> " << (id.renderer.empty() ? "(no context)" : id.renderer) << ", "
        << (id.version.empty() ? "-" : id.version) << ", device " << id.device << "\n";
    std::map<std::string, std::map<std::string, int>> counts;  // tier -> status -> n
    double total_seconds = 0.0;
    for (const Outcome& o : outcomes) {
        ++counts[tier_name(o.c->tier)][status_name(o.result.status)];
        total_seconds += o.result.seconds;
        if (o.result.status == Status::pass) continue;
        char head[64];
        std::snprintf(head, sizeof head, "  %-13s %7.2f s  ", status_name(o.result.status),
                      o.result.seconds);
        out << head << o.c->name << ": " << o.result.reason << "\n";
    }
    out << "  tier      pass  fail  skip crash  not-supported\n";
    for (const auto& entry : counts) {
        // Not a structured binding: clang 14 refuses to capture one in the lambda below.
        const std::string& tier = entry.first;
        const auto& by_status = entry.second;
        char row[96];
        const auto n = [&](const char* s) {
            const auto it = by_status.find(s);
            return it == by_status.end() ? 0 : it->second;
        };
        std::snprintf(row, sizeof row, "  %-8s %5d %5d %5d %5d %14d\n", tier.c_str(), n("pass"),
                      n("fail"), n("skip"), n("crash"), n("not-supported"));
        out << row;
    }
    out << "  " << outcomes.size() << " cases, " << seconds_text(total_seconds)
        << " s in the cases\n";
    for (const auto& line : verdict.regressions) out << "  regression: " << line << "\n";
    for (const auto& line : verdict.fixes) out << "  fixed: " << line << "\n";
    for (const auto& line : verdict.changes) out << "  changed: " << line << "\n";
    return out.str();
}

std::optional<std::string> write_csv(const std::string& path, const Identity& id,
                                     const std::vector<Outcome>& outcomes) {
    std::ofstream file(path);
    file << "case,tier,kind,status,seconds";
    for (const char* m : kMetricColumns) file << "," << m;
    file << ",reason,platform,device,renderer,version\n";
    for (const Outcome& o : outcomes) {
        file << csv_field(o.c->name) << "," << tier_name(o.c->tier) << ","
             << case_kind_name(o.c->kind) << "," << status_name(o.result.status) << ","
             << seconds_text(o.result.seconds);
        for (const char* m : kMetricColumns) {
            const auto it = o.result.metrics.find(m);
            file << "," << (it == o.result.metrics.end() ? "" : it->second);
        }
        file << "," << csv_field(o.result.reason) << "," << id.platform << "," << id.device << ","
             << csv_field(id.renderer) << "," << csv_field(id.version) << "\n";
    }
    return written(file, path);
}

std::optional<std::string> write_junit(const std::string& path, const Identity& id,
                                       const std::vector<Outcome>& outcomes) {
    std::map<Status, int> n;
    double seconds = 0.0;
    for (const Outcome& o : outcomes) {
        ++n[o.result.status];
        seconds += o.result.seconds;
    }
    std::ofstream file(path);
    file << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n";
    file << "  <testsuite name=\"aerial-regress." << xml(id.device) << "\" tests=\""
         << outcomes.size() << "\" failures=\"" << n[Status::fail] << "\" errors=\""
         << n[Status::crash] << "\" skipped=\"" << n[Status::skip] + n[Status::not_supported]
         << "\" time=\"" << seconds_text(seconds) << "\">\n    <properties>\n";
    const std::pair<const char*, const std::string*> props[] = {
        {"platform", &id.platform},      {"driver", &id.driver},        {"device", &id.device},
        {"GL_VENDOR", &id.vendor},       {"GL_RENDERER", &id.renderer}, {"GL_VERSION", &id.version},
        {"simd_target", &id.simd_target}};
    for (const auto& [name, value] : props) {
        file << "      <property name=\"" << name << "\" value=\"" << xml(*value) << "\"/>\n";
    }
    for (const std::string& var : id.environment) {
        file << "      <property name=\"env\" value=\"" << xml(var) << "\"/>\n";
    }
    file << "    </properties>\n";
    for (const Outcome& o : outcomes) {
        file << "    <testcase classname=\"" << tier_name(o.c->tier) << "."
             << case_kind_name(o.c->kind) << "\" name=\"" << xml(o.c->name) << "\" time=\""
             << seconds_text(o.result.seconds) << "\">\n      <properties>\n";
        file << "        <property name=\"status\" value=\"" << status_name(o.result.status)
             << "\"/>\n";
        for (const auto& [key, value] : o.result.metrics) {
            file << "        <property name=\"" << xml(key) << "\" value=\"" << xml(value)
                 << "\"/>\n";
        }
        if (!o.c->tolerance.text().empty()) {
            file << "        <property name=\"tolerance\" value=\"" << xml(o.c->tolerance.text())
                 << "\"/>\n";
        }
        file << "      </properties>\n";
        const std::string reason = xml(o.result.reason);
        switch (o.result.status) {
            case Status::fail:
                file << "      <failure message=\"" << reason << "\"/>\n";
                break;
            case Status::crash:
                file << "      <error message=\"" << reason << "\"/>\n";
                break;
            case Status::skip:
            case Status::not_supported:
                file << "      <skipped message=\"" << status_name(o.result.status) << ": "
                     << reason << "\"/>\n";
                break;
            case Status::pass:
                break;
        }
        file << "    </testcase>\n";
    }
    file << "  </testsuite>\n</testsuites>\n";
    return written(file, path);
}

std::optional<std::string> write_device_file(const std::string& path, const Identity& id,
                                             const Suite& suite) {
    std::ofstream file(path);
    file << "# The device these goldens were blessed on (aerial-regress --bless).\n";
    file << "platform " << id.platform << "\n";
    file << "GL_VENDOR " << id.vendor << "\n";
    file << "GL_RENDERER " << id.renderer << "\n";
    file << "GL_VERSION " << id.version << "\n";
    file << "size " << suite.width << "x" << suite.height << "\n";
    for (const std::string& var : id.environment) file << "env " << var << "\n";
    return written(file, path);
}

}  // namespace aerial::regress
