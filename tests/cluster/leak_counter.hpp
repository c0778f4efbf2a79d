// Counting what leaves this machine: a network interface besides loopback, in the test's own network
// namespace, whose transmitted packets are read from /proc.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace lpss::testing {

/// An interface besides loopback in this test's network namespace, with the default route and the
/// multicast routes through it, so that a packet sent anywhere but 127.0.0.1 leaves through it and is
/// counted. A veth pair: the kernel here has no dummy interfaces. Removed when the test ends.
class LeakCounter {
public:
    LeakCounter() {
        ok_ = std::system(
                  "ip link add lpssleak0 type veth peer name lpssleak1 && "
                  "sysctl -qw net.ipv6.conf.lpssleak0.disable_ipv6=1 "
                  "net.ipv6.conf.lpssleak1.disable_ipv6=1 && "
                  "ip addr add 10.253.0.1/24 dev lpssleak0 && ip link set lpssleak1 up && "
                  "ip link set lpssleak0 up && ip route add default dev lpssleak0 && "
                  "ip route add 224.0.0.0/4 dev lpssleak0") == 0;
    }
    ~LeakCounter() { std::system("ip link del lpssleak0 2>/dev/null"); }
    LeakCounter(const LeakCounter&) = delete;
    LeakCounter& operator=(const LeakCounter&) = delete;

    bool ok() const { return ok_; }
    /// Packets sent out of the interface so far (/proc/self/net/dev: this process's namespace).
    std::uint64_t sent() const {
        std::ifstream devices("/proc/self/net/dev");
        std::string line;
        while (std::getline(devices, line)) {
            const auto colon = line.find(':');
            if (colon == std::string::npos || line.find("lpssleak0") > colon) continue;
            std::istringstream fields(line.substr(colon + 1));
            std::uint64_t value = 0, transmitted = 0;
            for (int n = 0; n < 10 && fields >> value; ++n)
                if (n == 9) transmitted = value;  // receive: 8 fields; transmit: bytes, then packets
            return transmitted;
        }
        return 0;
    }

private:
    bool ok_ = false;
};

}  // namespace lpss::testing
