// Case results on disk (result.hpp).
#include "regress/result.hpp"

#include "regress/names.hpp"

#include <fstream>

namespace aerial::regress {

namespace {

constexpr Names<Status, 5> kStatusNames = {{Status::pass, "pass"},
                                           {Status::fail, "fail"},
                                           {Status::skip, "skip"},
                                           {Status::crash, "crash"},
                                           {Status::not_supported, "not-supported"}};

std::string one_line(std::string text) {
    for (char& c : text) {
        if (c == '\n' || c == '\r') c = ' ';
    }
    return text;
}

}  // namespace

const char* status_name(Status status) { return name_in(kStatusNames, status); }

std::optional<Status> parse_status(const std::string& name) { return value_in(kStatusNames, name); }

bool write_result(const std::string& path, const CaseResult& result) {
    std::ofstream file(path);
    file << "status=" << status_name(result.status) << "\n";
    file << "reason=" << one_line(result.reason) << "\n";
    for (const auto& [key, value] : result.metrics) {
        file << "metric." << key << "=" << one_line(value) << "\n";
    }
    return static_cast<bool>(file.flush());
}

std::optional<CaseResult> read_result(const std::string& path) {
    std::ifstream file(path);
    if (!file) return std::nullopt;
    CaseResult result;
    bool has_status = false;
    std::string line;
    while (std::getline(file, line)) {
        const auto eq = line.find('=');
        if (eq == std::string::npos) return std::nullopt;
        const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
        if (key == "status") {
            const auto status = parse_status(value);
            if (!status) return std::nullopt;
            result.status = *status;
            has_status = true;
        } else if (key == "reason") {
            result.reason = value;
        } else if (key.rfind("metric.", 0) == 0) {
            result.metrics[key.substr(7)] = value;
        }
    }
    if (!has_status) return std::nullopt;
    return result;
}

}  // namespace aerial::regress
