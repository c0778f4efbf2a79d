// How many commands a client may send: a token bucket per client name, so that one client flooding the
// coordinator (a bug, or a peer on the domain) is refused, each command with the reason, while the others'
// commands and the frames go on.
#pragma once

#include <chrono>
#include <string>
#include <unordered_map>

namespace lpss::coordinator {

class CommandRate {
public:
    using Clock = std::chrono::steady_clock;
    /// `per_second` commands a second on average, bursts of up to as many; 0: no limit.
    explicit CommandRate(double per_second) : per_second_(per_second) {}
    /// Whether a command from `client` may be taken now (and counts it).
    bool allow(const std::string& client, Clock::time_point now);
    double per_second() const { return per_second_; }

private:
    struct Bucket {
        double tokens = 0.0;
        Clock::time_point filled{};
    };
    double per_second_;
    std::unordered_map<std::string, Bucket> buckets_;
};

}  // namespace lpss::coordinator
