// Child processes (spawn.hpp), with posix_spawn: the child's standard output and error go to
// logs/CASE.log, its result to results/CASE.result.
#include "regress/spawn.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "regress/cases.hpp"

extern char** environ;

namespace aerial::regress {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

struct Running {
    pid_t pid = -1;
    std::size_t index = 0;
    Clock::time_point start;
    bool killed = false;
};

std::string result_path(const SpawnOptions& o, const std::string& name) {
    return (fs::path(o.out_dir) / "results" / (case_file_name(name) + ".result")).string();
}

std::string log_path(const SpawnOptions& o, const std::string& name) {
    return (fs::path(o.out_dir) / "logs" / (case_file_name(name) + ".log")).string();
}

pid_t start(const SpawnOptions& o, const std::string& name) {
    std::vector<std::string> args{o.executable, "--child", name, "--result", result_path(o, name)};
    args.insert(args.end(), o.common_args.begin(), o.common_args.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const std::string log = log_path(o, name);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, o.executable.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return rc == 0 ? pid : -1;
}

CaseResult finished(const SpawnOptions& o, const std::string& name, int wait_status, bool killed) {
    if (killed) {
        CaseResult r;
        r.status = Status::crash;
        r.reason = "timed out after " + std::to_string(o.timeout_seconds) + " s (killed)";
        return r;
    }
    if (WIFSIGNALED(wait_status)) {
        CaseResult r;
        r.status = Status::crash;
        r.reason = std::string("killed by signal ") + std::to_string(WTERMSIG(wait_status)) + " (" +
                   strsignal(WTERMSIG(wait_status)) + "); log: " + log_path(o, name);
        return r;
    }
    auto r = read_result(result_path(o, name));
    if (!r) {
        CaseResult crash;
        crash.status = Status::crash;
        crash.reason = "exited " + std::to_string(WEXITSTATUS(wait_status)) +
                       " without a result; log: " + log_path(o, name);
        return crash;
    }
    return *r;
}

}  // namespace

void run_children(const std::vector<std::string>& names, const SpawnOptions& options,
                  const std::function<void(std::size_t, const CaseResult&)>& done) {
    fs::create_directories(fs::path(options.out_dir) / "results");
    fs::create_directories(fs::path(options.out_dir) / "logs");
    std::vector<Running> running;
    std::size_t next = 0;
    while (next < names.size() || !running.empty()) {
        while (next < names.size() && int(running.size()) < std::max(1, options.jobs)) {
            fs::remove(result_path(options, names[next]));
            const pid_t pid = start(options, names[next]);
            if (pid < 0) {
                CaseResult r;
                r.status = Status::crash;
                r.reason = "cannot start " + options.executable + ": " + std::strerror(errno);
                done(next, r);
            } else {
                running.push_back({pid, next, Clock::now(), false});
            }
            ++next;
        }
        for (auto it = running.begin(); it != running.end();) {
            int status = 0;
            const pid_t got = waitpid(it->pid, &status, WNOHANG);
            if (got == it->pid) {
                CaseResult r = finished(options, names[it->index], status, it->killed);
                r.seconds = std::chrono::duration<double>(Clock::now() - it->start).count();
                done(it->index, r);
                it = running.erase(it);
                continue;
            }
            if (!it->killed &&
                Clock::now() - it->start > std::chrono::seconds(options.timeout_seconds)) {
                kill(it->pid, SIGKILL);
                it->killed = true;
            }
            ++it;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

}  // namespace aerial::regress
