// A child process owned by an object: started with fork and exec, stopped (SIGTERM, then SIGKILL after a
// grace period) when the object goes.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace lpss::runtime {

class ChildProcess {
public:
    /// Starts `program` with `arguments`; its output goes where ours does, or to `log_file` if given.
    static std::optional<ChildProcess> start(const std::string& program,
                                             const std::vector<std::string>& arguments,
                                             const std::string& log_file = "");
    ChildProcess(ChildProcess&& other) noexcept;
    ChildProcess& operator=(ChildProcess&& other) noexcept;
    ~ChildProcess();

    pid_t pid() const { return pid_; }
    /// Whether it still runs; collects its exit status if not.
    bool running();
    /// Its exit code once it has ended (128 + signal if killed by one).
    std::optional<int> exit_code() const { return exit_code_; }
    /// Asks it to stop (SIGTERM), waits up to `grace`, then kills it. Returns its exit code.
    int stop(std::chrono::milliseconds grace = std::chrono::seconds(5));
    /// Waits up to `limit` for it to end on its own.
    bool wait(std::chrono::milliseconds limit);

private:
    explicit ChildProcess(pid_t pid) : pid_(pid) {}
    pid_t pid_ = -1;
    std::optional<int> exit_code_;
};

/// An exit code as `exit_code()` gives it, in words: "exit 3", or "exit 135: killed by SIGBUS (Bus error)".
std::string describe_exit_code(int code);

}  // namespace lpss::runtime
