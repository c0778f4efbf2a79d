// Example: a federation-style observer. Follows only a region of sectors far from the origin (the
// region filter runs in DDS, so nothing else reaches it) and reports what is there in double global
// coordinates. usage: lpss-example-observer [DOMAIN] [FRAMES] [SECURITY_FOLDER] [PROFILE]
//   build/server/lpss-cluster deploy/scenes/far_stacks.textproto --workers 2 --realtime &
//   build/client/lpss-example-observer 0 300      # watches the stack 1e9 units out
// On a secured cluster (README, "A secured cluster") an observer's identity is enough:
//   build/client/lpss-example-observer 0 300 secure/observer
// On a cluster across hosts, the cluster's profile (docs/operations.md; "" for no identity):
//   build/client/lpss-example-observer 0 300 "" deploy/profiles/lpss-lan.xml
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>

#include "lpss/client/client.hpp"

int main(int argc, char** argv) {
    lpss::ClientOptions options;
    options.name = "observer";
    options.domain = argc > 1 ? std::atoi(argv[1]) : 0;
    const std::uint64_t frames = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 300;
    if (argc > 3) options.security = argv[3];
    if (argc > 4) options.profile = argv[4];
    // 1e9 units out along x, with sectors of 128: sector 7812500 and its neighbours.
    options.region = lpss::Region{{7812499, -1, -1}, {7812502, 1, 1}};
    auto client = lpss::Client::connect(options);
    if (!client) {
        fmt::print(stderr, "cannot start: {}\n", client.error().message);
        return 2;
    }
    if (!(*client)->wait_for_cluster(std::chrono::seconds(30))) {
        fmt::print(stderr, "no lpss cluster on domain {}\n", options.domain);
        return 3;
    }
    std::uint64_t seen = 0;
    auto last_frame = std::chrono::steady_clock::now();
    while (seen < frames) {
        if (std::chrono::steady_clock::now() - last_frame > std::chrono::seconds(30)) {
            fmt::print(stderr, "no frame for 30 s: the cluster has stopped\n");
            return 4;
        }
        for (const lpss::WorldFrame& f : (*client)->poll(std::chrono::milliseconds(100))) {
            last_frame = std::chrono::steady_clock::now();
            if (++seen % 60 != 0) continue;
            fmt::print("frame {}: {} bodies in the region\n", f.frame, f.bodies.size());
            for (const lpss::BodyView& b : f.bodies) {
                const auto desc = (*client)->description(b.id);
                fmt::print("  {:>4} {:<14} ({:.6f}, {:.6f}, {:.6f}){}\n", b.id, desc ? desc->name : "",
                           b.global.x(), b.global.y(), b.global.z(), b.awake ? "" : " asleep");
            }
        }
    }
    return 0;
}
