// Hosts on one machine for a test: network namespaces joined by a bridge in the test's own network
// namespace, each host with its own /dev/shm (Fast DDS's shared memory must not join processes of two
// hosts), as ../shared/tools/fake-hosts.sh builds them by hand. The test's own process is a host too, on
// the bridge. A host's link can be cut and restored (the kernel here has no netem: a link is up or down).
// The bridge floods multicast to every port (no IGMP snooping).
// Everything is removed when the object goes; the processes run on a host are their ChildProcess owners'.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace lpss::testing {

class FakeHosts {
public:
    /// Hosts 1..count at 10.78.0.N/24, the test's process at 10.78.0.254, multicast routed on the bridge.
    explicit FakeHosts(int count) : tag_(std::to_string(::getpid())), count_(count) {
        for (const char* candidate : {"/usr/sbin/ip", "/usr/bin/ip", "/sbin/ip", "/bin/ip"}) {
            if (::access(candidate, X_OK) == 0) {
                ip_ = candidate;
                break;
            }
        }
        // Multicast goes to every port, as a switch without IGMP snooping sends it: with snooping and no
        // querier on the bridge, a host whose link went down and up never hears multicast again (its
        // membership, reported while the link was down, is lost), and a participant it starts then discovers
        // no one.
        ok_ = !ip_.empty() && sh("ip link add " + bridge() + " type bridge mcast_snooping 0 && ip link set " +
                                 bridge() + " up && ip addr add 10.78.0.254/24 dev " + bridge() +
                                 " && ip route add 224.0.0.0/4 dev " + bridge());
        for (int h = 1; ok_ && h <= count; ++h) {
            const std::string ns = name(h);
            std::filesystem::create_directories(shm(h));
            ok_ = sh("ip netns add " + ns + " && ip link add " + outer(h) + " type veth peer name " +
                     inner(h) + " && ip link set " + inner(h) + " netns " + ns + " && ip link set " +
                     outer(h) + " master " + bridge() + " && ip link set " + outer(h) +
                     " up && ip netns exec " + ns + " ip link set lo up && ip netns exec " + ns +
                     " ip link set " + inner(h) + " name eth0 && ip netns exec " + ns +
                     " ip addr add 10.78.0." + std::to_string(h) + "/24 dev eth0 && ip netns exec " + ns +
                     " ip link set eth0 up multicast on && ip netns exec " + ns +
                     " ip route add 224.0.0.0/4 dev eth0");
        }
    }
    ~FakeHosts() {
        for (int h = 1; h <= count_; ++h) {
            sh("ip netns del " + name(h) + " 2>/dev/null");
            std::error_code ec;
            std::filesystem::remove_all(shm(h), ec);
        }
        sh("ip link del " + bridge() + " 2>/dev/null");
    }
    FakeHosts(const FakeHosts&) = delete;
    FakeHosts& operator=(const FakeHosts&) = delete;

    /// Whether the hosts are there (it needs root, and iproute2).
    bool ok() const { return ok_; }
    /// Runs `program` on host `h`, in its namespace, with its /dev/shm; its output to `log`.
    std::optional<runtime::ChildProcess> run(int h, const std::string& program,
                                             const std::vector<std::string>& arguments,
                                             const std::string& log) const {
        std::vector<std::string> args = {
            "netns", "exec", name(h), "unshare",
            "-m",    "sh",   "-c",    "mount --bind \"$0\" /dev/shm && exec \"$@\"",
            shm(h),  program};
        args.insert(args.end(), arguments.begin(), arguments.end());
        return runtime::ChildProcess::start(ip_, args, log);
    }
    /// Takes host `h`'s link down (a partition: it reaches no one, no one reaches it), or up again.
    bool cut(int h) const { return sh("ip link set " + outer(h) + " down"); }
    bool restore(int h) const { return sh("ip link set " + outer(h) + " up"); }

private:
    std::string name(int h) const { return "lpss" + tag_ + "h" + std::to_string(h); }
    std::string bridge() const { return "lpb" + tag_; }
    std::string outer(int h) const { return "lpo" + tag_ + "x" + std::to_string(h); }
    std::string inner(int h) const { return "lpi" + tag_ + "x" + std::to_string(h); }
    std::string shm(int h) const {
        return (std::filesystem::temp_directory_path() / ("lpss_" + tag_ + "_shm_h" + std::to_string(h)))
            .string();
    }
    static bool sh(const std::string& command) { return std::system(command.c_str()) == 0; }

    std::string tag_;
    int count_ = 0;
    std::string ip_;
    bool ok_ = false;
};

}  // namespace lpss::testing
