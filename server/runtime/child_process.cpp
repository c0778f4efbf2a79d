#include "child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <thread>

namespace lpss::runtime {

std::optional<ChildProcess> ChildProcess::start(const std::string& program,
                                                const std::vector<std::string>& arguments,
                                                const std::string& log_file) {
    std::vector<std::string> args;
    args.push_back(program);
    args.insert(args.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid < 0) return std::nullopt;
    if (pid == 0) {
        if (!log_file.empty()) {
            const int fd = open(log_file.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
            if (fd >= 0) {
                dup2(fd, STDOUT_FILENO);
                dup2(fd, STDERR_FILENO);
                close(fd);
            }
        }
        // Nothing else of the parent's: its DDS participant's sockets were inherited by every child
        // (seen with ss: lpss-cluster's discovery port held by all five processes), which kept that port
        // bound, unread, for as long as any child lived.
        if (close_range(3, ~0U, 0) != 0) {
            for (int fd = 3; fd < 1024; ++fd)
                close(fd);
        }
        // Stop with the parent, whatever ends it.
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        execv(program.c_str(), argv.data());
        _exit(127);
    }
    return ChildProcess(pid);
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept : pid_(other.pid_), exit_code_(other.exit_code_) {
    other.pid_ = -1;
}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
    if (this != &other) {
        if (pid_ > 0) stop();
        pid_ = other.pid_;
        exit_code_ = other.exit_code_;
        other.pid_ = -1;
    }
    return *this;
}

ChildProcess::~ChildProcess() {
    if (pid_ > 0) stop();
}

bool ChildProcess::running() {
    if (pid_ <= 0 || exit_code_) return false;
    int status = 0;
    const pid_t r = waitpid(pid_, &status, WNOHANG);
    if (r == 0) return true;
    exit_code_ = r < 0 ? 255 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return false;
}

bool ChildProcess::wait(std::chrono::milliseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (running()) {
        if (std::chrono::steady_clock::now() >= end) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
}

int ChildProcess::stop(std::chrono::milliseconds grace) {
    if (pid_ <= 0) return exit_code_.value_or(0);
    if (running()) {
        kill(pid_, SIGTERM);
        if (!wait(grace)) {
            kill(pid_, SIGKILL);
            wait(std::chrono::seconds(5));
        }
    }
    const int code = exit_code_.value_or(255);
    pid_ = -1;
    return code;
}

std::string describe_exit_code(int code) {
    std::string out = "exit " + std::to_string(code);
    if (code > 128 && code < 128 + 65) {
        const int sig = code - 128;
        const char* abbreviation = sigabbrev_np(sig);
        const char* description = strsignal(sig);
        out += ": killed by SIG" + std::string(abbreviation != nullptr ? abbreviation : "?") + " (" +
               (description != nullptr ? description : "?") + ")";
    }
    return out;
}

}  // namespace lpss::runtime
