// Example: a game backend. Spawns a few players (spheres) into a running lpss world and pushes them
// around, printing where they are. usage: lpss-example-game-backend [DOMAIN] [SECONDS] [SECURITY_FOLDER]
// [PROFILE]
//   build/server/lpss-cluster deploy/scenes/far_stacks.textproto --workers 2 --realtime &
//   build/client/lpss-example-game-backend 0 10
// On a secured cluster (README, "A secured cluster") it needs an operator's identity, since it commands:
//   build/client/lpss-example-game-backend 0 10 secure/operator
// On a cluster across hosts, the cluster's profile (docs/operations.md; "" for no identity):
//   build/client/lpss-example-game-backend 0 10 "" deploy/profiles/lpss-lan.xml
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <random>
#include <vector>

#include "lpss/client/client.hpp"

int main(int argc, char** argv) {
    lpss::ClientOptions options;
    options.name = "game-backend";
    options.domain = argc > 1 ? std::atoi(argv[1]) : 0;
    const int seconds = argc > 2 ? std::atoi(argv[2]) : 10;
    if (argc > 3) options.security = argv[3];
    if (argc > 4) options.profile = argv[4];
    auto client = lpss::Client::connect(options);
    if (!client) {
        fmt::print(stderr, "cannot start: {}\n", client.error().message);
        return 2;
    }
    lpss::Client& world = **client;
    if (!world.wait_for_cluster(std::chrono::seconds(30))) {
        fmt::print(stderr, "no lpss cluster on domain {}\n", options.domain);
        return 3;
    }

    // Players: spheres dropped next to the origin's stack, ids from 9000 on.
    std::vector<lpss::BodyId> players;
    for (int n = 0; n < 4; ++n) {
        lpss::BodyDesc player;
        player.id = 9000 + static_cast<lpss::BodyId>(n);
        player.name = fmt::format("player{}", n);
        player.shape = lpss::Sphere{0.4};
        player.mass = 80;
        player.position = Eigen::Vector3d(-6.0 + 3.0 * n, 2.0, 4.0);
        const std::uint64_t request = world.spawn(player);
        const auto outcome = world.wait_outcome(request, std::chrono::seconds(5));
        if (!outcome || !outcome->applied) {
            fmt::print("player {} not spawned: {}\n", player.id, outcome ? outcome->reason : "no answer");
            continue;
        }
        fmt::print("player {} spawned at frame {}\n", player.id, outcome->frame);
        players.push_back(player.id);
    }

    std::mt19937 random(7);
    std::uniform_real_distribution<double> push(-300.0, 300.0);
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
    auto next_push = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() < end) {
        world.poll(std::chrono::milliseconds(50));
        if (std::chrono::steady_clock::now() < next_push || !world.latest()) continue;
        next_push += std::chrono::seconds(1);
        for (lpss::BodyId id : players)
            world.apply_impulse(id, {push(random), 0.0, push(random)});
        for (const lpss::BodyView& b : world.latest()->bodies) {
            if (b.id >= 9000)
                fmt::print("frame {} player {} at ({:.3f}, {:.3f}, {:.3f})\n", world.latest()->frame, b.id,
                           b.global.x(), b.global.y(), b.global.z());
        }
    }
    for (lpss::BodyId id : players)
        world.remove(id);
    world.poll(std::chrono::milliseconds(200));
    return 0;
}
